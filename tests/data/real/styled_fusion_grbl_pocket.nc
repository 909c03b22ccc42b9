%
(1001)
(Machine)
(  vendor: Autodesk)
(  description: Generic Grbl)
(T1  D=3.175 CR=0. - ZMIN=-2. - flat end mill)
G90 G94
G17
G21

(Pocket1)
T1
S10000 M3
G54
G0 X20. Y15.
Z5.
G1 Z1. F300.
Z-1.
X30. F1000.
G3 X35. Y20. I0. J5.
G1 Y25.
G3 X30. Y30. I-5. J0.
G1 X20.
G3 X15. Y25. I0. J-5.
G1 Y20.
G3 X20. Y15. I5. J0.
G1 Z-2. F300.
X30. F1000.
G3 X35. Y20. I0. J5.
G1 Y25.
G3 X30. Y30. I-5. J0.
G1 X20.
G3 X15. Y25. I0. J-5.
G1 Y20.
G3 X20. Y15. I5. J0.
G0 Z5.
M5
M30
%
