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
(begin operation: Arcs)
(machine units: mm/min)
(Arcs) 
G0 Z15.000 
G0 X0.000 Y0.000 
G0 Z2.000 
G1 X0.000 Y0.000 Z0.000 F300.000 
G2 X10.000 Y0.000 Z0.000 I5.000 J0.000 F600.000 
G18 
G2 X15.000 Y0.000 Z5.000 I0.000 K5.000 F600.000 
G3 X10.000 Y0.000 Z0.000 I-5.000 K0.000 F600.000 
G19 
G2 X10.000 Y5.000 Z5.000 J0.000 K5.000 F600.000 
G3 X10.000 Y0.000 Z0.000 J-5.000 K0.000 F600.000 
G17 
G3 X0.000 Y0.000 Z0.000 I-5.000 J0.000 F600.000 
G0 Z15.000 
(finish operation: Arcs)
(begin postamble)
M05
G17 G54 G90 G80 G40
M2
