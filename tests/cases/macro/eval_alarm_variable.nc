(Fanuc macro B: a variable that does not exist is an alarm: the program stops there)
O0001
G21 G18 G99 G97 S500 M3
G0 X200 Z100
#2 = #50 (no such variable)
G0 Z20 (never reached)
M30
