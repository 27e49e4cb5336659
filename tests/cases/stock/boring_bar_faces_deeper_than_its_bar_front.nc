(test-case: modes=step,exact)
(T03 faces the bar end toward the axis, 3 mm deep: the tip at Z-1, machine z 77; the uncut bar end)
(is at Z2, z 80. The bar's front face sits 2 mm behind the cutting corner, at z 79, 1 mm inside the)
(bar end, and reaches 15 mm below the tip in x, where the insert reaches only about 6.1 mm. Feeding)
(from X90, the bar front's low corner meets the bar's 50 mm diameter at tip r 40, X80, while the)
(insert is still 8.9 mm outside it. The insert then cuts the whole band z 77 .. 80 down to the axis,)
(so the stock after the move is clear: only the stock at the instant shows the bar plowing into the)
(end face ahead of the insert. Depth min of radial 8.9 and axial 1 mm: 1 mm.)
%
G21 G18 G40 G97 G99
G28 U0 W0
T0303
G97 S1200 M3
G0 X90. Z-1.
G1 X0. F0.15
G0 Z5.
G28 U0 W0
M30
%
