(two G codes of one modal group, a word twice, an unknown code, a word nothing uses)
G21 G18
G0 G1 X100 Z50 F100
G0 X100 X90 Z50
G1.5 X100 Z50
G0 X100 Z50 I5
G0 X100 Z50 J1
G17
G19 G0 X100
G18
M30
