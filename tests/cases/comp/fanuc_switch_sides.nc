(test-case: machine=comp-fanuc-rear)
(Fanuc: G41 after G42 without G40 switches sides, a new start-up from where the tool is)
G99 G97 S500 M3 F0.2
T0101
G0 X30 Z5
G42 G1 X20 Z1
Z-10
X30
G41 G1 X30 Z-20
X20
G40 G0 X40 Z5
M30
