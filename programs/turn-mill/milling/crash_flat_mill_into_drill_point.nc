%
O2207 (CRASH: A FLAT END MILL LOWERED INTO A DRILLED HOLE'S POINT)
(T07 holds a Ø10 drill with a 118° point, from the job beside this program: it drills 10 mm deep)
(into the face, 10 mm off centre. T11, the Ø10 flat end mill, then rapids down the hole to Z-8.)
(Worked by hand: the drill's cone is r / TAN[59°] = 3.004 mm long, so the hole is full Ø10 only)
(to Z-6.996 and narrows to its point at Z-10. The flat end at Z-8 stands in the cone's material:)
(the deepest point, as far from its side as from its end face, is 0.627 mm inside it:)
(a + 1.664 b <= 5 - 2 x 1.664 with a = b. A flat-ended model of the drill would have left a)
(flat floor at Z-10 and no finding.)
G21 G18 G40 G97 G98
G28 U0 W0
M5
T0707 (AXIAL LIVE DRILL D10, 118 DEG POINT)
M154 (SPINDLE AS C AXIS)
G28 H0
M133 P2000 (LIVE TOOL ON)
G0 X20. Z2. C0. Y0.
G1 Z-10. F100. (DRILL 10 DEEP)
G0 Z2.
M135
T1111 (AXIAL LIVE END MILL D10, FLAT)
G0 X20. Z2. C0. Y0.
G0 Z-8. (DOWN THE HOLE AT RAPID, INTO THE DRILL'S CONE)
G0 Z2.
M155
G28 U0 W0
G28 V0
M30
%
