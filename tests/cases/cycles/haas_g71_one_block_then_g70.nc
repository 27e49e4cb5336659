; Haas G71 one-block form (P Q U W D F) then G70 with the profile's own feed, worked by hand
G21 G18 G99 G97 S800 M3
T0101
G0 X44 Z3
G71 P10 Q30 U1 W0 D3 F0.3
N10 G1 X36 F0.1
N20 Z-15
N30 X46
G70 P10 Q30
G0 X60
M30
; A = (22, 3) (the built-in machine's bar ends at Z2). Allowance U1 = 0.5 on the radius, W0. Offset profile: (18.5, 3) -> (18.5, -15) -> (23.5, -15).
; Span 22 - 18.5 = 3.5, D3: ceil(3.5 / 3) = 2 passes: level 19, then the offset profile.
; Level 19 meets the N30 face at z -15: feed to (19, -15), rapid to (19.5, -14.5), rapid to (19.5, 3).
; N10 is G1: the infeeds are feeds: (19, 3) and then (18.5, 3) at F0.3 (recorded at line 5).
; Last pass (18.5, -15), (23.5, -15); 23.5 > 22: back along Z to 3, then X to 22.
; G70 (line 9) from (22, 3): N10 feed to (18, 3), N20 (18, -15), N30 (23, -15) at F0.1 (the profile's F);
; then back: 23 > 22, so Z to 3 first, then X to 22. Execution goes on after G70: G0 X60 -> (30, 3).
