; G71 errors a control raises, each a program finding at the cycle's line
G21 G18 G99 G97 S800 M3
T0101
G0 X50 Z2
G71 P10 Q40 U0.4 W0.1 F0.25
G71 U2 R0.5
G71 P99 Q40 U0.4 F0.25
G71 P40 Q10 U0.4 F0.25
G71 P10 Q40 U0.4 F0.25
N10 G0 X30
N20 G1 Z-10 F0.1
N30 X20 Z-20
N40 X52
G0 X60
M30
; line 5: no depth of cut yet (no G71 U R, no D).
; line 7: no block N99.  line 8: Q (N10) before P (N40).
; line 9: type I profile whose X turns back (N30 goes to a smaller diameter).
