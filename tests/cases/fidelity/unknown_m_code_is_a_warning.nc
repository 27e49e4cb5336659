(M codes the built-in machine's table lacks are warnings that name them; the program is otherwise clean)
G18 G21 G99
T0101
G97 S500 M3
M123
M21
G0 X60 Z5
G1 Z-10 F0.2 M8
G0 X100 Z100 M9
M30
