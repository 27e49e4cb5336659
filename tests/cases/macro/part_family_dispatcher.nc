(A shop's part-family dispatcher: the family in common variable #500, bar diameter in #501, a wait loop on #502, parts per run in #503; only family 2 runs)
O0001
#500 = 2 (family, set on the control's variable page)
#501 = 40. (bar diameter)
#502 = 0 (bar-feeder wait passes)
#503 = 3 (parts per run)
G21 G18 G99 G97 S800 M3
T0101
G0 X200 Z100
N1 IF [#500 EQ 1] GOTO 100
IF [#500 EQ 2] GOTO 200
IF [#500 EQ 3] GOTO 300
#3000 = 1 (NO PART FAMILY SELECTED)
N100 (family 1: a short shaft)
G0 X[#501 + 2] Z2
G1 Z-20 F0.2
GOTO 900
N200 (family 2: wait for the bar feeder, then turn the diameter down 4 mm)
WHILE [#502 LT 3] DO1
G4 X0.5
#502 = #502 + 1
END1
G0 X[#501 - 4] Z2
G1 Z-30 F0.2
G1 X[#501 + 1] (up the shoulder)
G0 X[#501 + 10] Z2
GOTO 900
N300 (family 3: a face only)
G0 X[#501 + 2] Z0
G1 X-1 F0.15
N900 #3901 = #3901 + 1
IF [#3901 LT #503] GOTO 1
G0 X200 Z100
M30
