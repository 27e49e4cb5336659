; Fanuc G72 facing, two-block form (G72 W R, then G72 P Q U W F), worked by hand
G21 G18 G99 G97 S800 M3
T0101
G0 X54 Z2
G72 W1.5 R0.5
G72 P10 Q30 U0 W0.2 F0.2
N10 G0 Z-4
N20 G1 X20
N30 Z2
G0 X60
M30
; A = (27, 2). Allowance W0.2 in +Z. Offset profile: A' = (27, -3.8) -> (10, -3.8) -> (10, 2.2).
; G72 steps in Z from 2 toward -3.8: span 5.8, Δd 1.5: ceil(3.87) = 4 passes: 0.5, -1, -2.5, then the profile.
; Each level meets the profile first where z reaches it: on N30 (x = 10) for all three levels.
; Each pass: rapid Z to the level at x 27, feed X to 10, rapid 45 degrees by 0.5 to (10.5, level + 0.5),
; rapid back to x 27.
; Last pass: rapid to (27, -3.8), feed to (10, -3.8), (10, 2.2). z 2.2 lies beyond the start level 2:
; back along X to 27 first, then Z to 2.
