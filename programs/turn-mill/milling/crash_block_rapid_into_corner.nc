%
O2213 (CRASH: A RAPID INTO A CORNER OF A 40 MM SQUARE BAR)
(The job beside this program holds a 40 x 40 square bar. Turned to C45, one of its corners)
(points at +x, 20 x SQRT[2] = 28.284 mm from the axis. T10, the radial end mill D12, rapids)
(across it in Y at Z-20 with its end face at X54, x = 27: clear of the flats, but the corner's)
(ridge stands 28.284 - 27 = 1.284 mm into the mill's end face at Y0.)
G21 G18 G40 G97 G98
G28 U0 W0
M5
T1010 (RADIAL LIVE END MILL D12)
M154 (SPINDLE AS C AXIS)
G28 H0
G0 X70. Z-20. C45.
G0 Y-30.
G0 X54. (END FACE AT X = 27, BESIDE THE BAR)
G0 Y30. (ACROSS THE CORNER AT RAPID)
G0 X70.
M155
G28 U0 W0
G28 V0
M30
%
