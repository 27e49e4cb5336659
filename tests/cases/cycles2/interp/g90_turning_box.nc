(G90 turning box cycle, G-code system A: modal, three boxes from one start point, the last tapered)
G21 G99 G97 S800 M3
T0101
G0 X52 Z2
G90 X46 Z-20 F0.2
X42
X38 R-2
G0 X60 Z10
M30
(Hand-worked moves, canon prints X as a radius, Z in program coordinates.)
(Start S = X26 Z2 [X52 is a diameter].)
(line 5, E = X23 Z-20, R 0: rapid to X23 Z2, feed to X23 Z-20, feed out to X26 Z-20, rapid to S.)
(line 6, only X: E = X21 Z-20 [Z kept]: rapid X21 Z2, feed X21 Z-20, feed X26 Z-20, rapid S.)
(line 7, X38 R-2: E = X19 Z-20, cut start X = 19 + R = 17: rapid X17 Z2, feed X19 Z-20,)
(feed X26 Z-20, rapid S.  line 8: G0 cancels the cycle; rapid to X30 Z10.)
