(test-case: modes=step,exact)
(T04 grooves a pocket to X30 from Z-40 to Z-10, leaving a 50 mm collar from Z-10 to the bar end.)
(T01 then faces the pocket's chuck-side wall toward the axis, tip at Z-40.5, from X54 to X30. Its)
(holder spans 8 .. 33 mm above the tip, so up to Z-7.5: 2.5 mm over the collar, where the insert,)
(at most 14 mm above the tip, never reaches. The holder's bottom edge runs from x +5 at 8 mm up to)
(+8 at 33 mm: at Z-10, 30.5 mm up, it is tip + 7.7, so it meets the collar's 50 mm diameter at tip)
(r 17.3, X34.6, before the facing cut reaches X30. Depth at the end: min of radial 25 - 22.7 = 2.3)
(and axial 2.5: 2.3 mm.)
%
G21 G18 G40 G97 G99
G28 U0 W0
T0404
G97 S900 M3
G0 X54. Z-40.
G1 X30. F0.05
G0 X54.
Z-37.
G1 X30.
G0 X54.
Z-34.
G1 X30.
G0 X54.
Z-31.
G1 X30.
G0 X54.
Z-28.
G1 X30.
G0 X54.
Z-25.
G1 X30.
G0 X54.
Z-22.
G1 X30.
G0 X54.
Z-19.
G1 X30.
G0 X54.
Z-16.
G1 X30.
G0 X54.
Z-13.
G1 X30.
G0 X54.
G28 U0 W0
T0101
G96 S200 M3
G50 S3000
G0 X54. Z-40.5
G1 X30. F0.15
G0 X54.
G28 U0 W0
M30
%
