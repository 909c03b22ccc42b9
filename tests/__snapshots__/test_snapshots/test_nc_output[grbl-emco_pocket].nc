G21 G17 G90 G94 G40 G49
G54
(EMCO Concept Mill 105: a pocket and four holes, plain FreeCAD G-code)
(Path.toGCode form: one command a line, feeds in mm/s, I J relative to the start)
(T1: D10 end mill)
G0 Z50
(Change to tool 1, touch off Z, cycle start)
T1 M0
G0 Z50
S2500 M3
M8
(Pocket_Shape: helical ramp, then the pocket)
G0 Z20
G0 X30 Y20
G0 Z3
G1 Z1 F100
G2 X40 Y20 Z0.25 I5 J0 F200
G2 X30 Y20 Z-0.5 I-5 J0
G2 X40 Y20 Z-1.25 I5 J0
G2 X30 Y20 Z-2 I-5 J0
G2 X30 Y20 I5 J0
G1 X25 F300
G1 Y10
G1 X55
G3 X60 Y15 I0 J5
G1 Y45
G3 X55 Y50 I-5 J0
G1 X25
G1 Y10
G4 P0.5
G0 Z20
M9
(T2: D5 drill)
M5
G0 Z50
(Change to tool 2, touch off Z, cycle start)
T2 M0
G0 Z50
S1800 M3
M8
(Drilling: FreeCAD 0.19 writes G80 after every hole)
G0 X25 Y10 Z20
G0 X10
G0 Z3
G1 Z-8 F150
G0 Z3
G0 Z20
G0 X70
G0 Z3
G1 Z-8
G0 Z3
G0 Z20
(Peck drilling: holes of one cycle without G80 between them, return to the initial level)
G0 Y50
G0 Z3
G1 Z0 F120
G0 Z3
G0 Z0
G1 Z-3
G0 Z3
G0 Z-3
G1 Z-6
G0 Z3
G0 Z-6
G1 Z-9
G0 Z3
G0 Z-9
G1 Z-12
G0 Z3
G0 Z-12
G1 Z-15
G0 Z20
G0 X10
G0 Z3
G1 Z0
G0 Z3
G0 Z0
G1 Z-3
G0 Z3
G0 Z-3
G1 Z-6
G0 Z3
G0 Z-6
G1 Z-9
G0 Z3
G0 Z-9
G1 Z-12
G0 Z3
G0 Z-12
G1 Z-15
G0 Z20
G0 X40 Y55
G0 Z3
G1 Z0
G0 Z3
G0 Z0
G1 Z-3
G0 Z3
G0 Z-3
G1 Z-6
G0 Z3
G0 Z-6
G1 Z-9
G0 Z3
G0 Z-9
G1 Z-12
G0 Z3
G0 Z-12
G1 Z-15
G0 Z20
G0 Z50
M9
M5
G0 Z50
M30
