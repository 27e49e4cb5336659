(test-case: machine=haas-style-tailstock)
(M11 opens the chuck: with the spindle turning, or a spindle start while it is open, a program finding)
G18 G21 G99
T0101
G97 S500 M3
M11
M5
M11
M10
M3
M5
M11
M4
M10
M30
