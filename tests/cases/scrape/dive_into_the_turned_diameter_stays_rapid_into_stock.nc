(test-case: modes=step,exact)
(The rapid goes back along the diameter just turned, 0.25 mm below it: it moves into the)
(surface the feed traced, not away from it: a gouge, rapid_into_stock.)
G21 G18 G99 G97 S800 M3
T0101
G0 X52. Z2.
G0 X46.
G1 Z-30. F0.2
G0 X45.5 Z-10.
M30
