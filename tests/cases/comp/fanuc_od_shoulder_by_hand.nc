(test-case: machine=comp-fanuc-rear)
(Worked by hand: tip 3, r 0.8, G42 on an OD with a shoulder; see the expected file)
G99 G97 S500 M3 F0.2
T0404
G0 X30 Z5
G42 G1 X20 Z1
Z-10
X30
Z-20
G40 G0 X40 Z5
M30
