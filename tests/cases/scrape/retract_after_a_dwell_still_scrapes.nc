(test-case: modes=step,exact)
(A dwell at the bottom of the cut changes nothing: the rapid still follows the feed's cut.)
G21 G18 G99 G97 S800 M3
T0101
G0 X52. Z2.
G0 X46.
G1 Z-30. F0.2
G4 P0.5
G0 X52.
M30
