%
O2206 (A BALL END MILL LOWERED BESIDE THE BAR'S FRONT EDGE)
(T11 holds a Ø10 ball end mill, from the job beside this program. With the spindle positioned)
(it rapids down to 1 mm below the Ø50 bar's face 4 mm outside its round, X58: radius 29, and)
(across the front edge in Y. Worked by hand: 1 mm above its point the ball is SQRT[5^2 - 4^2])
(= 3 mm in radius, so at Z0 to Z-1 it comes no nearer the spindle axis than 29 - 3 = 26, at Y0:)
(1 mm clear of the round. A flat end of the same size would reach 29 - 5 = 24: 1 mm into it.)
G21 G18 G40 G97 G98
G28 U0 W0
M5
T1111 (AXIAL LIVE BALL END MILL D10)
M154 (SPINDLE AS C AXIS)
G28 H0
G0 X58. Z2. C0. Y-20.
G0 Z-1. (OUTSIDE THE ROUND, 1 MM BELOW THE FACE)
G0 Y20. (ACROSS THE FRONT EDGE)
G0 X80.
G0 Z2.
M155
G28 U0 W0
G28 V0
M30
%
