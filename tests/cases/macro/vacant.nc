(Fanuc macro B: vacant variables behave as #0: 0 in arithmetic, told from 0 by EQ and NE, a word whose value is vacant is as if absent)
O0001
G21 G18 G99 G97 S500 M3
G0 X200 Z100
#1 = #0 (stays vacant)
#2 = #1 (vacant copied: vacant)
#3 = #1 + 5 (5)
G0 X150 Z#1 (Z is absent: X only)
G0 Z#3 (5)
IF [#2 EQ #0] GOTO 10
G0 Z999
N10 IF [#2 EQ 0] GOTO 20 (vacant is not 0: not taken)
G0 Z11
N20 #4 = 0
IF [#4 EQ #0] GOTO 30 (0 is not vacant: not taken)
G0 Z12
N30 IF [#2 LT 1] GOTO 40 (vacant is 0 in LT: taken)
G0 Z998
N40 G0 Z[#2 * 3 + 13] (13)
IF [#500 NE #0] GOTO 50 (common variables start vacant)
G0 Z14
N50 IF [#100 NE #0] GOTO 60
G0 Z15
N60 M30
