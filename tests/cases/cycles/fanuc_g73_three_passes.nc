; Fanuc G73 pattern repeat, two-block form (G73 U W R3, then G73 P Q U W F), worked by hand
G21 G18 G99 G97 S800 M3
T0101
G0 X56 Z5
G73 U4 W2 R3
G73 P10 Q30 U1 W0.5 F0.2
N10 G0 X30 Z0
N20 G1 Z-20
N30 X52
G0 X60
M30
; A = (28, 5). Allowance (0.5, 0.5); relief U4 W2 (U a radius here: 4 in X, 2 in Z), 3 passes:
; shift k = allowance + relief (3 - k) / 2: (4.5, 2.5), (2.5, 1.5), (0.5, 0.5).
; Profile (15, 0) -> (15, -20) -> (26, -20). Each pass: rapid to (15, 0) + shift, feed along the
; shifted profile, then back to A: the end x 26 + shift.x is 30.5, 28.5, 26.5.
;   pass 1 ends (30.5, -17.5): outside 28 -> Z to 5 first, then X to 28.
;   pass 2 ends (28.5, -18.5): outside -> Z to 5, X to 28.
;   pass 3 ends (26.5, -19.5): inside 28 -> X to 28 first, then Z to 5.
;   The built-in machine holds a bar, not a casting: passes 2 and 3 start with a rapid into the
;   material the earlier, larger passes left (z below the bar's face at 2), and the checker reports
;   them at the cycle's line 6 (rapid_into_stock twice).
