O1
N10( SEZNAM NASTROJU)
N20( T1 )
N10 G0 G17 G40 G80 G90
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
(******************************)
N30 G91 G30 G0 Z0.
N40 G91 G30 G0 X0. Y0.
N50 T1
N60 M6
(******************************)
N70 G54 G17 G90 G0 G94
N80 S5000 M3
(finish operation: TC: Endmill 6mm)
(begin operation: Pocket)
(machine units: mm/min)
(Pocket)
N90 G43 H1 D1 Z15.
N100 G0 X10. Y10.
N110 Z5.
N120 G1 Z-2. F300
N130 X50. F600
N140 G3 X55. Y15. I0. J5.
N150 G1 Y35.
N160 G3 X50. Y40. I-5. J0.
N170 G1 X10.
N180 Y10.
N190 G0 Z5.
N200 X20. Y-4.375
N210 G1 Z-1. F300
N220 G2 X20. Y4.375 I0. J4.375 F600
N230 G2 X20. Y-4.375 I0. J-4.375
N240 G1 X30.125
N250 G0 Z15.
(finish operation: Pocket)
(begin postamble)
N260 M5
N270 G91 G30 G0 Z0.
N280 G91 G30 G0 X0. Y0.
N290 M30
