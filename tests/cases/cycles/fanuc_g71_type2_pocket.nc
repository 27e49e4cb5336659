; Fanuc G71 type II (block P names X and Z) with a pocket, worked by hand in radius mm
G21 G18 G99 G97 S800 M3
T0101
G0 X50 Z3
G71 U4 R1
G71 P10 Q70 U0 W0 F0.2
N10 G0 X40 Z3
N20 G1 Z-10
N30 X20 Z-15
N40 Z-25
N50 X40 Z-30
N60 Z-40
N70 X52
G0 X60
M30
; A = (25, 3); no allowance. Profile (20, 3) -> (20, -10) -> (10, -15) -> (10, -25) -> (20, -30)
; -> (20, -40) -> (26, -40). Type II: X falls into a pocket (N30) and rises out of it (N50).
; Levels step Δd = 4 from 25 toward the deepest point 10: span 15, ceil(3.75) = 4 passes:
; 21, 17, 13, then the last pass along the profile. Retract e = 1.
; Level 21: the whole profile lies below 21 until N70 rises through it at z -40: one stretch
; open toward A: rapid to (21, 3) (N10 is G0), feed to (21, -40), rapid 45 degrees to (22, -39),
; rapid back to (22, 3).
; Level 17: the profile starts above it (20); N30 falls through 17 at 3/10 of its length:
; (17, -11.5); N50 rises through it at 7/10: (17, -28.5). A pocket from -11.5 to -28.5: rapid up
; to the start level (25, 3), over to (25, -11.5), down to the level cut before (21, -11.5), feed
; to (17, -11.5), feed to (17, -28.5), rapid 45 degrees to (18, -27.5), up to (25, -27.5), rapid to A.
; Level 13: N30 at 7/10: (13, -13.5); N50 at 3/10: (13, -26.5): from A over to (25, -13.5), down
; to (17, -13.5), feed to (13, -13.5), (13, -26.5), rapid to (14, -25.5), (25, -25.5), A.
; Last pass: rapid to (20, 3), the profile at F0.2; it ends at (26, -40) outside 25: back along Z
; to 3, then X to 25. Execution resumes after N70: G0 X60 -> (30, 3).
; The built-in machine's T01 is a general OD tool: its holder cannot follow the insert down the
; steep walls of the pocket, and the checker reports the holder in the stock at the cycle's line 6
; (the level 13 plunge, and the last pass down N30).
