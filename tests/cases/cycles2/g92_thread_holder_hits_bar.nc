(test-case: modes=step,exact)
(A G92 thread cut 15 mm deep into the 50 mm bar in one pass with the roughing tool: its holder runs into the bar inside the cycle, reported at the cycle's line 6 in both modes)
G21 G99 G97 S600 M3
T0101
G0 X30 Z5
G92 X19.2 Z-15 F1.5
G0 X60 Z20
M30
