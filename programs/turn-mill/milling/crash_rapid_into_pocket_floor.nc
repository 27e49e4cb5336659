%
O2202 (CRASH: A RAPID BACK INTO A FACE POCKET BELOW ITS FLOOR)
(The axial end mill, Ø10, mills a slot 3 mm deep into the front face, 10 mm off centre, along)
(Y; it leaves, and comes back down at rapid to Z-4.: 1 mm below the slot's floor.)
G21 G18 G40 G97 G98
G28 U0 W0
M5
T1111 (AXIAL LIVE END MILL D10)
M154 (SPINDLE AS C AXIS)
G28 H0
M133 P3000 (LIVE TOOL ON)
G0 X20. Z2. C0. Y-8.
G1 Z-3. F150. (PLUNGE 3 DEEP)
G1 Y8. F200. (THE SLOT)
G0 Z2.
G0 Y0.
G0 Z-4. (BACK DOWN AT RAPID, BELOW THE FLOOR)
G0 Z2.
M135 (LIVE TOOL OFF)
M155
G28 U0 W0
G28 V0
M30
%
