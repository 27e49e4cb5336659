(test-case: machine=jaw-test modes=step,exact)
(the insert feeds 0.01 mm past the jaw face: deepest 0.01 mm, below the default min_depth 0.1: a graze, a warning)
G21 G18 G98 G97 S500 M3
G0 X25 Z5
G1 Z-0.01 F100
G0 Z5
M30
