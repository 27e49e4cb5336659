(test-case: modes=step,exact)
; A G71 whose profile runs past the jaw faces: program Z-79 is 1 mm behind the chuck face (program
; Z0 lies 78 mm in front of it), so the roughing passes drive the insert into the chuck. Each
; finding is at the cycle's line 8 (the moves record the profile line N20 too), in both modes.
G21 G18 G99 G97 S800 M3
T0101
G0 X50 Z3
G71 P10 Q30 U0.4 W0.1 D2 F0.25
N10 G0 X30
N20 G1 Z-79
N30 X52
G0 X60
M30
; A = (25, 3); offset profile (15.2, 3.1) -> (15.2, -78.9) -> (26.2, -78.9). Levels 23, 21, 19,
; 17, then the profile: each pass feeds to z -78.9, 0.9 mm behind the chuck face at -78. The
; chuck face begins at radius 25: the passes at 23, 21 and 19 and the last pass (its N30 face
; climbs from 15.2 to 26.2) reach it with the insert's flank; at level 17 the insert's lower edge
; is still in front of the face where it crosses radius 25 (8 mm up the flank it has risen 1.33 mm:
; z -78.9 + 1.33 > -78), so that pass touches nothing.
