(test-case: machine=jaw-test modes=step,exact)
(a rapid along X+ Z- slides the insert's corner past the jaw's corner: 25 um deep, 0.07 mm of travel, 0.4 ms)
G21 G18 G98
G0 X39 Z0.95
G0 X41 Z-1.05
G0 X100
M30
