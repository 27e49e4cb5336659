; G71 errors a control raises, each a program finding at the cycle's line (the profile comes first, in the air, so that no refused cycle skips over the others)
G21 G18 G99 G97 S800 M3
T0101
G0 X70 Z5
N10 G0 X60
N20 G1 Z-10 F0.1
N30 X56 Z-20
N40 X64
G0 X70 Z5
G71 P10 Q40 U0.4 W0.1 F0.25
G71 U2 R0.5
G71 P99 Q40 U0.4 F0.25
G71 P40 Q10 U0.4 F0.25
G71 P10 Q40 U0.4 F0.25
G71 P10 F0.25
G0 X80
M30
; line 10: no depth of cut yet (no G71 U R before it, no D in it).
; line 12: no block N99.  line 13: Q (N10) before P (N40).
; line 14: a type I profile whose X turns back (N30, line 7, goes to a smaller diameter).
; line 15: P without Q.
; None of them moves: after the profile's plain run (lines 5-8, above the bar) the tool goes
; from line 9 straight to line 16.
