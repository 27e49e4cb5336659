%
O2201 (MILL A FLAT, THEN RAPID BACK OVER IT)
(The radial end mill, Ø12, mills a flat 5 mm deep across the Ø50 bar at Z-20. with Y, the)
(spindle positioned at C0; it then rapids back across the bar 1 mm above the flat: inside the)
(round bar it was, clear of the part it is now.)
G21 G18 G40 G97 G98
G28 U0 W0
M5
T1010 (RADIAL LIVE END MILL D12)
M154 (SPINDLE AS C AXIS)
G28 H0
M133 P3000 (LIVE TOOL ON)
G0 X70. Z-20. C0.
G0 Y-40.
G1 X40. F300. (5 MM BELOW THE SURFACE, BESIDE THE BAR)
G1 Y40. F200. (THE FLAT)
G0 X42. (1 MM ABOVE THE FLAT)
G0 Y-40. (RAPID BACK OVER THE FLAT)
G0 X70.
M135 (LIVE TOOL OFF)
M155
G28 U0 W0
G28 V0
M30
%
