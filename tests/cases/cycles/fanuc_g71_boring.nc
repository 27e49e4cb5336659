(test-case: machine=generic-slant-bed-tube)
; Fanuc G71 boring (inside, U negative) with the T03 boring bar in the 20 mm bore of a tube,
; worked by hand in radius mm; the cycle (G71 P Q) is on line 8
G21 G18 G99 G97 S800 M3
T0303
G0 X20 Z2
G71 U1.5 R0.5
G71 P10 Q50 U-0.4 W0.1 F0.2
N10 G0 X40
N20 G1 Z-10
N30 X30 Z-15
N40 Z-25
N50 X18
G0 Z10
M30
; A = (10, 2). Allowance U-0.4 = -0.2 on the radius (toward the axis, inside), W0.1.
; Offset profile (19.8, 2.1) -> (19.8, -9.9) -> (14.8, -14.9) -> (14.8, -24.9) -> (8.8, -24.9).
; Levels step 1.5 outward from 10 toward 19.8: span 9.8, ceil(6.53) = 7 passes: 11.5, 13, 14.5,
; 16, 17.5, 19, then the profile.
; A level L is met where the profile first comes down to L:
;   11.5, 13, 14.5: only N50 (x 14.8 -> 8.8 at z -24.9) does: z -24.9.
;   16, 17.5, 19: the taper N30, x = 19.8 - (-9.9 - z): z = -9.9 - (19.8 - L) = -13.7, -12.2, -10.7.
; Each pass: rapid X to L at z 2, feed Z, rapid 45 degrees inward and back to (L - 0.5, z + 0.5),
; rapid to z 2. Last pass: rapid to (19.8, 2.1), the profile at F0.2, ending at (8.8, -24.9),
; inside A's radius 10 (toward the axis: the way out of the bore): Z first to 2, then X to 10.
