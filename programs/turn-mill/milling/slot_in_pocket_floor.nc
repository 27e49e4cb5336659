%
O2203 (A SLOT IN A POCKET FLOOR, THE COLLET NUT OVER THE POCKET)
(T10, the radial end mill Ø12, mills a pocket 8 mm deep across the Ø50 bar at C0 from Z-20. to)
(Z-60.; T12, an end mill Ø10 only 10 mm out of a Ø30 collet nut, then mills a slot 3 mm deeper)
(along Z in the pocket's floor: the nut reaches 1 mm inside the round bar it was.)
(The nut spans Z-51. to Z-21. at the end of the slot: inside the pocket, clear of its shoulders.)
G21 G18 G40 G97 G98
G28 U0 W0
M5
T1010 (RADIAL LIVE END MILL D12)
M154 (SPINDLE AS C AXIS)
G28 H0
M133 P3000 (LIVE TOOL ON)
G0 X70. Z-26. C0.
G0 Y-40.
G1 X34. F300.
G1 Y40. F200.
G0 X70.
G0 Y-40. Z-32.
G1 X34. F300.
G1 Y40. F200.
G0 X70.
G0 Y-40. Z-38.
G1 X34. F300.
G1 Y40. F200.
G0 X70.
G0 Y-40. Z-44.
G1 X34. F300.
G1 Y40. F200.
G0 X70.
G0 Y-40. Z-50.
G1 X34. F300.
G1 Y40. F200.
G0 X70.
G0 Y-40. Z-54.
G1 X34. F300.
G1 Y40. F200.
G0 X70.
G0 Y0.
M135 (LIVE TOOL OFF)
G28 U0
T1212 (RADIAL LIVE END MILL D10, D30 COLLET NUT)
M133 P3000 (LIVE TOOL ON)
G0 X70. Z-40.
G1 X28. F100. (3 MM INTO THE POCKET FLOOR: THE NUT 1 MM BELOW THE BAR'S SURFACE)
G1 Z-36. F150. (THE SLOT: THE NUT STAYS BETWEEN THE SHOULDERS)
G0 X70.
M135 (LIVE TOOL OFF)
M155
G28 U0 W0
G28 V0
M30
%
