(Fanuc macro B: an endless GOTO loop ends at the execution budget with a program finding at the looping line)
O0001
G0 X200 Z100
N10 #1 = #1 + 1
GOTO 10
