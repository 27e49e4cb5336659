(G76 threading: the Fanuc two-block form with and without a chamfer-out, and the Haas one-block form with taper I)
G21 G99 G97 S500 M3
T0505
G0 X56 Z5
G76 P020060 Q100 R0.05
G76 X46.8 Z-20 R0 P1000 Q400 F2
G76 P011060 Q100 R0
G76 X46.8 Z-20 P1000 Q600 F2
G76 X46.8 Z-20 K1. D0.5 F2 A60 I-0.5
G0 X60 Z20
M30
(Start S = X28 Z5 [radius, program Z]. Thread end E = X23.4 Z-20, height k = P1000 = 1.000 mm, external: the)
(pass at depth t runs at X = 23.4 + [k - t]; one-edge infeed at a = 60: shifted +[k - t]*tan 30 = [k - t]*0.577350 in Z.)
(Each pass: rapid S to the pass start, thread [feed per rev 2] to the end, rapid out in X to X28, rapid to S.)
(line 6: Dd = Q400 = 0.4, Ddmin = Q100 = 0.1, d = 0.05, m = 2: roughing to k - d = 0.95.)
(  0.4*sqrt n: 0.4, 0.565685, 0.692820, 0.8 [increments 0.166, 0.127, 0.107, all >= 0.1],)
(  0.894427 is only 0.094 past 0.8, so 0.8 + 0.1 = 0.9; 0.979796 is 0.08 past 0.9, so 1.0, above 0.95: 0.95;)
(  finishing: 1.0 twice.  k - t and the shift: 0.6/0.346410, 0.434315/0.250752, 0.307180/0.177350,)
(  0.2/0.115470, 0.1/0.057735, 0.05/0.028868, 0/0, 0/0.)
(line 7-8: m = 1, r = 10 [chamfer 1.0 lead = 2 mm], Dd = 0.6: depths 0.6, 0.848528, 1.0 [1.039 > 1.0], finishing 1.0.)
(  with the chamfer the thread stops 2 mm before the end [Z + 2] and leaves at 45 deg: +2 in X, to the end Z.)
(  k - t and shift: 0.4/0.230940, 0.151472/0.087452, 0/0, 0/0.)
(line 9, Haas: K 1.0, D 0.5, A60, P1 [one edge, constant area], no allowance, no finishing pass, taper I-0.5:)
(  depths 0.5, 0.707107, 0.866025, 1.0; k - t and shift: 0.5/0.288675, 0.292893/0.169102, 0.133975/0.077350, 0/0;)
(  the pass starts at X = 23.4 + [k - t] - 0.5.)
