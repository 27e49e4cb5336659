(test-case: machine=jaw-test)
(a full circle whose start and end are clear dips 10 mm below the jaw face at its lowest point)
G21 G18 G98 G97 S500 M3
G0 X25 Z30
G2 X25 Z30 I0 K-20 F500
G0 Z50
M30
