(Exported by FreeCAD)
(Post Processor: linuxcnc_post)
(Output Time:2021-01-22 04:57:30)
(begin preamble)
G17 G54 G40 G49 G80 G90
G21
(begin operation: Tap M10)
(machine units: mm/min)
M5
M6 T4 
G43 H4 
M3 S500 
G0 X20.000 Y15.000 Z30.000 
G0 Z3.000 
G33.1 Z-15.000 K1.5000 
G0 Z15.000 
G0 X80.000 
G0 Z3.000 
G33.1 Z-15.000 K1.5000 
G0 Z15.000 
G0 Y45.000 
G0 Z3.000 
G33.1 Z-15.000 K1.5000 
G0 Z15.000 
G0 X50.000 Y30.000 
G0 Z8.000 
G33.1 Z-10.000 K1.5000 
G0 Z15.000 
G0 Z50.000 
(finish operation: Tap M10)
(begin operation: Tap M8 left-hand)
(machine units: mm/min)
M5
M6 T5 
G43 H5 
M4 S400 
G0 X20.000 Y45.000 Z30.000 
G0 Z3.000 
G33.1 Z-12.000 K1.2500 
G0 X35.000 
G0 Z3.000 
G33.1 Z-12.000 K1.2500 
G0 Z50.000 
M5 
(finish operation: Tap M8 left-hand)
(begin postamble)
M05
G17 G54 G90 G80 G40
M2
