; Fanuc G71 type I over a convex arc (G3), worked by hand in radius mm
G21 G18 G99 G97 S800 M3
T0101
G0 X50 Z3
G71 U3 R0.5
G71 P10 Q40 U0 W0 F0.2
N10 G0 X20
N20 G1 Z0
N30 G3 X40 Z-10 R10
N40 G1 X52
G0 X60
M30
; A = (25, 3), no allowance. Profile (10, 3) -> (10, 0) -> arc about (10, -10), radius 10, to
; (20, -10) -> (26, -10). Levels step 3 from 25 toward 10: 5 passes: 22, 19, 16, 13, the profile.
; Level 22 lies above the arc's top (20): N40 meets it at z -10.
; On the arc (x - 10)^2 + (z + 10)^2 = 100, so z = -10 + sqrt(100 - (L - 10)^2):
;   L = 19: -10 + sqrt(19) = -5.641101;  L = 16: -10 + 8 = -2;  L = 13: -10 + sqrt(91) = -0.460608.
; Each pass: rapid to (L, 3), feed to (L, z), rapid to (L + 0.5, z + 0.5), rapid to (L + 0.5, 3).
; Last pass: rapid to (10, 3), feed to (10, 0), the arc (canon: ARC_FEED to z -10 x 20 about
; z -10 x 10), feed to (26, -10); 26 > 25: back along Z to 3 first, then X to 25.
