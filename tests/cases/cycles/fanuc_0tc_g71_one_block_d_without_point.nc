(The one-block G71 of old Fanuc controls [0-TC, 10T, 15T: machine g71_d = "increment"]: D1500 without a decimal point is 1.5 mm, D1.5 with one is 1.5 mm too: lines 5 and 10 make the same passes) (test-case: machine=generic-slant-bed-old-fanuc)
G21 G18 G99 G97 S800 M3
T0101
G0 X44. Z3.
G71 P10 Q30 U0.4 W0.1 D1500 F0.25
N10 G1 X36. F0.1
N20 Z-15.
N30 X46.
G0 X44. Z3.
G71 P10 Q30 U0.4 W0.1 D1.5 F0.25
G0 X100. Z100.
M30
; A = (22, 3) (radius, program Z; the bar face is at Z2). Allowance U0.4 = 0.2 on the radius, W0.1 along Z.
; Offset profile: (18.2, 3.1) -> (18.2, -14.9) -> (23.2, -14.9). Span 22 - 18.2 = 3.8, Δd 1.5: levels 20.5 and 19, then the last pass.
; Level 20.5: feed in X to (20.5, 3) [N10 is G1], feed to the offset face (20.5, -14.9), retract 45° by e = 0.5 to (21, -14.4), rapid back to (21, 3).
; Level 19: feed to (19, 3), (19, -14.9), retract to (19.5, -14.4), rapid to (19.5, 3).
; Last pass: feed to (18.2, 3.1), along the offset profile to (18.2, -14.9), (23.2, -14.9); 23.2 > 22: rapid along Z to 3, then X to 22.
; Line 9 comes back to (22, 3) and line 10 repeats the same passes with D1.5. Read as 1500 mm [g71_d = "length"], D1500 would make one pass.
