(test-case: modes=step,exact)
(T04 grooves a pocket to X30 from Z-40 to Z-4; T01 then feeds toward +Z from inside it with its)
(holder 1 mm below the bar surface, ahead of the insert: it meets bar the insert has not cut yet)
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
Z-10.
G1 X30.
G0 X54.
Z-7.
G1 X30.
G0 X54.
G28 U0 W0
T0101
G96 S200 M3
G50 S3000
G0 X54. Z-40.
X32.
G1 Z-38. F0.2
G0 X54.
G28 U0 W0
M30
%
