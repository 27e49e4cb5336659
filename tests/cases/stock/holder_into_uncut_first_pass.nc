(a first pass 15 mm deep: the insert is 14 mm high, so the holder meets the ring of bar above it)
%
G21 G18 G40 G97 G99
G28 U0 W0
T0101
G96 S200 M3
G50 S3000
G0 X54. Z2.
X20.
G1 Z-20. F0.25 (TOO DEEP FOR THIS TOOL)
G0 X54.
G28 U0 W0
M30
%
