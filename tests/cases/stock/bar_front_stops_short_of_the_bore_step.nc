(test-case: modes=step,exact)
(As bar_front_leads_down_a_taper, but the taper move, the G1 after the 36 mm pass, stops at X35)
(Z-7, 1 mm down: the bar front, 2 mm behind the cutting corner, ends at Z-5, above the ring at the)
(bore step Z-6, whose top is at most Z-6 + 0.256 at r 10 and lower further out: 0.74 mm short.)
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
X35. Z-7.
G0 W3.
X24.
Z5.
G28 U0 W0
M30
%
