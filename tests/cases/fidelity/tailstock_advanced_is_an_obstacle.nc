(test-case: machine=haas-style-tailstock modes=step,exact)
(M21 advances the tailstock: the same rapid as in tailstock_retracted_is_no_obstacle hits it; after M22 it passes again)
G18 G21 G99
T0101
M21
G0 X20 Z170
G0 X200 Z300
M22
G0 X20 Z170
G0 X200 Z300
M30
