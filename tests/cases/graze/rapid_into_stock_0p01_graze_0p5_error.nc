(test-case: modes=step,exact)
(T01 on the built-in machine, bar 50 mm: a rapid that ends 0.01 mm into the diameter is a graze;)
(a later rapid 0.5 mm into it is an error: rapid_into_stock grazes too, by the same rule)
G21 G18 G40 G97 G99
G28 U0 W0
T0101
G97 S800 M3
G0 X60. Z-5.
G0 X49.98
G1 X49.98 Z-10. F0.2
G0 X60.
G0 Z-20.
G0 X49.
G0 X60.
G28 U0 W0
M30
