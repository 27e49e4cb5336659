(test-case: modes=step,exact)
(A 95-degree-style tool turns to a shoulder and rapids straight out: its leading edge, leaning)
(9.5 degrees on the built-in T01, drags over the wedge it left on the shoulder: rapid_scrape.)
G21 G18 G99 G97 S800 M3
T0101
G0 X52. Z2.
G0 X46.
G1 Z-30. F0.2
G0 X52.
G0 Z2.
M30
