G21 G17 G90 G94 G40 G49
G54
(Exported by FreeCAD)
(Post Processor: grbl_MIHO_post)
(Output Time:2021-05-03 18:40:18.753540)
(begin preamble)
(begin operation: Fixture)
(Path: Fixture)
(finish operation: Fixture)
(begin operation: Profile)
(Path: Profile)
(inactive operation)
(finish operation: Profile)
(begin operation: TC: 3mm_endmill)
(Path: TC: 3mm_endmill)
(TC: 3mm_endmill)
(begin toolchange)
(M6 T1.0)
S9000 M3
(finish operation: TC: 3mm_endmill)
(begin operation: Drilling)
(Path: Drilling)
(Drilling)
(Begin Drilling)
G0 Z6
(MIHOG99)
(G83 X15.000 Y4.000 Z-3.000 F30.00 Q1.000 R2.000)
G0 X15 Y4
G1 Z1 F30
G0 Z2
G1 Z0
G0 Z2
G1 Z-1
G0 Z2
G1 Z-2
G0 Z2
G1 Z-3
G0 Z2
(G80)
G0 Z4
(G83 X35.000 Y4.000 Z-3.000 F30.00 Q1.000 R2.000)
G0 X35
G1 Z1
G0 Z2
G1 Z0
G0 Z2
G1 Z-1
G0 Z2
G1 Z-2
G0 Z2
G1 Z-3
G0 Z2
(G80)
G0 Z4
(G83 X55.000 Y4.000 Z-3.000 F30.00 Q1.000 R2.000)
G0 X55
G1 Z1
G0 Z2
G1 Z0
G0 Z2
G1 Z-1
G0 Z2
G1 Z-2
G0 Z2
G1 Z-3
G0 Z2
(G80)
G0 Z4
(G83 X90.000 Y4.000 Z-3.000 F30.00 Q1.000 R2.000)
G0 X90
G1 Z1
G0 Z2
G1 Z0
G0 Z2
G1 Z-1
G0 Z2
G1 Z-2
G0 Z2
G1 Z-3
G0 Z2
(G80)
G0 Z4
(G83 X125.000 Y4.000 Z-3.000 F30.00 Q1.000 R2.000)
G0 X125
G1 Z1
G0 Z2
G1 Z0
G0 Z2
G1 Z-1
G0 Z2
G1 Z-2
G0 Z2
G1 Z-3
G0 Z2
(G80)
G0 Z4
(G83 X125.000 Y96.000 Z-3.000 F30.00 Q1.000 R2.000)
G0 Y96
G1 Z1
G0 Z2
G1 Z0
G0 Z2
G1 Z-1
G0 Z2
G1 Z-2
G0 Z2
G1 Z-3
G0 Z2
(G80)
G0 Z4
(G83 X90.000 Y96.000 Z-3.000 F30.00 Q1.000 R2.000)
G0 X90
G1 Z1
G0 Z2
G1 Z0
G0 Z2
G1 Z-1
G0 Z2
G1 Z-2
G0 Z2
G1 Z-3
G0 Z2
(G80)
G0 Z4
(G83 X55.000 Y96.000 Z-3.000 F30.00 Q1.000 R2.000)
G0 X55
G1 Z1
G0 Z2
G1 Z0
G0 Z2
G1 Z-1
G0 Z2
G1 Z-2
G0 Z2
G1 Z-3
G0 Z2
(G80)
G0 Z4
(G83 X35.000 Y96.000 Z-3.000 F30.00 Q1.000 R2.000)
G0 X35
G1 Z1
G0 Z2
G1 Z0
G0 Z2
G1 Z-1
G0 Z2
G1 Z-2
G0 Z2
G1 Z-3
G0 Z2
(G80)
G0 Z4
(G83 X15.000 Y96.000 Z-3.000 F30.00 Q1.000 R2.000)
G0 X15
G1 Z1
G0 Z2
G1 Z0
G0 Z2
G1 Z-1
G0 Z2
G1 Z-2
G0 Z2
G1 Z-3
G0 Z2
(G80)
G0 Z4
G0 Z6
(finish operation: Drilling)
(begin operation: Helix)
(Path: Helix)
(inactive operation)
(finish operation: Helix)
(begin postamble)
M5
G0 Z6
M30
