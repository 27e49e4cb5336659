(test-case: modes=step,exact)
(a pass ends, pulls off, and the tool comes back by rapids to exactly where the pass ended: a touch, clean.)
(each rapid moves one axis, so its path is the same on a dogleg machine: first down the pass's own)
(retract column, then back along the pass to its final pose)
%
G21 G18 G40 G97 G99
G28 U0 W0
T0101
G96 S200 M3
G50 S3000
G0 X54. Z2.
X44.
G1 Z-30. F0.25
U2. W1.
G0 X44.
G0 Z-30. (EXACTLY THE FINAL POSE OF THE PASS)
G0 U2. W1.
Z2.
G28 U0 W0
M30
%
