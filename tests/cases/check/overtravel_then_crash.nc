(test-case: modes=step,exact)
(Issue 26: a move out of travel, one back in, then a rapid through the bar into the chuck. The)
(over-travel puts nothing inside anything: the crash at line 7 is errors of its own.)
G21 G18
T0101
G0 X500. Z200.
G0 X54. Z144.
G0 X38. Z-200.
M30
