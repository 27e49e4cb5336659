(test-case: machine=generic-slant-bed-tube)
(a 50 x 20 mm tube: the boring bar opens the bore to 22 and 24 mm; then a rapid to 26 mm hits the wall)
%
G21 G18 G40 G97 G99
G28 U0 W0
T0303
G96 S150 M3
G50 S2500
G0 X22. Z2.
G1 Z-40. F0.1
U-1. W1.
G0 Z2.
X24.
G1 Z-40.
U-1. W1.
G0 Z2.
X26. (RAPID INTO THE BORE WALL AT THE FRONT FACE)
Z-10.
G0 X20.
Z5.
G28 U0 W0
M30
%
