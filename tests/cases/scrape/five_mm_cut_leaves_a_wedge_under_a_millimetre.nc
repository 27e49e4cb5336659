(test-case: modes=step,exact)
(A 5 mm depth of cut: the wedge is 0.68 mm thick at its thickest, still a scrape.)
G21 G18 G99 G97 S800 M3
T0101
G0 X52. Z2.
G0 X40.
G1 Z-30. F0.2
G0 X52.
M30
