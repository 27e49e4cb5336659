(test-case: machine=fold-test modes=step,exact)
(Station 2's long holder block stands 30 degrees out of the working plane. With the turret)
(reference point 40 mm from the axis, the block's plane passes 90 mm from the spindle axis at)
(a point inside the block, whose ends stand 106 and 110.5 mm out: the block reaches 5 mm past)
(the jaw face into the 100 mm chuck body. Its section once lost that point: a clear move.)
O0001
G0 X40 Z20
M30
