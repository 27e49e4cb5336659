(test-case: machine=haas-style-inch)
(Issue: a G42 start-up after G40 and a Z retract starts from where the tool is, not from where the last compensated move left it)
G18 G20 G40 G99
T0202
G97 S1000 M03
G00 G54 X1.6 Z0.1
G00 G42 X1.455 Z-1.98
G01 X1.415 F0.004
X1.375 Z-2.0
Z-2.157
X1.455
G00 G40 X1.6
G00 Z0.1
G00 G42 X-0.062 Z0.1
G01 Z0.0 F0.005
X0.3
G00 G40 X1.6
M30
