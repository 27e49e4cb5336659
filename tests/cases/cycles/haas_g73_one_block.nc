; Haas G73 one-block form (P Q U W I K D F), worked by hand in radius mm
G21 G18 G99 G97 S800 M3
T0101
G0 X60 Z5
G73 P10 Q20 U0.4 W0.2 I3 K1 D2 F0.2
N10 G0 X30 Z3
N20 G1 X52 Z-20
G0 X70
M30
; A = (30, 5). Allowance U0.4 W0.2 = (0.2, 0.2); relief I3 (a radius) K1; D2 passes:
; shift k = allowance + relief (2 - k) / (2 - 1): (3.2, 1.2), then (0.2, 0.2).
; Profile (15, 3) -> (26, -20).
; Pass 1: rapid to (18.2, 4.2), feed to (29.2, -18.8); 29.2 < 30: X out to 30 first, then Z to 5.
; Pass 2: rapid to (15.2, 3.2), feed to (26.2, -19.8); X to 30, then Z to 5.
; Execution resumes after N20: G0 X70 -> (35, 5).
