(after a pass to 44 mm, a rapid to 43 mm drives the insert 0.5 mm into the stock that is left)
%
G21 G18 G40 G97 G99
G28 U0 W0
T0101
G96 S200 M3
G50 S3000
G0 X54. Z2.
X44.
G1 Z-30. F0.25
G0 X43. (0.5 MM INTO THE REMAINING STOCK)
G0 X54.
G28 U0 W0
M30
%
