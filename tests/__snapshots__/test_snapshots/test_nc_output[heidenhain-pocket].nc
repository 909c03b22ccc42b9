0 BEGIN PGM PGM MM
1 BLK FORM 0.1 Z X+10 Y-4.375 Z-2
2 BLK FORM 0.2 X+55 Y+40 Z+15
3 ; T1
4 ; Exported by FreeCAD
5 ; Post Processor: linuxcnc_post
6 ; Output Time:2026-11-23 11:29:04.840954
7 ; begin preamble
8 ; begin operation: G54
9 ; machine units: mm/min
10 ; finish operation: G54
11 ; begin operation: TC: Endmill 6mm
12 ; machine units: mm/min
13 ; TC: Endmill 6mm
14 M5
15 L M140 MB MAX
16 TOOL CALL 1 Z S5000
17 L M140 MB MAX
18 M3
19 ; finish operation: TC: Endmill 6mm
20 ; begin operation: Pocket
21 ; machine units: mm/min
22 ; Pocket
23 L Z+15 R0 FMAX
24 L X+10 Y+10 R0 FMAX
25 L Z+5 R0 FMAX
26 L Z-2 R0 F300
27 L X+50 R0 F600
28 CC X+50 Y+15
29 C X+55 Y+15 DR+ R0
30 L Y+35 R0
31 CC X+50 Y+35
32 C X+50 Y+40 DR+ R0
33 L X+10 R0
34 L Y+10 R0
35 L Z+5 R0 FMAX
36 L X+20 Y-4.375 R0 FMAX
37 L Z-1 R0 F300
38 CC X+20 Y+0
39 C X+20 Y+4.375 DR- R0 F600
40 CC X+20 Y+0
41 C X+20 Y-4.375 DR- R0
42 L X+30.125 R0
43 L Z+15 R0 FMAX
44 ; finish operation: Pocket
45 ; begin postamble
46 M5
47 L M140 MB MAX
48 M30
49 END PGM PGM MM
