(Fanuc U/W increments, U a diameter; G28 U0 W0 returns home through the current point; T0303 indexes)
G21 G18 G99 G97 S500 M3
G0 X100 Z50
G0 U-20 W-10
G1 U10 W-5 F0.2
G0 X150
G28 U0 W0
T0202
G0 X100 Z50
G28 U0
M30
