(test-case: machine=comp-fanuc-rear)
(G40 with no move, then a G90 box cycle: its first move starts where compensation left the tool)
G99 G97 S500 M3 F0.2
T0101
G0 X30 Z5
G42 G1 X20 Z1
Z-10
G40
G90 X18 Z-5 F0.1
G0 X40 Z5
M30
