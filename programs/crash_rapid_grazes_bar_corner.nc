(test-case: modes=step,exact)
%
O1109 (A RAPID GRAZES THE CORNER OF THE RAW BAR: 19 UM DEEP FOR A FRACTION OF A MILLISECOND)
(No 1 ms sample lands in it, but the gaps proven at the samples around it do not cover the way)
(between them: both modes measure it exactly, rapid_into_stock at N70. See the README's table.)
N10 G21 G18 G40 G97 G99
N20 G28 U0 W0
N30 T0101
N40 G97 S800 M3
N50 G0 X48. Z3.67
N60 Z2.67
N70 X52. Z0.67 (DIAGONAL PAST THE CORNER OF THE 50 MM BAR AT Z2)
N80 G0 X60.
N90 G28 U0 W0
N100 M30
%
