(test-case: modes=step,exact)
(T04 rapids from X52 Z-1 to X44 Z3.8: tip r 26 to 22, machine z 77 to 81.8. The dogleg moves each)
(axis at its own rate, x 20000 and z 24000 mm/min, and dr : dz = -4 : 4.8 = -5 : 6 is their ratio,)
(so the path is one straight line: r = 26 - 5t, z = 77 + 6t, t from 0 to 0.8. The groover's)
(flat x-minus face at the tip, 3 mm wide in z, sweeps over the uncut bar end's corner, r 25 at)
(z 80. The 0.2 mm nose is set as an imaginary tip: its lowest point is at the programmed z and)
(the face at the programmed r. Depth = min of radial 25 - r = 5t - 1 and axial 80 - z = 3 - 6t:)
(equal at t = 4/11, X48.364 Z1.182: 9/11 = 0.818 mm, mid-move. The column model measures the)
(axial extent in 0.01 mm columns, so within 0.01 of that: 0.82. tests/depth_cases.rs)
%
G21 G18 G40 G97 G99
G28 U0 W0
T0404
G97 S1000 M3
G0 X52. Z-1.
X44. Z3.8
G0 X100.
G28 U0 W0
M30
%
