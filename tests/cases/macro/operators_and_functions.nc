(Fanuc macro B: every operator and function; each result is the Z of the next rapid, hand-computed in the comment)
O0001
G21 G18 G99 G97 S500 M3
G0 X200 Z100
#1 = 7
#2 = 2
#10 = #1 + #2 (9)
G0 Z#10
#10 = #1 - #2 (5)
G0 Z#10
#10 = #1 * #2 (14)
G0 Z#10
#10 = #1 / #2 (3.5)
G0 Z#10
#10 = #1 MOD #2 (1)
G0 Z#10
#10 = -7 MOD 3 + 10 (the remainder keeps the dividend's sign: -1 + 10 = 9)
G0 Z#10
#10 = 12 AND 10 (1100 AND 1010 = 1000: 8)
G0 Z#10
#10 = 12 OR 10 (1110: 14)
G0 Z#10
#10 = 12 XOR 10 (0110: 6)
G0 Z#10
#10 = [#1 EQ 7] + 10 (11)
G0 Z#10
#10 = [#1 NE 7] + 20 (20)
G0 Z#10
#10 = [#1 GT 7] + 30 (30)
G0 Z#10
#10 = [#1 GE 7] + 40 (41)
G0 Z#10
#10 = [#1 LT 8] + 50 (51)
G0 Z#10
#10 = [#1 LE 6] + 60 (60)
G0 Z#10
#10 = SIN[30] * 100 (50)
G0 Z#10
#10 = COS[60] * 100 (50)
G0 Z#10
#10 = TAN[45] * 100 (100)
G0 Z#10
#10 = ASIN[0.5] (30)
G0 Z#10
#10 = ASIN[-0.5] (-30 shown as 330)
G0 Z#10
#10 = ACOS[-0.5] (120)
G0 Z#10
#10 = ATAN[1]/[1] (45)
G0 Z#10
#10 = ATAN[-1,-1] (third quadrant: 225)
G0 Z#10
#10 = SQRT[144] (12)
G0 Z#10
#10 = ABS[-17.5] (17.5)
G0 Z#10
#10 = ROUND[2.5] (3)
G0 Z#10
#10 = ROUND[-2.5] + 10 (away from zero: -3 + 10 = 7)
G0 Z#10
#10 = FIX[-1.2] + 10 (toward zero: -1 + 10 = 9)
G0 Z#10
#10 = FUP[-1.2] + 10 (away from zero: -2 + 10 = 8)
G0 Z#10
#10 = FIX[1.7] (1)
G0 Z#10
#10 = FUP[1.2] (2)
G0 Z#10
#10 = LN[EXP[2]] (2)
G0 Z#10
#10 = BIN[18] (18 = 0x12, BCD digits 1 and 2: 12)
G0 Z#10
#10 = BCD[12] (digits 1 and 2 as 0x12: 18)
G0 Z#10
#10 = POW[2,5] (32)
G0 Z#10
#10 = 1 + 2 * 3 (7)
G0 Z#10
#10 = 2 + 12 AND 10 (AND binds as *: 2 + 8 = 10)
G0 Z#10
#10 = [1 + 2] * 3 (9)
G0 Z#10
#10 = 1 EQ 1 + 0 (+ binds tighter than EQ: 1)
G0 Z#10
M30
