; postprocesor: BP_234_010
; stroj: VMC 500
; program vytvoril: 
; vytvoreno: 22.01.2021 v 4:57:30
; nazev projektu: program_stop and optional_stop: M1 with the spindle running, M0 after M5 M9
; nazev NC programu: STOPS
; polotovar (XxYxZ): 
; pohyb nastroje (XxYxZ): (0.;20.) x (0.;0.) x (-3.;20.)
; nastroj (typ a prumer):  10.
; vypocitany cas: 0 hod 0 min 25 sek
; =====================================================
 :
N10  T1 M6
N20  M3 S2000
N30  M8
N40  G0 X0. Y0. Z20.
N50  G0 Z5.
N60  G1 Z-1. F200.0
N70  G1 X20.
N80  G0 Z20.
N90  M1
N100  G0 Z5.
N110  G1 Z-2.
N120  G1 X0.
N130  G0 Z20.
N140  M5
N150  M9
N160  M0
N170  M3 S2000
N180  G0 Z5.
N190  G1 Z-3.
N200  G1 X20.
N210  G0 Z20.
N220  M2
