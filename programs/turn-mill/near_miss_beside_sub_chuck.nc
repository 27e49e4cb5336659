%
O2006 (NEAR MISS: THE RADIAL DRILL STOPS HALF A MILLIMETRE FROM THE SUB-SPINDLE CHUCK)
(the set-up of crash_y_move_into_sub_chuck.nc, but the Y move stops at Y46.31: the drill's)
(side passes 0.5 mm outside the chuck body, 180 mm across. Clean as it stands; with)
(--clearance 1 a near miss from line 13 to line 15.)
G21 G18 G40 G97 G98
G28 U0 W0
T0808 (RADIAL LIVE DRILL D8)
G0 B-500. (SUB-SPINDLE FORWARD)
G0 Y50.
G0 Z202.
X160.
G1 Y46.31 F2000.
G4 P1.
G0 Y50.
G0 B0. (SUB-SPINDLE BACK)
G28 U0 W0
G28 V0
M30
%
