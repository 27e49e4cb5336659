%
O2212 (A RAPID OVER A FLAT SIDE OF A 40 MM SQUARE BAR)
(The job beside this program holds a 40 x 40 square bar standing at C0: its top flat is x = 20,)
(its corners 28.284 mm from the axis. T10, the radial end mill D12, rapids across it in Y at)
(Z-20 with its end face at X42, x = 21: 1 mm above the flat, well inside the corners' radius.)
(A round bar of the corners' diameter, the block's revolved envelope, would put the rapid)
(7.284 mm into the stock; the block leaves the mill 1 mm clear. Clean.)
G21 G18 G40 G97 G98
G28 U0 W0
M5
T1010 (RADIAL LIVE END MILL D12)
M154 (SPINDLE AS C AXIS)
G28 H0
G0 X70. Z-20. C0.
G0 Y-30.
G0 X42. (1 MM ABOVE THE FLAT, BESIDE THE BAR)
G0 Y30. (RAPID ACROSS THE FLAT SIDE)
G0 X70.
M155
G28 U0 W0
G28 V0
M30
%
