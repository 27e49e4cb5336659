(test-case: machine=haas-style-tailstock)
(T0808: station 8 holds no tool in the machine file. The feed at line 7 would drive T01's holder into the bar; it is not checked as T01, and not at all: where the turret is depends on T08's unknown offsets. T0101 brings the check back: line 11 drives T01's holder into the bar. T0909: no such station)
G18 G21 G99
T0101
G97 S500 M3
T0808
G0 X20 Z2
G1 Z-30 F0.2
G0 X200 Z200
T0101
G0 X20 Z2
G1 Z-30 F0.2
G0 X200 Z200
T0909
G0 X20 Z2
G1 Z-30 F0.2
M30
