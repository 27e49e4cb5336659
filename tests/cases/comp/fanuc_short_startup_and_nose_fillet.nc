(test-case: machine=comp-fanuc-rear)
(Fanuc: a start-up block shorter than the nose radius, and a fillet of exactly the nose radius)
G99 G97 S500 M3 F0.2
T0101
G0 X21 Z2
G42 G1 X20 Z1.8
Z-10
G2 X21.6 Z-10.8 R0.8
G1 X30
G40 G0 X40 Z5
M30
