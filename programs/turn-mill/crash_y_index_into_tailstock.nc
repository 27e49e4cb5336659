%
O2005 (CRASH: AN INDEX WITH THE TURRET OFF CENTRE IN Y SWINGS THE DRILL INTO THE LIVE CENTRE)
(the sub-spindle has come forward to B-500. with its live centre: point at Z62., shank 30 mm)
(across from Z88. to its chuck face at Z122.; the radial drill waits beside the shank at Y50.,)
(its point on the spindle's centre height X0. but 50 mm off to the side, clear of the centre.)
(On the centre line the turret turns its tools through the working position, away from the)
(part; 50 mm off centre, T07 comes the short way round and the drill's point sweeps past the)
(spindle axis at 5 mm: through the live centre's shank.)
G21 G18 G40 G97 G98
G28 U0 W0
T0808 (RADIAL LIVE DRILL D8)
G0 B-500. (SUB-SPINDLE FORWARD)
G0 Y50.
G0 Z95.
X0.
T0707 (INDEXED HERE, 50 MM OFF CENTRE)
G0 X200.
G0 Y0.
G0 B0. (SUB-SPINDLE BACK)
G28 U0 W0
M30
%
