(test-case: machine=haas-style-inch)
(Haas G71 type II whose block Q is G00 G40 Z0.1, a retract back toward the start inside P-Q)
G18 G20 G40 G99
T0101
G97 S1000 M03
G00 G54 X1.3 Z0.1
G71 P10 Q50 U0.02 W0.005 D0.05 F0.01
N10 G00 G42 X0.8 Z0.1
N20 G01 Z-0.5 F0.005
N30 X1.0 Z-0.7
N40 X1.3
N50 G00 G40 Z0.1
G70 P10 Q50
G00 X3.0 Z2.0
M30
