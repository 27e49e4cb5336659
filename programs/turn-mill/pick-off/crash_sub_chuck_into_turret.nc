%
O2102 (CRASH: THE SUB-SPINDLE COMES FORWARD TOO FAR, INTO THE TURRET)
(As pick_off.nc, but the sub-spindle is sent to B-666. instead of B-636.: its chuck, 180 mm)
(across, stops 30 mm too far forward, clear of the turret, but over the drum's way in: as the)
(blade feeds in to part off, the turret drum runs into the sub chuck's body.)
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
G0 B-666. (SUB-SPINDLE OVER THE PART: 30 MM TOO FAR)
M110 (CLAMP THE SUB CHUCK)
G1 X-1. F0.05 (PART OFF THROUGH THE AXIS)
G0 X54.
G0 B0. (SUB-SPINDLE BACK WITH THE PART)
M5
G28 U0 W0
M111 (UNCLAMP: THE PART DROPS INTO THE CATCHER)
M30
%
