(test-case: modes=step,exact)
(T06 drills a 20 mm hole to Z-25; T03 bores it to 27 mm, then to 36 mm, both to Z-6, the bore step.)
(That leaves a ring below the step, r 10 .. 18. Its top is the 27 mm pass's bottom edge, which rises)
(1 in 12 toward the axis: Z-6 + 0.256 at r 10. Line 30 then bores a taper from X36 Z-6 to X28 Z-14)
(in one pass: the tip's r falls 0.5 mm per mm of depth. The bar's front face is 2 mm behind the)
(cutting corner and reaches from tip-15 to tip-4 in r, while at that height the insert reaches down)
(only to tip-6.09. So at depth u below the step the bar front is in the ring between r 10 and the)
(cut, tip-6.09 = 11.91-0.5u, once u > 2-0.256 = 1.744: first contact at X34.256 Z-7.744, tip r 17.13.)
(Lower down the taper the insert cuts that ring away - at the end, at every height the bar passed,)
(the cut reaches below r 10 - so the stock after the move is clear: only the stock at the instant)
(shows the bar front leading into the ring. Depth rises, then falls: tests/depth_cases.rs.)
%
G21 G18 G40 G97 G99
G28 U0 W0
T0606
G97 S1500 M3
G0 X0. Z5.
G1 Z-25. F0.2
G0 Z5.
G28 U0 W0
T0303
G97 S2500 M3
G0 X27. Z3.
G1 Z-6. F0.3
G0 W3.
X24.
Z3.
X36.
G1 Z-6.
X28. Z-14.
G0 W3.
X24.
Z5.
G28 U0 W0
M30
%
