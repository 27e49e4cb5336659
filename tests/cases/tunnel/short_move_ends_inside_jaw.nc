(test-case: machine=jaw-test modes=step,exact)
(a 0.02 mm move that ends 0.01 mm inside the jaw face, then leaves)
G21 G18 G98 G97 S500 M3
G0 X25 Z5
G0 Z0.01
G1 Z-0.01 F50
G0 Z5
M30
