; postprocesor: BP_234_010
; stroj: VMC 500
; program vytvoril: 
; vytvoreno: 22.01.2021 v 4:57:30
; nazev projektu: boring: G85 (feed out) and G89 (a dwell, then feed out), two holes each
; nazev NC programu: BORING
; polotovar (XxYxZ): 
; pohyb nastroje (XxYxZ): (0.;60.) x (0.;50.) x (-15.;50.)
; nastroj (typ a prumer): boring bar 20.
; vypocitany cas: 0 hod 2 min 26 sek
; =====================================================
 :
N10  T3 M6
N20  M3 S800
N30  G0 X0. Y0. Z30. M9
N40  G0 X20. Y20.
N50  G0 Z3.
N60  G1 Z-15. F60.0
N70  G1 Z3.
N80  G0 Z30.
N90  G0 X60.
N100  G0 Z3.
N110  G1 Z-15.
N120  G1 Z3.
N130  G0 Z30.
N140 G80
; """""""""""""  Konec cyklu  """"""""""""""
N150  G0 X20. Y50.
N160  G0 Z3.
N170  G1 Z-15.
N180  G4 F0.5
N190  G1 Z3.
N200  G0 Z30.
N210  G0 X60.
N220  G0 Z3.
N230  G1 Z-15.
N240  G4 F0.5
N250  G1 Z3.
N260  G0 Z30.
N270 G80
; """""""""""""  Konec cyklu  """"""""""""""
N280  G0 Z50.
N290  M2
