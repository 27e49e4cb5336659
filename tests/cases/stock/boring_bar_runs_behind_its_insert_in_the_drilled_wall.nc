(test-case: modes=step,exact)
(T06 drills a 20 mm hole to Z-25; T03 bores it to 27 mm down to Z-23 in one pass. Its bar's top, 3 mm)
(below the cutting corner at r 10.5, is 0.5 mm inside the drilled wall, but always behind the insert,)
(which has already cut that wall to r 13.5: against the stock at the instant the bar is about 1.8 mm)
(clear, until near the end of the pass its front, 2 mm behind the corner, reaches the cone the drill)
(point left near the axis, below r 7.5 where the insert does not reach: a collision at Z-22.555. When gap)
(bounds used the stock before the move, this pass was tested sample by sample: 10-50 times the cost.)
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
G1 Z-23. F0.3
G0 W3.
X18.
Z5.
G28 U0 W0
M30
%
