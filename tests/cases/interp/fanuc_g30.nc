(test-case: machine=g30-fanuc)
(Fanuc G30: through the intermediate point to the 2nd reference point [200, 300] without P or with P2, the 3rd [150, 450] with P3, home with P4 (not in the machine file); only the axes named go, U0 W0 through the current point; P5 is refused)
G21 G18 G99 G97 S500 M3
T0101
G0 X100 Z50
G30 U0 W0
G0 X100 Z50
G30 P2 U0
G0 X100 Z50
G30 P3 X120 Z60
G30 P4 W0
G30 P5 U0 W0
G0 X100 Z50
M30
