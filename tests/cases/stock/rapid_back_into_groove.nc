(a groove is cut, the tool leaves, and later rapids back down into the groove it cut: clean)
%
G21 G18 G40 G97 G99
G28 U0 W0
T0404
G97 S900 M3
G0 X54. Z-20.
G1 X40. F0.05
G0 X54.
Z10.
Z-20.
X41. (RAPID BACK INTO THE GROOVE)
X54.
G28 U0 W0
M30
%
