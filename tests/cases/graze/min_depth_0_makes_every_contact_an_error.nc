(test-case: machine=jaw-test modes=step,exact min_depth=0)
(min_depth 0 turns grazes off: the 0.01 mm contact is an error again)
G21 G18 G98 G97 S500 M3
G0 X25 Z5
G1 Z-0.01 F100
G0 Z5
M30
