G21 G18
G0 X100 Z50 (café in a comment is fine)
G0 X100 é Z50
M30
