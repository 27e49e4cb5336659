(test-case: modes=step,exact)
(A G83 deeper than the drill is long: at Z-68 the drill's holder [70 mm behind the tip] reaches the bar's face [program Z2] on the peck from Z-58 to Z-78, and again on the peck after it [pecks of 20 from the R point Z2, R-8. from the initial level Z10 as the Fanuc machine reads it: -18, -38, -58, -78, -85]: two crashes at the cycle's line 7, in both modes)
G21 G99 G97 S800 M3
T0606
G28 U0 W0
G0 X0 Z10
G83 Z-85 R-8. Q20000 F0.1
G80 G0 Z50
M30
