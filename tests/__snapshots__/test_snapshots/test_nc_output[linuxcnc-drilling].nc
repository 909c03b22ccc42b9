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
(begin operation: TC: Drill 5mm)
(machine units: mm/min)
(TC: Drill 5mm) 
M5
M6 T3 
G43 H3 
M3 S2000 
(finish operation: TC: Drill 5mm)
(begin operation: Drilling)
(machine units: mm/min)
(Drilling) 
(Begin Drilling) 
G0 Z10.000 
G90 
G99 
G0 X10.000 Y10.000 
G0 Z3.000 
G81 X10.000 Y10.000 Z-8.000 F90.000 R1.000 
G0 X40.000 Y10.000 
G0 Z3.000 
G81 X40.000 Y10.000 Z-8.000 F90.000 R1.000 
G0 X40.000 Y30.000 
G0 Z3.000 
G81 X40.000 Y30.000 Z-8.000 F90.000 R1.000 
G80 
G0 Z5.000 
G0 Z10.000 
(finish operation: Drilling)
(begin operation: Drilling001)
(machine units: mm/min)
(Drilling001) 
(Begin Drilling) 
G0 Z10.000 
G90 
G98 
G0 X10.000 Y10.000 
G0 Z3.000 
G82 X10.000 Y10.000 Z-8.000 F90.000 R1.000 P0.500 
G0 X40.000 Y10.000 
G0 Z3.000 
G82 X40.000 Y10.000 Z-8.000 F90.000 R1.000 P0.500 
G0 X40.000 Y30.000 
G0 Z3.000 
G82 X40.000 Y30.000 Z-8.000 F90.000 R1.000 P0.500 
G80 
G0 Z5.000 
G0 Z10.000 
(finish operation: Drilling001)
(begin operation: Drilling002)
(machine units: mm/min)
(Drilling002) 
(Begin Drilling) 
G0 Z10.000 
G90 
G98 
G0 X10.000 Y10.000 
G0 Z3.000 
G83 X10.000 Y10.000 Z-8.000 F90.000 Q2.500 R1.000 
G0 X40.000 Y10.000 
G0 Z3.000 
G83 X40.000 Y10.000 Z-8.000 F90.000 Q2.500 R1.000 
G0 X40.000 Y30.000 
G0 Z3.000 
G83 X40.000 Y30.000 Z-8.000 F90.000 Q2.500 R1.000 
G80 
G0 Z5.000 
G0 Z10.000 
(finish operation: Drilling002)
(begin postamble)
M05
G17 G54 G90 G80 G40
M2
