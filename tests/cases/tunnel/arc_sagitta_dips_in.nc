(test-case: machine=jaw-test modes=step,exact)
(a fast arc whose chord stays 0.05 mm above the jaw face while its sagitta of 0.06 mm dips 0.01 mm in)
G21 G18 G98 G97 S500 M3
G0 X10 Z0.05
G2 X50 Z0.05 R3333.363 F5000
G0 Z50
M30
