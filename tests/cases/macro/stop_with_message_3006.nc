(Fanuc macro B: #3006 stops with a message: a warning at its line, and the program goes on as if cycle start were pressed; IF … THEN may set several variables)
O0001
G21 G18 G99 G97 S500 M3
G0 X200 Z100
IF [1 EQ 1] THEN #1 = 20 #2 = 30
#3006 = 1 (TURN THE PART OVER)
G0 Z[#1 + #2] (50)
M30
