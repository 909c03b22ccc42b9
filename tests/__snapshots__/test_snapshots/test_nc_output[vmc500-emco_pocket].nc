; postprocesor: BP_234_010
; stroj: VMC 500
; program vytvoril: 
; vytvoreno: 22.01.2021 v 4:57:30
; nazev projektu: 
; nazev NC programu: 
; polotovar (XxYxZ): 
; pohyb nastroje (XxYxZ): (10.;70.) x (10.;55.) x (-15.;50.)
; nastroj (typ a prumer): VICE NEZ JEDEN NASTROJ!!!
; vypocitany cas: 0 hod 2 min 15 sek
; =====================================================
 :
; EMCO Concept Mill 105: a pocket and four holes, plain FreeCAD G-code
; Path.toGCode form: one command a line, feeds in mm/s, I J relative to the start
; T1: D10 end mill
N10  T1 M6
N20  M3 S2500
N30  M8
; Pocket_Shape: helical ramp, then the pocket
N40  G0 Z20.
N50  G0 X30. Y20.
N60  G0 Z3.
N70  G1 Z1. F100.0
N80  G17 G2 X40. Y20. Z0.25 I5. J0. F200.0
N90  G2 X30. Y20. Z-0.5 I-5. J0.
N100  G2 X40. Y20. Z-1.25 I5. J0.
N110  G2 X30. Y20. Z-2. I-5. J0.
N120  G2 X30. Y20. I5. J0.
N130  G1 X25. F300.0
N140  G1 Y10.
N150  G1 X55.
N160  G3 X60. Y15. I0. J5.
N170  G1 Y45.
N180  G3 X55. Y50. I-5. J0.
N190  G1 X25.
N200  G1 Y10.
N210  G4 F0.5
N220  G0 Z20.
; T2: D5 drill
N230  T2 M6
N240  M3 S1800
; Drilling: FreeCAD 0.19 writes G80 after every hole
; """""""""""""  ZACATEK CYKLU  """"""""""""""
[$CYCLE_PARAMS(2)GAGE_HT_MM] = 0.0
[$CYCLE_PARAMS(2)G82_DWELL] = 0.0
[$CYCLE_PARAMS(2)G82_FEED_FAC] = 100.0
[$CYCLE_PARAMS(2)G82_FIN_DPTH] = 0.0
N250 G82 X10. Y10. Z11.0 R3.0 F150.0
; **************************************************************************
N260 G80
; """""""""""""  Konec cyklu  """"""""""""""
N270  G0 Z20.
; """""""""""""  ZACATEK CYKLU  """"""""""""""
[$CYCLE_PARAMS(2)GAGE_HT_MM] = 0.0
[$CYCLE_PARAMS(2)G82_DWELL] = 0.0
[$CYCLE_PARAMS(2)G82_FEED_FAC] = 100.0
[$CYCLE_PARAMS(2)G82_FIN_DPTH] = 0.0
N280 G82 X70. Y10. Z11.0 R3.0 F150.0
; **************************************************************************
N290 G80
; """""""""""""  Konec cyklu  """"""""""""""
N300  G0 Z20.
; Peck drilling: holes of one cycle without G80 between them, return to the initial level
; """""""""""""  ZACATEK CYKLU  """"""""""""""
[$CYCLE_PARAMS(2)GAGE_HT_MM] = 0.0
[$CYCLE_PARAMS(2)G83_RELIEF] = 1.0
N310 G83 X70. Y50. Z18.0 R3.0 F120.0 J13 K3.0
; **************************************************************************
N320  X10.
N330  X40. Y55.
N340 G80
; """""""""""""  Konec cyklu  """"""""""""""
N350  G0 Z50.
N360  M2
