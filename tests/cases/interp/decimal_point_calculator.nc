(decimal_point = calculator: X100 is 100 mm)
G21 G18
G0 X100 Z50
G0 X200 Z100
G0 X100
G0 Z-10 (inside the stock length, above its diameter: a misread X would be a rapid into the bar)
M30
