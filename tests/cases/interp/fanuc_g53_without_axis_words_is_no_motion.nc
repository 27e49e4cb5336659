(A Fanuc G53 block with no axis word, as CAM posts write it before a tool change: a one-shot with nothing to move, no alarm; the turret stays where it is and the next G53 with axes still moves in machine coordinates, here to machine zero, home)
G21 G18 G99 G97 S1200 M3
T0101
G0 X60. Z5.
G1 X48. F0.2
G0 X60.
G53
G53 G0 X0 Z0
T0202
G53
G0 X60. Z5.
M30
