%
O2101 (PICK-OFF AND PART-OFF: THE SUB-SPINDLE TAKES THE PART)
(The bar, Ø50 and 80 mm out of the main chuck, is faced and turned to Ø36 for 53 mm; the)
(sub-spindle comes forward to B-636., its jaw faces 14 mm onto the Ø36, clamps with M110,)
(the blade parts off through the axis at Z-56., and the sub-spindle goes back with the part.)
G21 G18 G40 G97 G99
G28 U0 W0
T0101 (OD ROUGH)
G50 S2500
G96 S180 M3
G0 X54. Z0.
G1 X-1.6 F0.15 (FACE)
G0 Z2.
X44.
G1 Z-53. F0.25
G0 U2. Z2.
X38.
G1 Z-53.
G0 U2. Z2.
X36.
G1 Z-53.
X52.
G0 Z2.
G28 U0 W0
T0909 (PARTING BLADE 2.5)
G97 S800 M3
G0 X54. Z-56.
G0 B-636. (SUB-SPINDLE OVER THE PART)
M110 (CLAMP THE SUB CHUCK)
G1 X-1. F0.05 (PART OFF THROUGH THE AXIS)
G0 X54.
G0 B0. (SUB-SPINDLE BACK WITH THE PART)
M5
G28 U0 W0
M111 (UNCLAMP: THE PART DROPS INTO THE CATCHER)
M30
%
