(test-case: kin=turnmill)
(Fanuc turn-mill: C needs C-axis mode (M154); V and H are incremental Y and C; G28 H0 homes C only; live tool M133 P is the speed; M155 leaves C-axis mode)
G21 G18 G99
T0101
G97 S800 M3
G0 X60 Z5
C30
M154
G0 C30 Y4
G0 H15 V-2
G98 G1 C90 F720
M133 P2500
G1 Z-10 F100
M135
G28 H0
G28 V0
M155
G0 X80 Z10 C10
M30
