(EMCO Concept Mill 105: a pocket and four holes, plain FreeCAD G-code)
(Path.toGCode form: one command a line, feeds in mm/s, I J relative to the start)
G90
G17
G54
(T1: D10 end mill)
M6 T1
M3 S2500
M8
(Pocket_Shape: helical ramp, then the pocket)
G0 Z20
G0 X30 Y20
G0 Z3
G1 F1.6667 Z1
G2 F3.3333 I5 J0 X40 Y20 Z0.25
G2 F3.3333 I-5 J0 X30 Y20 Z-0.5
G2 F3.3333 I5 J0 X40 Y20 Z-1.25
G2 F3.3333 I-5 J0 X30 Y20 Z-2
G2 F3.3333 I5 J0 X30 Y20 Z-2
G1 F5 X25 Y20 Z-2
G1 F5 X25 Y10 Z-2
G1 F5 X55 Y10 Z-2
G3 F5 I0 J5 X60 Y15 Z-2
G1 F5 X60 Y45 Z-2
G3 F5 I-5 J0 X55 Y50 Z-2
G1 F5 X25 Y50 Z-2
G1 F5 X25 Y10 Z-2
G4 P0.5
G0 Z20
M9
(T2: D5 drill)
M6 T2
M3 S1800
M8
(Drilling: FreeCAD 0.19 writes G80 after every hole)
G0 Z20
G90
G99
G81 F2.5 R3 X10 Y10 Z-8
G80
G0 Z20
G81 F2.5 R3 X70 Y10 Z-8
G80
G0 Z20
(Peck drilling: holes of one cycle without G80 between them, return to the initial level)
G98
G83 F2 Q3 R3 X70 Y50 Z-15
G83 X10 Y50
G83 X40 Y55
G80
G0 Z50
M9
M5
