(Drilling cycles on the spindle axis as Haas lathes run them [R the absolute Z of the R plane, drill_r = "absolute"]: G83 modal with a repeat, G82, G84, G85, an off-axis hole refused, G80) (test-case: machine=haas-style-tailstock)
G21 G99 G97 S800 M3
G28 U0 W0
T0606
G0 X0 Z10
G83 Z-20 R2. Q8000 F0.1
Z-25
G80
G82 Z-5 R2. P500
G84 Z-10 R3. F1.5
G85 Z-8 R3. F0.1
G81 X10 Z-5 R2.
G0 G40 G80 X0 Z30
M30
(line 3: home, where the machine starts: no move.  line 4: index to T06.  line 5: rapid X0 Z10: the initial level is Z10.)
(line 6 G83: R plane Z2, Q8000 = 8 mm, bottom Z-20 [22 mm below R: pecks to -6, -14, -20].)
(  rapid Z2; feed Z-6; rapid out Z2; rapid down to 1 mm above: Z-5; feed Z-14; rapid Z2; rapid Z-13; feed Z-20;)
(  rapid out to R Z2; rapid to the initial level Z10 [system A].)
(line 7: the same cycle, bottom Z-25 [27 mm: -6, -14, -22, -25]: rapid Z2; feed -6; Z2; Z-5; feed -14; Z2; Z-13;)
(  feed -22; Z2; Z-21; feed -25; rapid Z2; rapid Z10.)
(line 8: G80 cancels.)
(line 9 G82, F0.1 modal, P500 = 0.5 s: rapid Z2, feed Z-5, dwell 0.5, rapid Z2, rapid Z10.)
(line 10 G84, F1.5 the pitch: rapid Z3, feed Z-10, spindle reversed: feed out Z3, rapid Z10.)
(line 11 G85, F0.1: rapid Z3, feed Z-8, feed out Z3, rapid Z10.)
(line 12: X10 is off the spindle axis: a program error, no move.)
(line 13: G0 and G80 together: rapid X0 Z30.)
