(test-case: machine=generic-slant-bed-tube modes=step,exact)
(A boring bar opens the tube's 20 mm bore to 24 mm for 20 mm and rapids toward the axis and past)
(it: its edge, leaning 4.8 degrees, first scrapes the wedge it left on the step: rapid_scrape.)
(Then, in the same rapid, the bar and the insert's back hit the far wall of the bore: crashes.)
G21 G18 G99 G97 S800 M3
T0303
G0 X24. Z2.
G1 Z-20. F0.1
G0 X-12.
M30
