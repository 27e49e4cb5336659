(facing passes that cross the spindle axis to X-1.6 cut both sides; the last rapid runs along the faced front)
%
G21 G18 G40 G97 G99
G28 U0 W0
T0101
G96 S180 M3
G50 S2500
G0 X54. Z1.
G1 X-1.6 F0.15
G0 Z3.
X54.
Z0.
G1 X-1.6
G0 X54. (ALONG THE FACE JUST CUT: CLEAN)
Z3.
G28 U0 W0
M30
%
