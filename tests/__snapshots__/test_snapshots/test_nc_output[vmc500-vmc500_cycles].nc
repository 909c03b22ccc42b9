; postprocesor: BP_234_010
; stroj: VMC 500
; program vytvoril: Thinkpad
; vytvoreno: 22.01.2021 v 4:57:30
; nazev projektu: BP_Vsechny_cykly
; nazev NC programu: BP_Vagner
; polotovar (XxYxZ): 9.99999999999999 x 9.99999999999999 x 50
; pohyb nastroje (XxYxZ): (40.;100.) x (20.;20.) x (16.996;150.)
; nastroj (typ a prumer): VICE NEZ JEDEN NASTROJ!!!
; vypocitany cas: 0 hod 3 min 58 sek
; =====================================================
 :
N10  T1 M6
N20  M3 S500 M8
N30  G0 X40. Y20. Z80.
; """""""""""""  ZACATEK CYKLU  """"""""""""""
[$CYCLE_PARAMS(2)GAGE_HT_MM] = 5.0
[$CYCLE_PARAMS(2)G82_DWELL] = 0.5
[$CYCLE_PARAMS(2)G82_FEED_FAC] = 100.0
[$CYCLE_PARAMS(2)G82_FIN_DPTH] = 0.0
N40 G82 X40. Y20. Z50.0 R70.0 F200.0
; **************************************************************************
N50  G0 Z80.
N60 G80
; """""""""""""  Konec cyklu  """"""""""""""
; """""""""""""  ZACATEK CYKLU  """"""""""""""
[$CYCLE_PARAMS(2)GAGE_HT_MM] = 5.0
[$CYCLE_PARAMS(2)G83_RELIEF] = 1.0
N70 G83 X40. Y20. Z53.0043 R70.0 F200.0 J13 K10.0
; **************************************************************************
N80 G80
; """""""""""""  Konec cyklu  """"""""""""""
N90  G0 X60.
; """""""""""""  ZACATEK CYKLU  """"""""""""""
[$CYCLE_PARAMS(2)GAGE_HT_MM] = 5.0
[$CYCLE_PARAMS(2)G83_RET_DIST] = 1.0
N100 G83 X60. Y20. Z53.0043 R70.0 F200.0 J11 K10.0
; **************************************************************************
N110 G80
; """""""""""""  Konec cyklu  """"""""""""""
N120  G0 Z100.
N130  G0 X80. M9
N140  G0 Z80.
N150  T2 M6
N160  M3 S200 M8
; """""""""""""  ZACATEK CYKLU  """"""""""""""
[$CYCLE_PARAMS(2)GAGE_HT_MM] = 5.0
[$CYCLE_PARAMS(2)G84_DWELL] = 0.5
N170 G84 X80. Y20. Z35.0 R70.0 F100.0 J1
; **************************************************************************
N180 G80
; """""""""""""  Konec cyklu  """"""""""""""
N190  G0 X100.
; """""""""""""  ZACATEK CYKLU  """"""""""""""
[$CYCLE_PARAMS(2)GAGE_HT_MM] = 5.0
N200 G84.1 X100. Y20. Z35.0 R70.0J1 K10.0 P1
; **************************************************************************
N210 G80
; """""""""""""  Konec cyklu  """"""""""""""
N220  G0 Z150.
N230  M2
