(test-case: machine=comp-fanuc-rear)
(G73 whose profile carries G42 on block P and G40 on block Q)
G21 G18 G99 G97 S800 M3
T0404
G0 X56 Z5
G73 U4 W2 R3
G73 P10 Q40 U1 W0.5 F0.2
N10 G0 G42 X30 Z0
N20 G1 Z-20 F0.1
N30 X52
N40 G40 X56
G70 P10 Q40
G0 X60
M30
