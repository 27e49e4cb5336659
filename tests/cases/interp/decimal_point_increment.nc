(test-case: machine=generic-slant-bed-increment)
(decimal_point = increment: X100000 is 100 mm, X100. is 100 mm, Z100 is 0.1 mm)
G21 G18
G0 X100000 Z50.
G0 X100. Z50000
G0 Z100
G0 X100000
G0 Z-10000 (Z-10: above the bar; read as mm it would be far past the Z travel)
M30
