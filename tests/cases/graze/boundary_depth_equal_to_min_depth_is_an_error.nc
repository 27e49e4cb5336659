(test-case: machine=jaw-test modes=step,exact min_depth=0.25)
(deepest 0.25 mm with min_depth 0.25: only a contact strictly shallower than min_depth is a graze)
G21 G18 G98 G97 S500 M3
G0 X25 Z5
G1 Z-0.25 F100
G0 Z5
M30
