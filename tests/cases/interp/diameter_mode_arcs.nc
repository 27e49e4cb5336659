(X is a diameter, I is a radius: a quarter circle of radius 10 from X100 Z50 to X120 Z40)
G21 G18 G99 G97 S500 M3
G0 X100 Z50
G2 X120 Z40 I10 K0 F0.2
(the same with U/W increments: U is a diameter too)
G0 X100 Z50
G2 U20 W-10 I10 K0
G0 U10 W5
M30
