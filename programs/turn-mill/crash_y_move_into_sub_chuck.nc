%
O2004 (CRASH: A Y MOVE SWINGS THE RADIAL DRILL INTO THE SUB-SPINDLE CHUCK)
(the sub-spindle has come forward to B-500., its chuck body, 180 mm across, now between Z152.)
(and Z252.; the radial drill waits beside it at Y50., clear, its point 80 mm from the axis,)
(and the program moves Y back to 0 for the next hole, as if the sub-spindle were still parked)
G21 G18 G40 G97 G98
G28 U0 W0
T0808 (RADIAL LIVE DRILL D8)
G0 B-500. (SUB-SPINDLE FORWARD)
G0 Y50.
G0 Z202.
X160.
G1 Y0. F2000.
G0 Y50.
G0 B0. (SUB-SPINDLE BACK)
G28 U0 W0
G28 V0
M30
%
