(test-case: machine=generic-slant-bed-increment)
(Fanuc macro B on a machine whose plain numbers without a point are increments: a variable's value in an address is in mm, never scaled; X200 here is 0.2 mm)
O0001
G21 G18 G99 G97 S500 M3
G0 X200. Z100.
#1 = 150
#2 = 50
G0 X#1 Z#2 (X150 mm as a diameter, Z50 mm)
G0 Z[#2 + 10] (Z60 mm)
G0 Z30000 (a plain number without a point: 30 mm)
M30
