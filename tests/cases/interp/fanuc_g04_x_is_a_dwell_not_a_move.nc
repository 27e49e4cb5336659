(Fanuc G04: X, U or P is the dwell time, never an axis word; the block does not move)
G18 G21 G40 G97 G99
T0101
S800 M03
G00 X50. Z5.
G01 Z-1. F0.2
G04 X0.5
G04 U1.5
G04 P500
G04 X.25
G00 X100. Z100.
M30
