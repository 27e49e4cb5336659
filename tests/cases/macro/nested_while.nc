(Fanuc macro B: WHILE … DO1/DO2/DO3 nested three deep, and DO1 alone left by IF … GOTO)
O0001
G21 G18 G99 G97 S500 M3
G0 X200 Z100
#1 = 0
#4 = 0
WHILE [#1 LT 2] DO1
#2 = 0
WHILE [#2 LT 2] DO2
#3 = 0
WHILE [#3 LT 2] DO3
#4 = #4 + 1
G0 Z[#4 * 10] (10, 20, … 80: eight passes)
#3 = #3 + 1
END3
#2 = #2 + 1
END2
#1 = #1 + 1
END1
G0 Z[#4 + 100] (108)
#5 = 0
DO1
#5 = #5 + 1
IF [#5 GE 3] GOTO 50
G0 Z[200 + #5] (201, 202)
END1
N50 G0 Z300
M30
