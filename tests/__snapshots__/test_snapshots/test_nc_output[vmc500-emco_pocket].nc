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
N250  G0 X25. Y10. Z20.
; """""""""""""  ZACATEK CYKLU  """"""""""""""
[$CYCLE_PARAMS(2)GAGE_HT_MM] = 0.0
[$CYCLE_PARAMS(2)G82_DWELL] = 0.0
[$CYCLE_PARAMS(2)G82_FEED_FAC] = 100.0
[$CYCLE_PARAMS(2)G82_FIN_DPTH] = 0.0
N260 G82 X10. Y10. Z11.0 R3.0 F150.0
; **************************************************************************
N270 G80
; """""""""""""  Konec cyklu  """"""""""""""
N280  G0 Z20.
; """""""""""""  ZACATEK CYKLU  """"""""""""""
[$CYCLE_PARAMS(2)GAGE_HT_MM] = 0.0
[$CYCLE_PARAMS(2)G82_DWELL] = 0.0
[$CYCLE_PARAMS(2)G82_FEED_FAC] = 100.0
[$CYCLE_PARAMS(2)G82_FIN_DPTH] = 0.0
N290 G82 X70. Y10. Z11.0 R3.0 F150.0
; **************************************************************************
N300 G80
; """""""""""""  Konec cyklu  """"""""""""""
N310  G0 Z20.
; Peck drilling: holes of one cycle without G80 between them, return to the initial level
; """""""""""""  ZACATEK CYKLU  """"""""""""""
N320  G0 Y50.
N330  G0 Z3.
N340  G1 Z0. F120.0
N350  G0 Z3.
N360  G0 Z0.
N370  G1 Z-3.
N380  G0 Z3.
N390  G0 Z-3.
N400  G1 Z-6.
N410  G0 Z3.
N420  G0 Z-6.
N430  G1 Z-9.
N440  G0 Z3.
N450  G0 Z-9.
N460  G1 Z-12.
N470  G0 Z3.
N480  G0 Z-12.
N490  G1 Z-15.
N500  G0 Z20.
N510  G0 X10. Z20.
N520  G0 Z3.
N530  G1 Z0.
N540  G0 Z3.
N550  G0 Z0.
N560  G1 Z-3.
N570  G0 Z3.
N580  G0 Z-3.
N590  G1 Z-6.
N600  G0 Z3.
N610  G0 Z-6.
N620  G1 Z-9.
N630  G0 Z3.
N640  G0 Z-9.
N650  G1 Z-12.
N660  G0 Z3.
N670  G0 Z-12.
N680  G1 Z-15.
N690  G0 Z20.
N700  G0 X40. Y55.
N710  G0 Z3.
N720  G1 Z0.
N730  G0 Z3.
N740  G0 Z0.
N750  G1 Z-3.
N760  G0 Z3.
N770  G0 Z-3.
N780  G1 Z-6.
N790  G0 Z3.
N800  G0 Z-6.
N810  G1 Z-9.
N820  G0 Z3.
N830  G0 Z-9.
N840  G1 Z-12.
N850  G0 Z3.
N860  G0 Z-12.
N870  G1 Z-15.
N880  G0 Z20.
N890 G80
; """""""""""""  Konec cyklu  """"""""""""""
N900  G0 Z50.
N910  M2
