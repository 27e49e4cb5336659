(test-case: machine=comp-fanuc-rear)
(G72 type I whose profile carries G41 on block P and G40 on block Q)
G21 G18 G99 G97 S800 M3
T0404
G0 X54 Z2
G72 W1.5 R0.5
G72 P10 Q40 U0 W0.2 F0.2
N10 G0 G41 Z-4
N20 G1 X20 F0.1
N30 Z2
N40 G40 X16 Z3
G70 P10 Q40
G0 X60
M30
