(Fanuc macro B: position, modal and offset system variables a lathe program reads, and the parts counter)
O0001
G21 G18 G99 G97 S500 M3
T0101
G0 X200 Z100
#1 = #5001 (X, a diameter: 200)
#2 = #5002 (Z: 100)
G1 X[#1 - 10] Z[#2 - 10] F0.25 (X190 Z90)
#3 = #4001 (G01: 1)
#4 = #4005 (G99: 99)
#5 = #4109 (F: 0.25)
#6 = #4119 (S: 500)
#7 = #4120 (T: 101)
#8 = #4113 (M: 3)
#9 = #4006 (G21: 21)
#10 = #4002 (G97: 97)
#11 = #5041 (work X: 190)
G0 Z[#3 + #4 + #6 / 100] (1 + 99 + 5 = 105)
G0 Z[#5 * 100 + #7] (25 + 101 = 126)
G0 Z[#8 + #9 + #10] (3 + 21 + 97 = 121)
G0 Z[#11] (190)
#3901 = #3901 + 1 (parts count: 1)
G0 Z[#3901 + 140] (141)
#12 = #2001 (X wear of offset 1: the machine file has none, 0)
G0 Z[#12 + 150] (150)
M30
