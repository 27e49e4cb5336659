(test-case: modes=step,exact)
(As holder_meets_collar_facing_a_pocket_wall, but the facing cut stops at X36, tip r 18: the)
(holder's bottom edge over the collar, at Z-10, is at r 18 + 7.7 = 25.7, 0.7 mm clear of the 50 mm)
(collar. No finding.)
%
G21 G18 G40 G97 G99
G28 U0 W0
T0404
G97 S900 M3
G0 X54. Z-40.
G1 X30. F0.05
G0 X54.
Z-37.
G1 X30.
G0 X54.
Z-34.
G1 X30.
G0 X54.
Z-31.
G1 X30.
G0 X54.
Z-28.
G1 X30.
G0 X54.
Z-25.
G1 X30.
G0 X54.
Z-22.
G1 X30.
G0 X54.
Z-19.
G1 X30.
G0 X54.
Z-16.
G1 X30.
G0 X54.
Z-13.
G1 X30.
G0 X54.
G28 U0 W0
T0101
G96 S200 M3
G50 S3000
G0 X54. Z-40.5
G1 X36. F0.15
G0 X54.
G28 U0 W0
M30
%
