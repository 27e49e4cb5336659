(Fanuc macro B: G66 calls its macro after each move block until G67; moves inside the macro call nothing)
O0001
G21 G18 G99 G97 S500 M3
G0 X200 Z100
G66 P9020 A5
G0 Z50 (then the macro: X195, back to X200)
G0 Z40 (again)
G67
G0 Z30 (no call)
M30
O9020
G1 U-#1 F0.2
G0 U#1
M99
