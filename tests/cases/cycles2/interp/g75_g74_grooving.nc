(G75 OD grooving with pecks [Fanuc two-block form] and G74 face peck drilling [Haas one-block form])
G21 G99 G97 S600 M3
T0404
G0 X54 Z-10
G75 R0.5
G75 X40 Z-16 P3000 Q2500 R0 F0.08
G28 U0 W0
T0606
G0 X0 Z3
G74 Z-12 K5. F0.1
G0 X60 Z20
M30
(line 4: S = X27 Z-10 [radius].  line 5: return amount e = 0.5.)
(line 6: E = X20 Z-16; peck along X P3000 = 3.0 mm, shift along Z Q2500 = 2.5 mm, no relief.)
(  pecks from X27: 24, 21, then the end X20 [7 mm = 3 + 3 + 1]; after each peck but the last a rapid back by e.)
(  grooves at Z -10, -12.5, -15 and the end Z -16 [6 mm = 2.5 + 2.5 + 1].)
(  per groove: [rapid X27 to the groove Z], feed X24, rapid X24.5, feed X21, rapid X21.5, feed X20, rapid out to X27.)
(  at the end a rapid back to S.)
(line 7: home: the turret reference point to [300, 600], the T04 tip [-60, -12.5] there is X240 Z[600 - 12.5 - 78] = 509.5.)
(line 8: index to the drill T06.  line 9: rapid X0 Z3 = S.)
(line 10, Haas form: K5 the Z peck, no X shift [X stays 0], e still 0.5 from line 5:)
(  feed Z-2, rapid Z-1.5, feed Z-7, rapid Z-6.5, feed Z-12 [15 mm = 5 + 5 + 5], rapid out to Z3 = S.)
