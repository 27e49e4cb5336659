(Fanuc M98 P… L…, the 0i form M98 Pllllnnnn, M99 Pn returning to a sequence number, and a subprogram sharing its caller's locals)
O0001
G21 G18 G99 G97 S500 M3
G0 X200 Z100
#1 = 0
M98 P1000 L3 (three passes: Z10, Z20, Z30)
M98 P21000 (repeat 2, program 1000: Z40, Z50)
M98 P00011001 (once, returns to N60)
G0 Z999 (skipped)
N60 G0 Z60
M30
O1000
#1 = #1 + 10
G0 Z#1
M99
O1001
G0 Z55
M99 P60
