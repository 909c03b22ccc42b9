; postprocesor: BP_234_010
; stroj: VMC 500
; program vytvoril: 
; vytvoreno: 22.01.2021 v 4:57:30
; nazev projektu: 
; nazev NC programu: 
; polotovar (XxYxZ): 
; pohyb nastroje (XxYxZ): (10.;55.) x (-4.375;40.) x (-2.;15.)
; nastroj (typ a prumer):  0.
; vypocitany cas: 0 hod 0 min 21 sek
; =====================================================
 :
; Exported by FreeCAD
; Post Processor: linuxcnc_post
; Output Time:2026-11-23 11:29:04.840954
; begin preamble
; begin operation: G54
; machine units: mm/min
; finish operation: G54
; begin operation: TC: Endmill 6mm
; machine units: mm/min
; TC: Endmill 6mm
N10  T1 M6
N20  M3 S5000
; finish operation: TC: Endmill 6mm
; begin operation: Pocket
; machine units: mm/min
; Pocket
N30  G0 Z15. M9
N40  G0 X10. Y10.
N50  G0 Z5.
N60  G1 Z-2. F300.0
N70  G1 X50. F600.0
N80  G17 G3 X55. Y15. I0. J5.
N90  G1 Y35.
N100  G3 X50. Y40. I-5. J0.
N110  G1 X10.
N120  G1 Y10.
N130  G0 Z5.
N140  G0 X20. Y-4.375
N150  G1 Z-1. F300.0
N160  G2 X20. Y4.375 I0. J4.375 F600.0
N170  G2 X20. Y-4.375 I0. J-4.375
N180  G1 X30.125
N190  G0 Z15.
; finish operation: Pocket
; begin postamble
N200  M2
