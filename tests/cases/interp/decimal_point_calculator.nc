(decimal_point = calculator: X100 is 100 mm)
G21 G18
G0 X100 Z50
G0 X200 Z100
M30
