(Exported by FreeCAD)
(Post Processor: linuxcnc_post)
(Output Time:2021-01-22 04:57:30)
(begin preamble)
G17 G54 G40 G49 G80 G90
G21
(begin operation: G54)
(machine units: mm/min)
G54 
G0 Z15.000 
(finish operation: G54)
(begin operation: TC: Endmill 6mm)
(machine units: mm/min)
(TC: Endmill 6mm) 
M5
M6 T1 
G43 H1 
M3 S5000 
(finish operation: TC: Endmill 6mm)
(begin operation: Pocket)
(machine units: mm/min)
(Pocket) 
G0 Z15.000 
G0 X10.000 Y10.000 
G0 Z5.000 
G1 X10.000 Y10.000 Z-2.000 F300.000 
G1 X50.000 Y10.000 Z-2.000 F600.000 
G3 X55.000 Y15.000 Z-2.000 I0.000 J5.000 F600.000 
G1 X55.000 Y35.000 Z-2.000 F600.000 
G3 X50.000 Y40.000 Z-2.000 I-5.000 J0.000 F600.000 
G1 X10.000 Y40.000 Z-2.000 F600.000 
G1 X10.000 Y10.000 Z-2.000 F600.000 
G0 Z5.000 
G0 X20.000 Y-4.375 
G1 X20.000 Y-4.375 Z-1.000 F300.000 
G2 X20.000 Y4.375 Z-1.000 I0.000 J4.375 F600.000 
G2 X20.000 Y-4.375 Z-1.000 I0.000 J-4.375 F600.000 
G1 X30.125 Y-4.375 Z-1.000 F600.000 
G0 Z15.000 
(finish operation: Pocket)
(begin postamble)
M05
G17 G54 G90 G80 G40
M2
