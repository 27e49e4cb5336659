; G71 type II (block P names X and Z) with a pocket: not modelled yet, an unsupported error at the
; cycle's line, and the profile blocks are not run as plain moves (execution resumes after Q)
G21 G18 G99 G97 S800 M3
T0101
G0 X50 Z3
G71 U1 R0.5
G71 P10 Q50 U0.4 W0.1 F0.25
N10 G0 X30 Z3
N20 G1 Z-10 F0.1
N30 X20 Z-15
N40 Z-20
N50 X52
G0 X60
M30
