(test-case: clearance=0.5)
%
O1108 (NEAR MISS: THE INSERT STOPS 0.3 MM ABOVE A JAW FACE)
(Clean with the default clearance 0; with --clearance 0.5 a near_miss warning at N60.)
N10 G21 G18 G40 G97 G99
N20 G28 U0 W0
N30 T0101
N40 G97 S800 M3
N50 G0 X88. Z5.
N60 G1 Z-77.7 F0.2 (THE JAW FACES ARE AT Z-78)
N70 G0 X120.
N80 G28 U0 W0
N90 M30
%
