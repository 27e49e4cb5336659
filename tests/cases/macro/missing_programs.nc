(Fanuc macro B: calls to programs not in the file, GOTO to a missing N number, unsupported system variables)
O0001
G0 X200 Z100
M98 P7777
G65 P8888 A1
#1 = #1000 (an input signal: not modelled)
#1012 = 1 (an output signal: not modelled)
GOTO 1234
M30
