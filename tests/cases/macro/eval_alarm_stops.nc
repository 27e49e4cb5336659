(Fanuc macro B: a value the control cannot compute is an alarm: a program finding at its line, and the program stops there, loop or not)
O0001
G21 G18 G99 G97 S500 M3
G0 X200 Z100
#1 = 0
WHILE [#1 LT 1000] DO1
G0 Z[50 + #1]
#2 = 10 / #3 (#3 is vacant: 0, a division by zero)
#1 = #1 + 1
END1
G0 Z20 (never reached)
M30
