(test-case: machine=jaw-test)
(the insert sits in the notch of the stepped jaw: inside the jaw's box and convex hull, clear of the jaw)
G21 G18 G98 G97 S500 M3
G0 X45 Z5
G1 Z-9 F100
G1 X49
G0 Z5
M30
