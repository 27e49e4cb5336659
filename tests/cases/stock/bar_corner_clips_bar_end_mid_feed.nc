(test-case: modes=step,exact)
(T03 feeds diagonally toward the axis and away from the chuck, from X82 Z-3 to X74 Z1: tip r 41 to)
(37, machine z 75 to 79, r = 41 - 4s, z = 75 + 4s. The insert stays 8.5 mm above the bar's front)
(corner, in the air; the bar's low front corner, tip + -15, +2, clips the uncut bar end's corner,)
(r 25 at z 80. The overlap is the rectangle from tip-15 to r 25 and from tip z + 2 to z 80, so the)
(depth is min of radial 40 - tip r = 4s - 1 and axial 78 - tip z = 3 - 4s: it rises from s 0.25,)
(peaks at s 0.5, X78 Z-1, at exactly 1 mm, and falls to nothing at s 0.75. tests/depth_cases.rs)
%
G21 G18 G40 G97 G99
G28 U0 W0
T0303
G97 S1000 M3
G0 X82. Z-3.
G1 X74. Z1. F0.2
G0 X100.
G28 U0 W0
M30
%
