(Exported by FreeCAD)
(Post Processor: linuxcnc_post)
(Output Time:2021-01-22 04:57:30)
(begin preamble)
G17 G54 G40 G49 G80 G90
G21
M5
M6 T2 
G43 H2 
M3 S4000 
(begin operation: SLOT FACE A0)
(machine units: mm/min)
G0 X5.000 Y0.000 Z30.000 A0.000 
G0 Y0.000 Z22.000 
G1 Y0.000 Z19.000 F150.000 
G1 X35.000 F400.000 
G0 Y0.000 Z30.000 
(finish operation: SLOT FACE A0)
(begin operation: SLOT FACE A90)
(machine units: mm/min)
G0 X5.000 A90.000 
G0 Z22.000 
G1 Z19.000 F150.000 
G1 X35.000 F400.000 
G0 Z30.000 
(finish operation: SLOT FACE A90)
(begin operation: SLOT FACE A180)
(machine units: mm/min)
G0 X5.000 A180.000 
G0 Z22.000 
G1 Z19.000 F150.000 
G1 X35.000 F400.000 
G0 Z30.000 
(finish operation: SLOT FACE A180)
(begin operation: SLOT FACE A270)
(machine units: mm/min)
G0 X5.000 A270.000 
G0 Z22.000 
G1 Z19.000 F150.000 
G1 X35.000 F400.000 
G0 Z30.000 
(finish operation: SLOT FACE A270)
(begin postamble)
M05
G17 G54 G90 G80 G40
M2
