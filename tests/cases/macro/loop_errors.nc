(Fanuc macro B: the loops the manual forbids are program findings where they are; the program stops at the first)
O0001
G0 X200 Z100
#1 = 0
WHILE [#1 LT 1] DO1
WHILE [#1 LT 1] DO2
END1 (overlaps DO2)
END2
G0 Z50
DO1
DO2
DO3
DO1 (nested in DO1)
END3
END2
END1
END3 (no DO3 open)
DO2 (never closed)
M30
