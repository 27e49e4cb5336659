(test-case: modes=step,exact)
(The rapid leaves toward the chuck: the nose enters the bar beyond the shoulder, material the)
(feed never cut: rapid_into_stock.)
G21 G18 G99 G97 S800 M3
T0101
G0 X52. Z2.
G0 X46.
G1 Z-30. F0.2
G0 X48. Z-31.
M30
