(rs274ngc arc checks in inch: 0.0028 in, 0.1 % over that; R short by 0.00005 in)
G20 G18 G99 G97 S500 M3
G0 X4 Z2
(end radius 0.4028 against 0.4: inside)
G3 X4.8056 Z2.4 I0 K0.4 F0.01
G0 X4 Z2
(end radius 0.4029: outside)
G3 X4.8058 Z2.4 I0 K0.4
G0 X4 Z2
(R short of the half chord by 0.00004 in: fine; by 0.00006 in: error)
G2 X4 Z2.8 R0.39996
G0 X4 Z2
G2 X4 Z2.8 R0.39994
M30
