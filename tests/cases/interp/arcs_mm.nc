(rs274ngc arc checks in mm: radius difference 0.0283 mm at most, 0.1 % when over that)
G21 G18 G99 G97 S500 M3
G0 X100 Z50
(end radius 10.028 against start radius 10: inside 0.0283)
G3 X120.056 Z60 I0 K10 F0.2
G0 X100 Z50
(end radius 10.029: outside)
G3 X120.058 Z60 I0 K10
G0 X100 Z50
(big arc: 30 mm radius, difference 0.029 mm = 0.097 % is fine)
G3 X160.058 Z80 I0 K30
G0 X100 Z50
(difference 0.031 mm on a 30 mm radius = 0.103 %: error)
G3 X160.062 Z80 I0 K30
G0 X100 Z50
(R arc: half chord 10 over R 9.9988 by 0.0012: a semicircle; over by 0.0013: error)
G2 X100 Z70 R9.9988
G0 X100 Z50
G2 X100 Z70 R9.9987
G0 X100 Z50
(negative R: more than 180 degrees)
G2 X100 Z60 R-6
(full circle in I/K format: start equals end)
G2 X100 Z60 I5 K0
(R arc with start equal to end: error)
G2 X100 Z60 R5
(zero radius)
G2 X100 Z60 I0 K0
(R with I/K)
G2 X110 Z65 R5 I5
M30
