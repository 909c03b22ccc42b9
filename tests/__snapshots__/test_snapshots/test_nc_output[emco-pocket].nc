N10 ;Export souboru postproceosrem: emco_post
N20 ;Cas exportu: 22.01.2021 04:57:30
N30 ; Uvodni cast programu
N40 G17 G40
N50 G54 G90
N60 ;Exported by FreeCAD
N70 ;Post Processor: linuxcnc_post
N80 ;Output Time:2026-11-23 11:29:04.840954
N90 ;begin preamble
N100 ;begin operation: G54
N110 ;machine units: mm/min
N120 ;finish operation: G54
N130 ;begin operation: TC: Endmill 6mm
N140 ;machine units: mm/min
N150 ;TC: Endmill 6mm
N160 M5
N170 ;Vymena nastroje
N180 M6 T1
N190 M3 S5000
N200 ;finish operation: TC: Endmill 6mm
N210 ;begin operation: Pocket
N220 ;machine units: mm/min
N230 ;Pocket
N240 G0 Z15.000
N250 X10.000 Y10.000
N260 Z5.000
N270 G1 Z-2.000 F300
N280 X50.000 F600
N290 G3 X55.000 Y15.000 I0.000 J5.000
N300 G1 Y35.000
N310 G3 X50.000 Y40.000 I-5.000 J0.000
N320 G1 X10.000
N330 Y10.000
N340 G0 Z5.000
N350 X20.000 Y-4.375
N360 G1 Z-1.000 F300
N370 G2 Y4.375 I0.000 J4.375 F600
N380 Y-4.375 I0.000 J-4.375
N390 G1 X30.125
N400 G0 Z15.000
N410 ;finish operation: Pocket
N420 ;begin postamble
N430 M5
N440 M30
