(test-case: machine=haas-style-tailstock modes=step,exact)
(the tailstock starts retracted: a rapid through where its centre stands when advanced is clean)
G18 G21 G99
T0101
G0 X20 Z170
G0 X200 Z300
M30
