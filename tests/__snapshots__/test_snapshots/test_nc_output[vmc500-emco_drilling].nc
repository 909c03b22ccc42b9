; postprocesor: BP_234_010
; stroj: VMC 500
; program vytvoril: postdsl example
; vytvoreno: 22.01.2021 v 4:57:30
; nazev projektu: plate_80x60
; nazev NC programu: EMCO_DRILL
; polotovar (XxYxZ): 
; pohyb nastroje (XxYxZ): (10.;70.) x (10.;50.) x (-25.;100.)
; nastroj (typ a prumer): VICE NEZ JEDEN NASTROJ!!!
; vypocitany cas: 0 hod 3 min 59 sek
; =====================================================
 :
N10  T2 M6
N20  M3 S3000
N30  M8
N40  G0 X10. Y10. Z20.
; """""""""""""  ZACATEK CYKLU  """"""""""""""
[$CYCLE_PARAMS(2)GAGE_HT_MM] = 2.0
[$CYCLE_PARAMS(2)G82_DWELL] = 0.0
[$CYCLE_PARAMS(2)G82_FEED_FAC] = 100.0
[$CYCLE_PARAMS(2)G82_FIN_DPTH] = 0.0
N50 G82 X10. Y10. Z2.0 R0.0 F150.0
; **************************************************************************
N60  X70.
N70  Y50.
N80  X10.
N90  X40. Y30.
N100 G80
; """""""""""""  Konec cyklu  """"""""""""""
N110  T3 M6
N120  M3 S1500 M8
N130  G0 X10. Y10. Z20.
; """""""""""""  ZACATEK CYKLU  """"""""""""""
[$CYCLE_PARAMS(2)GAGE_HT_MM] = 2.0
[$CYCLE_PARAMS(2)G83_RELIEF] = 1.0
N140 G83 X10. Y10. Z25.0 R0.0 F120.0 J13 K5.0
; **************************************************************************
N150  X70.
N160  Y50.
N170  X10.
N180 G80
; """""""""""""  Konec cyklu  """"""""""""""
; """""""""""""  ZACATEK CYKLU  """"""""""""""
[$CYCLE_PARAMS(2)GAGE_HT_MM] = 1.5
[$CYCLE_PARAMS(2)G83_RET_DIST] = 1.0
N190 G83 X40. Y30. Z18.0 R0.0 F100.0 J11 K3.0
; **************************************************************************
N200  Y45.
N210 G80
; """""""""""""  Konec cyklu  """"""""""""""
N220  T4 M6
N230  M3 S800 M8
N240  G0 Y30. Z20.
; """""""""""""  ZACATEK CYKLU  """"""""""""""
[$CYCLE_PARAMS(2)GAGE_HT_MM] = 2.0
[$CYCLE_PARAMS(2)G82_DWELL] = 0.8
[$CYCLE_PARAMS(2)G82_FEED_FAC] = 100.0
[$CYCLE_PARAMS(2)G82_FIN_DPTH] = 0.0
N250 G82 X40. Y30. Z6.0 R0.0 F60.0
; **************************************************************************
N260  Y45.
N270 G80
; """""""""""""  Konec cyklu  """"""""""""""
N280  G0 Z50.
N290  T5 M6
N300  M3 S400
N310  G0 X10. Y10. Z20. M9
; """""""""""""  ZACATEK CYKLU  """"""""""""""
[$CYCLE_PARAMS(2)GAGE_HT_MM] = 3.0
[$CYCLE_PARAMS(2)G84_DWELL] = 0.3
N320 G84 X10. Y10. Z18.0 R0.0 F600.0 J1
; **************************************************************************
N330  X70.
N340 G80
; """""""""""""  Konec cyklu  """"""""""""""
N350  T6 M6
N360  M4 S400
N370  G0 Y50. Z20.
; """""""""""""  ZACATEK CYKLU  """"""""""""""
[$CYCLE_PARAMS(2)GAGE_HT_MM] = 3.0
[$CYCLE_PARAMS(2)G84_DWELL] = 0.0
N380 G84 X70. Y50. Z18.0 R0.0 F600.0 J1
; **************************************************************************
N390  X10.
N400 G80
; """""""""""""  Konec cyklu  """"""""""""""
N410  T7 M6
N420  M3 S500
N430  G0 X40. Y30. Z20.
; """""""""""""  ZACATEK CYKLU  """"""""""""""
[$CYCLE_PARAMS(2)GAGE_HT_MM] = 3.0
N440 G84.1 X40. Y30. Z15.0 R0.0 F750.0J1 K0.0 P1
; **************************************************************************
N450  Y45.
N460 G80
; """""""""""""  Konec cyklu  """"""""""""""
N470  T8 M6
N480  M4 S600
N490  G0 X25. Y20. Z20.
; """""""""""""  ZACATEK CYKLU  """"""""""""""
[$CYCLE_PARAMS(2)GAGE_HT_MM] = 2.0
N500 G84.1 X25. Y20. Z12.0 R0.0J1 K4.0 P1
; **************************************************************************
N510  X55.
N520  Y40.
N530 G80
; """""""""""""  Konec cyklu  """"""""""""""
N540  G0 Z100.
N550  M2
