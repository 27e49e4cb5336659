(test-case: machine=comp-fanuc-rear)
(G71 type I whose profile carries G42 on block P and no G40: G40 comes after the G70)
G21 G18 G99 G97 S800 M3
T0404
G0 X50 Z8
G0 X44 Z3
G71 U3 R0.5
G71 P10 Q30 U1 W0.2 F0.3
N10 G0 G42 X30
N20 G1 Z-15 F0.1
N30 X46
G70 P10 Q30
G40 G0 X60 Z5
M30
