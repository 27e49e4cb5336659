(Fanuc macro B: IF … GOTO backward and forward, GOTO with a computed target, IF … THEN, and the search order for a repeated N number: ahead first, then from the top)
O0001
G21 G18 G99 G97 S500 M3
G0 X200 Z100
#1 = 1
N10 G0 Z[10 * #1] (10, 20, 30)
#1 = #1 + 1
IF [#1 LE 3] GOTO 10
IF [#1 EQ 4] GOTO 30
N20 G0 Z999 (skipped)
N30 G0 Z50
GOTO 40
G0 Z998 (skipped)
N40 IF [#1 GT 0] THEN #2 = 60
IF [#1 LT 0] THEN #2 = 999
G0 Z#2 (60)
#3 = 70
GOTO #3
G0 Z997 (skipped)
N70 G0 Z70
N80 G0 Z81 (the first N80, reached by falling through)
#4 = 0
N90 #4 = #4 + 1
IF [#4 EQ 2] GOTO 100
GOTO 80 (the N80 ahead: Z82)
N80 G0 Z82
GOTO 90 (none ahead: from the top)
N100 G0 Z83
M30
