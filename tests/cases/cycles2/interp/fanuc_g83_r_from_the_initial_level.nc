(A Fanuc G83 on the built-in Fanuc machine [drill_r = "incremental"]: the bar is faced to Z0, then from the initial level Z3 R-2. puts the R point at Z1, 1 mm clear of the face; Q5000 = 5 mm pecks from Z1 to Z-20 [-4, -9, -14, -19, -20], back to Z1, then to the initial level Z3: clean. The same program on a Haas-style machine: haas_g83_same_program_r_absolute.nc)
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
