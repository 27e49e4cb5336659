; Fanuc G71 type I, two-block form (G71 U R, then G71 P Q U W F), worked by hand in radius mm
G21 G18 G99 G97 S800 M3
T0101
G0 X50 Z2
G71 U2 R0.5
G71 P10 Q50 U0.4 W0.1 F0.25
N10 G0 X30
N20 G1 Z-10 F0.1
N30 X40 Z-20
N40 Z-30
N50 X52
G0 X60
M30
; Start A = X50 Z2: radius 25, z 2. Allowance U0.4 = 0.2 on the radius, W0.1 in +Z.
; Offset profile: A' = (15.2, 2.1) -> (15.2, -9.9) -> (20.2, -19.9) -> (20.2, -29.9) -> (26.2, -29.9).
; Levels step Δd = 2 from 25 toward 15.2: span 9.8, ceil(9.8 / 2) = 5 passes: 23, 21, 19, 17, then
; the last pass along the offset profile.
; Where a level L meets the profile: the first profile point whose x reaches L.
;   L = 23, 21: only the N50 face reaches them: z = -29.9.
;   L = 19, 17: the taper x = 15.2 + (-9.9 - z) / 2, so z = -9.9 - 2 (L - 15.2): -17.5 and -13.5.
; Each pass (line 6): rapid X to L at z 2, feed Z to the meeting point, rapid 45 degrees by
; e = 0.5 to (L + 0.5, z + 0.5), rapid back to z 2.
; Last pass: rapid to A' (N10 is G0), feed along the offset profile at F0.25 (the profile's F0.1
; is for G70), end (26.2, -29.9) lies outside radius 25: back along Z to 2 first, then X to 25.
; After the cycle execution resumes after N50: line 12 G0 X60 -> (30, 2).
