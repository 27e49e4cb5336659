(test-case: modes=step,exact)
(Two moves out of travel in a row are two over-travels; a move that starts out of travel and)
(comes back in is none.)
G21 G18
T0101
G0 X500. Z200.
G0 X700. Z300.
G0 X700. Z250.
G0 X54. Z144.
M30
