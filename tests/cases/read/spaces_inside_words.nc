(spaces and tabs inside words and numbers are ignored, as in rs274ngc)
G21 G18 G99
G 0 X1 0 0 Z 5	0
G0 X 9 0 . 5
g0 x100 z50 ; lower case is the same
M30
