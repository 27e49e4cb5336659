(test-case: machine=jaw-test)
(a large arc over the jaw face: its chord stays 0.5 mm above the face, its sagitta of 0.6 mm dips 0.1 mm in)
G21 G18 G98 G97 S500 M3
G0 X10 Z0.5
G2 X50 Z0.5 R333.633 F200
G0 Z50
M30
