(test-case: machine=comp-fanuc-rear)
(The alarms a Fanuc control raises with nose-radius compensation, each a program finding at its line)
G99 G97 S500 M3 F0.2
T0404
G0 X30 Z5
G42 G2 X20 Z0 R6
G40 G0 X30 Z5
G42 G1 X20 Z1
Z-10
G2 X22 Z-11 R0.75
G40 G0 X30 Z5
G42 G1 X20 Z1
Z-10
X16
Z-11
X20
Z-20
G40 G0 X30 Z5
M30
