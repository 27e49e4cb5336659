(test-case: machine=jaw-test modes=step,exact)
(the insert feeds 0.5 mm past the jaw face: deeper than the default min_depth 0.1: an error)
G21 G18 G98 G97 S500 M3
G0 X25 Z5
G1 Z-0.5 F100
G0 Z5
M30
