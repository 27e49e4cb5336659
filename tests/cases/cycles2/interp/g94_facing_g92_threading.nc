(G94 facing box and G92 threading box, G-code system A; G0 G40 G80 on one line is legal)
G21 G99 G97 S600 M3
T0101
G0 G40 G80 X54 Z3
G94 X20 Z-1 F0.15
Z-2
Z-3 R-1.5
G0 X56 Z5 T0505
G92 X48.2 Z-15 F1.5
X47.6
X47.38
G0 X60 Z20
M30
(Hand-worked moves [X radius, Z program]:)
(line 4: G80 is not in group 01, so G0 moves: rapid X27 Z3 = S.)
(line 5 G94, E = X10 Z-1: rapid in Z to X27 Z-1, feed to X10 Z-1, feed out in Z to X10 Z3, rapid to S.)
(line 6 only Z: E = X10 Z-2 [X kept]: rapid X27 Z-2, feed X10 Z-2, feed X10 Z3, rapid S.)
(line 7 R-1.5: cut starts at Z -3 + R = -4.5: rapid X27 Z-4.5, feed X10 Z-3, feed X10 Z3, rapid S.)
(line 8: index to the thread tool T05 [step 4 comes before the motion], then rapid X28 Z5 = new S.)
(line 9 G92, E = X24.1 Z-15, lead 1.5: rapid X24.1 Z5, thread X24.1 Z-15, rapid out X28 Z-15, rapid S.)
(line 10: X23.8; line 11: X23.69, each the same four moves.  line 12: rapid X30 Z20.)
