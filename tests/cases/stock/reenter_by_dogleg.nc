(test-case: modes=step,exact)
(the same pass, but the way back is one rapid on both axes: on this dogleg machine Z, the faster axis,)
(reaches Z-30 first while X is still 0.17 mm out, so the insert's leading edge dips into the shoulder)
(the pass left. Both modes see it; a straight line back would only touch.)
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
G0 X44. Z-30.
G0 U2. W1.
Z2.
G28 U0 W0
M30
%
