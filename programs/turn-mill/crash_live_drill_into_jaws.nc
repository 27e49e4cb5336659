%
O2003 (CRASH: AXIAL LIVE DRILL FED PAST THE BAR INTO THE CHUCK JAWS)
(the holes are meant on a 100 mm bolt circle of a flange, but the bar here is 50 mm:)
(X100. is off the part, and Z-95. is past the outer step of the jaws at Z-90.)
G21 G18 G40 G97 G99
G28 U0 W0
T0707 (AXIAL LIVE DRILL D10)
M154 (SPINDLE AS C AXIS)
G28 H0
M133 P2500
G98
G0 X100. Z5. C0.
G1 Z-95. F120.
G0 Z5.
M135
M155
G99
G28 U0 W0
M30
%
