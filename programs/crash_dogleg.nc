%
O1105 (CRASH ON A DOGLEG RAPID: THE STRAIGHT LINE CLEARS THE SHOULDER, THE BENT PATH DOES NOT)
(On this machine each axis rapids at its own rate: X arrives first and drops the insert into the shoulder.)
(With rapid = "linear" the same program is clean: see tests/cases/check/dogleg_linear.nc.)
(Expected: rapid_into_stock at N200.)
N10 G21 G18 G40 G97 G99 (STOCK DIA 50)
N20 G28 U0 W0
N30 T0101
N40 G50 S3000
N50 G96 S200 M3
N60 G0 X54. Z2.
N70 X46.
N80 G1 Z-30. F0.25
N90 U2. W1.
N100 G0 Z2.
N110 X42.
N120 G1 Z-30.
N130 U2. W1.
N140 G0 Z2.
N150 X40.
N160 G1 Z-30.
N170 X52. (UP THE SHOULDER)
N180 G0 X60. Z-40.
N200 X44. Z-20. (LINEAR: CLEARS THE SHOULDER CORNER BY 1 MM. DOGLEG: X ARRIVES FIRST)
N210 G28 U0 W0
N220 M30
%
