(The program of fanuc_g83_r_from_the_initial_level.nc on a Haas-style machine [drill_r = "absolute"]: R-2. is the Z of the R plane, so the rapid from the initial level Z3 down to it runs 2 mm into the faced bar [face at Z0]: a rapid into the stock at the cycle line 10) (test-case: machine=haas-style-tailstock)
G21 G99 G97 S800 M3
T0101
G0 X55. Z0.
G1 X-1.6 F0.2
G0 Z3.
X100. Z100.
T0606
G0 X0 Z3.
G83 Z-20. R-2. Q5000 F0.1
G80
G0 Z50.
M30
