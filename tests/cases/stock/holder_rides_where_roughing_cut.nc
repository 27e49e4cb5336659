(two roughing passes, then a pass whose holder rides 3 mm below the raw bar surface:)
(clean only because the holder rides where the first passes cut)
%
G21 G18 G40 G97 G99
G28 U0 W0
T0101
G96 S200 M3
G50 S3000
G0 X54. Z2.
X42.
G1 Z-30. F0.25
U2. W1.
G0 Z2.
X36.
G1 Z-30.
U2. W1.
G0 Z2.
X34.
G1 Z-30. (THE HOLDER'S UNDERSIDE IS AT X44: BELOW THE RAW 50, ABOVE THE 36 ALREADY CUT)
U2. W1.
G0 Z2.
G28 U0 W0
M30
%
