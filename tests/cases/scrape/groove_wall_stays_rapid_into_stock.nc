(test-case: modes=step,exact)
(A groove plunged at feed, then a rapid along Z: the groove's wall is material the plunge did)
(not cut, the insert's side drives 3 mm into it: rapid_into_stock.)
G21 G18 G99 G97 S800 M3
T0404
G0 X52. Z-10.
G1 X40. F0.1
G0 Z-5.
M30
