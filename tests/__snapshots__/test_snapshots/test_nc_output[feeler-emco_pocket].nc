O1
N10( SEZNAM NASTROJU)
N20( T1 )
N30( T2 )
N10 G0 G17 G40 G80 G90
(EMCO Concept Mill 105: a pocket and four holes, plain FreeCAD G-code)
(Path.toGCode form: one command a line, feeds in mm/s, I J relative to the start)
(T1: D10 end mill)
(******************************)
N20 G91 G30 G0 Z0.
N30 G91 G30 G0 X0. Y0.
N40 T1
N50 M6
(******************************)
N60 G54 G17 G90 G0 G94
N70 S2500 M3
N80 M8
(Pocket_Shape: helical ramp, then the pocket)
N90 G43 H1 D1 Z20.
N100 G0 X30. Y20.
N110 Z3.
N120 G1 Z1. F100
N130 G2 X40. Y20. Z0.25 I5. J0. F200
N140 G2 X30. Y20. Z-0.5 I-5. J0.
N150 G2 X40. Y20. Z-1.25 I5. J0.
N160 G2 X30. Y20. Z-2. I-5. J0.
N170 G2 X30. Y20. I5. J0.
N180 G1 X25. F300
N190 Y10.
N200 X55.
N210 G3 X60. Y15. I0. J5.
N220 G1 Y45.
N230 G3 X55. Y50. I-5. J0.
N240 G1 X25.
N250 Y10.
N260 G4 P500
N270 G0 Z20.
N280 M9
(T2: D5 drill)
(******************************)
N290 G91 G30 G0 Z0.
N300 G91 G30 G0 X0. Y0.
N310 T2
N320 M6
(******************************)
N330 G54 G17 G90 G0 G94
N340 S1800 M3
N350 M8
(Drilling: FreeCAD 0.19 writes G80 after every hole)
N360 G0 X25. Y10.
N370 G43 H2 D2 Z20.
N380 G95 G99 G81 X10. Y10. Z-8. R3. F0.0833
N390 G80 G94
N400 G0 Z20.
N410 G95 G99 G81 X70. Y10. Z-8. R3. F0.0833
N420 G80 G94
N430 G0 Z20.
(Peck drilling: holes of one cycle without G80 between them, return to the initial level)
N440 G95 G98 G83 X70. Y50. Z-15. R3. Q3. F0.0667
N450 X10.
N460 X40. Y55.
N470 G80 G94
N480 G0 Z50.
N490 M9
N500 M5
N510 G91 G30 G0 Z0.
N520 G91 G30 G0 X0. Y0.
N530 M30
