(test-case: machine=generic-slant-bed)
( Fanuc G32 reads its lead from F, and F is one modal register for feed and lead: a G32 without )
( F cuts at the F in force, and a G1 after a thread without F feeds at the lead. A K in a G32 )
( block is the LinuxCNC G33 lead word, not a Fanuc one: a warning at the K, the thread cut at )
( the modal F, as the Fanuc 0i-TD and Haas lathe manuals describe G32; an NX post writes )
( G32 Z3.46 K.05 - in the air )
G21 G18 G99
T0101
G97 S300 M3
G0 X120. Z30.
G1 X118. F0.2
G32 Z10. K1.5
G0 X122.
Z30.
X118.
G32 Z10. F1.5
G0 X122.
Z30.
X118.
G32 Z10.
G0 X122.
G1 Z40.
M30
