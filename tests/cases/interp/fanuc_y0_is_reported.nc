(A Fanuc 2-axis lathe has no Y address: Y0 is reported once, as unsupported, and ignored)
G21 G18 G99
T0101
G0 X100 Y0 Z5
G0 X90 Y0 Z5
M30
