(Fanuc macro B: G65 arguments in specification I and II, a new level of locals per call, L repeats with the same arguments)
O0001
G21 G18 G99 G97 S500 M3
G0 X200 Z100
#1 = 500
(specification I: each variable gets its own number; the macro moves to Z100 + #n for each one set)
G65 P9010 A1 B2 C3 I4 J5 K6 D7 E8 F9 H11 M13 Q17 R18 S19 T20 U21 V22 W23 X24 Y25 Z26
(specification II: A B C, then I J K in sets: I J K I J K I K J gives #4 … #9, #10, #12, #14)
G65 P9010 A1 B2 C3 I4 J5 K6 I7 J8 K9 I10 K12 J14
G0 Z#1 (the caller's #1 is back: 500)
G65 P9012 L3 A5 (three calls, each starting from A5: Z60 three times)
M30
O9010
#33 = 1
WHILE [#33 LE 26] DO1
IF [#[#33] EQ #0] GOTO 10
G0 Z[#[#33] + 100]
N10 #33 = #33 + 1
END1
M99
O9012
#1 = #1 + 1
G0 Z[#1 * 10]
M99
