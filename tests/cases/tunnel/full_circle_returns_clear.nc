(test-case: machine=jaw-test modes=step,exact)
(a full circle at 2000 mm/min whose start and end are clear crosses the jaw's corner 0.3 mm deep)
G21 G18 G98 G97 S500 M3
G0 X39.7 Z10
G2 X39.7 Z10 I0 K-5.15 F2000
G0 Z50
M30
