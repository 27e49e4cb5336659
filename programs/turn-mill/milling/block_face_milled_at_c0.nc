%
O2211 (MILL THE TOP FLAT OF A 40 MM SQUARE BAR AT C0)
(The job beside this program holds a 40 x 40 square bar; at C0 its top flat is x = 20, X40.)
(T10, the radial end mill D12, takes 1 mm off that flat across the bar in Y at Z-10: its end)
(face at X38, from Y-30 to Y30, beyond both sides of the 40 mm bar. Clean.)
G21 G18 G40 G97 G98
G28 U0 W0
M5
T1010 (RADIAL LIVE END MILL D12)
M154 (SPINDLE AS C AXIS)
G28 H0
M133 P3000 (LIVE TOOL ON)
G0 X70. Z-10. C0.
G0 Y-30.
G1 X38. F300. (1 MM BELOW THE FLAT, BESIDE THE BAR)
G1 Y30. F200. (ACROSS THE FLAT)
G0 X70.
M135 (LIVE TOOL OFF)
M155
G28 U0 W0
G28 V0
M30
%
