%
O2208 (CRASH: A FLAT END MILL LOWERED ONTO A BULL NOSE'S CORNERS)
(T07 holds a Ø10 bull-nose end mill with 2 mm corners, from the job beside this program: it)
(plunges 3 mm into the face, 10 mm off centre, leaving a floor Ø6 flat with a 2 mm fillet round)
(it. T11, the Ø10 flat end mill, then rapids down the hole to the floor, Z-3. Worked by hand:)
(the fillet fills the corner of the flat end's square section; its deepest point, on the)
(corner's diagonal, is 2 - SQRT[2] = 0.586 mm inside the flat end: rc x [1 - 1/SQRT[2]].)
(A flat-ended model of the bull nose would have left a square corner and no finding.)
G21 G18 G40 G97 G98
G28 U0 W0
M5
T0707 (AXIAL LIVE BULL-NOSE END MILL D10 R2)
M154 (SPINDLE AS C AXIS)
G28 H0
M133 P3000 (LIVE TOOL ON)
G0 X20. Z2. C0. Y0.
G1 Z-3. F100. (PLUNGE 3 DEEP)
G0 Z2.
M135
T1111 (AXIAL LIVE END MILL D10, FLAT)
G0 X20. Z2. C0. Y0.
G0 Z-3. (DOWN TO THE FLOOR AT RAPID, ONTO THE FILLET)
G0 Z2.
M155
G28 U0 W0
G28 V0
M30
%
