%
O0001
(T1)
N10 G0 G17 G21 G40 G49 G80 G90 G94
(Exported by FreeCAD)
(Post Processor: linuxcnc_post)
(Output Time:2026-11-23 11:29:04.840954)
(begin preamble)
(begin operation: G54)
(machine units: mm/min)
(finish operation: G54)
(begin operation: TC: Endmill 6mm)
(machine units: mm/min)
(TC: Endmill 6mm)
N20 M5
N30 G91 G28 Z0.
N40 T1 M6
N50 G54 G90 G17 G94
N60 S5000 M3
(finish operation: TC: Endmill 6mm)
(begin operation: Pocket)
(machine units: mm/min)
(Pocket)
N70 G0 G43 H1 Z15.
N80 X10. Y10.
N90 Z5.
N100 G1 Z-2. F300.
N110 X50. F600.
N120 G3 X55. Y15. I0. J5.
N130 G1 Y35.
N140 G3 X50. Y40. I-5. J0.
N150 G1 X10.
N160 Y10.
N170 G0 Z5.
N180 X20. Y-4.375
N190 G1 Z-1. F300.
N200 G2 X20. Y4.375 I0. J4.375 F600.
N210 G2 X20. Y-4.375 I0. J-4.375
N220 G1 X30.125
N230 G0 Z15.
(finish operation: Pocket)
(begin postamble)
N240 M5
N250 G91 G28 Z0.
N260 G28 X0. Y0.
N270 G90
N280 M30
%
