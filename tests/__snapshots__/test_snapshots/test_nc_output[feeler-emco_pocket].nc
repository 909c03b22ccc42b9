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
N90 G0
N100 G43 H1 D1 Z20.
N110 X30. Y20.
N120 Z3.
N130 G1 Z1. F100
N140 G2 X40. Y20. Z0.25 I5. J0. F200
N150 G2 X30. Y20. Z-0.5 I-5. J0.
N160 G2 X40. Y20. Z-1.25 I5. J0.
N170 G2 X30. Y20. Z-2. I-5. J0.
N180 G2 X30. Y20. I5. J0.
N190 G1 X25. F300
N200 Y10.
N210 X55.
N220 G3 X60. Y15. I0. J5.
N230 G1 Y45.
N240 G3 X55. Y50. I-5. J0.
N250 G1 X25.
N260 Y10.
N270 G4 P500
N280 G0 Z20.
N290 M9
(T2: D5 drill)
(******************************)
N300 G91 G30 G0 Z0.
N310 G91 G30 G0 X0. Y0.
N320 T2
N330 M6
(******************************)
N340 G54 G17 G90 G0 G94
N350 S1800 M3
N360 M8
(Drilling: FreeCAD 0.19 writes G80 after every hole)
N370 G0 X25. Y10.
N380 G43 H2 D2 Z20.
N390 G95 G99 G81 X10. Y10. Z-8. R3. F0.0833
N400 G80 G94
N410 G0 Z20.
N420 G95 G99 G81 X70. Y10. Z-8. R3. F0.0833
N430 G80 G94
N440 G0 Z20.
(Peck drilling: holes of one cycle without G80 between them, return to the initial level)
N450 G95 G98 G83 X70. Y50. Z-15. R3. Q3. F0.0667
N460 X10.
N470 X40. Y55.
N480 G80 G94
N490 G0 Z50.
N500 M9
N510 M5
N520 G91 G30 G0 Z0.
N530 G91 G30 G0 X0. Y0.
N540 M30
