(test-case: machine=jaw-test)
(1 um past the jaw face: a collision 0.001 mm deep)
G21 G18 G98 G97 S500 M3
G0 X25 Z5
G1 Z-0.001 F100
G0 Z5
M30
