(test-case: machine=comp-fanuc-rear)
(A G42 start-up block right before G70: its vector is normal to the G70's first move, as before a plain block)
G21 G18 G99 G97 S800 M3
T0404
G0 X44 Z3
G71 P10 Q30 U1 W0 D3 F0.3
N10 G1 X36 F0.1
N20 Z-15
N30 X46
G0 X50 Z8
G42 G0 X44 Z3
G70 P10 Q30
G40 G0 X60 Z5
M30
