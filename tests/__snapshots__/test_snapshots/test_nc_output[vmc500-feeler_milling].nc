; postprocesor: BP_234_010
; stroj: VMC 500
; program vytvoril: 
; vytvoreno: 22.01.2021 v 4:57:30
; nazev projektu: 
; nazev NC programu: FEELER MILLING
; polotovar (XxYxZ): 
; pohyb nastroje (XxYxZ): (-10.;80.) x (-10.;40.) x (-4.;50.)
; nastroj (typ a prumer):  10.
; vypocitany cas: 0 hod 1 min 25 sek
; =====================================================
 :
; T1 END MILL D10
N10  T1 M6
N20  M3 S2500
N30  M8
N40  G0 X-10. Y-10. Z50.
N50  G0 Z2.
N60  G1 Z-2. F200.0
N70  G1 X40. F500.0
N80  G17 G3 X50. Y0. I0. J10.
N90  G1 Y30.
N100  G2 X60. Y40. I10. J0.
N110  G1 X80.
N120  G2 X80. Y20. I0. J-10.
N130  G1 X70.
N140  G3 X70. Y20. I-10. J0.
N150  G2 X60. Y10. I-10. J0.
N160  G0 Z50.
; HELIX
N170  G0 X40. Y15.
N180  G0 Z2.
N190  G1 Z0. F150.0
N200  G3 X40. Y15. Z-3. I-10. J0.
N210  G2 X20. Y15. Z-4. I-10. J0.
N220  G2 X30. Y25. I10. J0.
N230  G1 Z0.
N240  G18 G3 X35. Z5. I5. K0.
N250  G19 G2 Y30. Z10. J5. K0.
N260  G0 Z50.
N270  M2
