; postprocesor: BP_234_010
; stroj: VMC 500
; program vytvoril: 
; vytvoreno: 22.01.2021 v 4:57:30
; nazev projektu: 
; nazev NC programu: FEELER DRILLING
; polotovar (XxYxZ): 
; pohyb nastroje (XxYxZ): (10.;90.) x (10.;50.) x (-20.;50.)
; nastroj (typ a prumer): VICE NEZ JEDEN NASTROJ!!!
; vypocitany cas: 0 hod 1 min 48 sek
; =====================================================
 :
N10  T2 M6
N20  M3 S1000
N30  M8
N40  G0 X10. Y10. Z50.
; """""""""""""  ZACATEK CYKLU  """"""""""""""
[$CYCLE_PARAMS(2)GAGE_HT_MM] = 2.0
[$CYCLE_PARAMS(2)G82_DWELL] = 0.0
[$CYCLE_PARAMS(2)G82_FEED_FAC] = 100.0
[$CYCLE_PARAMS(2)G82_FIN_DPTH] = 0.0
N50 G82 X10. Y10. Z10.0 R0.0 F200.0
; **************************************************************************
N60  X30.
[$CYCLE_PARAMS(2)GAGE_HT_MM] = 2.0
[$CYCLE_PARAMS(2)G82_DWELL] = 0.0
[$CYCLE_PARAMS(2)G82_FEED_FAC] = 100.0
[$CYCLE_PARAMS(2)G82_FIN_DPTH] = 0.0
N70 G82 X50. Y10. Z10.0 R-5.0 F200.0
; **************************************************************************
N80 G80
; """""""""""""  Konec cyklu  """"""""""""""
N90  G0 Z50.
; """""""""""""  ZACATEK CYKLU  """"""""""""""
[$CYCLE_PARAMS(2)GAGE_HT_MM] = 2.0
[$CYCLE_PARAMS(2)G82_DWELL] = 0.5
[$CYCLE_PARAMS(2)G82_FEED_FAC] = 100.0
[$CYCLE_PARAMS(2)G82_FIN_DPTH] = 0.0
N100 G82 X10. Y30. Z10.0 R0.0 F200.0
; **************************************************************************
N110  X30.
N120 G80
; """""""""""""  Konec cyklu  """"""""""""""
; """""""""""""  ZACATEK CYKLU  """"""""""""""
[$CYCLE_PARAMS(2)GAGE_HT_MM] = 2.0
[$CYCLE_PARAMS(2)G83_RELIEF] = 1.0
N130 G83 X10. Y50. Z20.0 R0.0 F150.0 J13 K4.0
; **************************************************************************
N140  X30.
N150 G80
; """""""""""""  Konec cyklu  """"""""""""""
; """""""""""""  ZACATEK CYKLU  """"""""""""""
[$CYCLE_PARAMS(2)GAGE_HT_MM] = 2.0
[$CYCLE_PARAMS(2)G83_RET_DIST] = 1.0
N160 G83 X50. Y50. Z20.0 R0.0 F150.0 J11 K3.0
; **************************************************************************
N170 G80
; """""""""""""  Konec cyklu  """"""""""""""
N180  G0 Z50.
; T3 TAP M10X1.5
N190  T3 M6
N200  M3 S500 M8
N210  G0 X70. Y10. Z50.
; """""""""""""  ZACATEK CYKLU  """"""""""""""
[$CYCLE_PARAMS(2)GAGE_HT_MM] = 5.0
[$CYCLE_PARAMS(2)G84_DWELL] = 0.0
N220 G84 X70. Y10. Z15.0 R0.0 F750.0 J1
; **************************************************************************
N230  Y30.
N240 G80
; """""""""""""  Konec cyklu  """"""""""""""
; """""""""""""  ZACATEK CYKLU  """"""""""""""
[$CYCLE_PARAMS(2)GAGE_HT_MM] = 5.0
[$CYCLE_PARAMS(2)G84_DWELL] = 0.2
N250 G84.1 X70. Y50. Z15.0 R0.0J1 K0.0 P1
; **************************************************************************
N260 G80
; """""""""""""  Konec cyklu  """"""""""""""
N270  G0 Z50.
; T4 TAP M10X1.5 LH
N280  T4 M6
N290  M4 S400 M8
N300  G0 X90. Y10. Z50.
; """""""""""""  ZACATEK CYKLU  """"""""""""""
[$CYCLE_PARAMS(2)GAGE_HT_MM] = 5.0
[$CYCLE_PARAMS(2)G84_DWELL] = 0.0
N310 G84 X90. Y10. Z12.0 R0.0 F600.0 J1
; **************************************************************************
N320 G80
; """""""""""""  Konec cyklu  """"""""""""""
; """""""""""""  ZACATEK CYKLU  """"""""""""""
[$CYCLE_PARAMS(2)GAGE_HT_MM] = 5.0
N330 G84.1 X90. Y30. Z12.0 R0.0J1 K0.0 P1
; **************************************************************************
N340 G80
; """""""""""""  Konec cyklu  """"""""""""""
N350  G0 Z50.
N360  M2
