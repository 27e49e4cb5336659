(test-case: machine=jaw-test)
(the insert's bottom edge comes down exactly onto the jaw face z 0: touching is not a collision)
G21 G18 G98 G97 S500 M3
G0 X25 Z5
G1 Z0 F100
G0 Z5
M30
