(Fanuc G80 cancels the drilling cycle only: the G0 it ran over stays in force, so X100 Z100)
(after it is a rapid, as on the control; the G1 face pass later keeps its own mode)
(R5 from Z10: Z5 read as Haas does, Z15 as Fanuc does; clear of the face either way)
G21 G18 G99
T0606
G97 S800 M3
G0 X0 Z10.
G83 Z-20. R5. Q5000 F0.1
G80
X100. Z100.
T0101
G0 X55. Z2.
G1 X-1.6 F0.2
G0 Z5.
X100. Z100.
M30
