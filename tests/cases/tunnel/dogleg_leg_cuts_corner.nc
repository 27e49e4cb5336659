(test-case: machine=jaw-test-dogleg modes=step,exact)
(Z rapids twice as fast as X: the Z leg ends first and drops the insert past the jaw's corner; the straight line would clear it)
G21 G18 G98
G0 X30 Z12
G0 X45 Z-2
G0 X100
M30
