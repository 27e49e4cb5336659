(test-case: modes=step,exact)
(As boring_bar_faces_deeper_than_its_bar_front, but facing 1.5 mm deep: the tip at Z0.5, machine z)
(78.5, the bar front at z 80.5, 0.5 mm clear of the uncut bar end at z 80. No finding.)
%
G21 G18 G40 G97 G99
G28 U0 W0
T0303
G97 S1200 M3
G0 X90. Z0.5
G1 X0. F0.15
G0 Z5.
G28 U0 W0
M30
%
