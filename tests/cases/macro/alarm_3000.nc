(Fanuc macro B: #3000 raises an alarm: a program finding with its message at its line, and the program stops)
O0001
G21 G18 G99 G97 S500 M3
G0 X200 Z100
#1 = 5
IF [#1 GE 10] GOTO 10
#3000 = 1 (STOCK TOO SHORT)
N10 G0 Z50 (never reached)
M30
