(test-case: machine=generic-slant-bed-tube modes=step,exact)
(The same bore, the bar brought off the wall into the old bore and out along Z: the scrape of)
(the wedge on the step, nothing else.)
G21 G18 G99 G97 S800 M3
T0303
G0 X24. Z2.
G1 Z-20. F0.1
G0 X20.
G0 Z2.
M30
