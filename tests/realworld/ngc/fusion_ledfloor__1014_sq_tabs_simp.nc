(1014)
(T1  D=2 CR=0 - ZMIN=-6.25 - flat end mill)
G90 G94
G17
G21
(When using Fusion 360 for Personal Use, the feedrate of)
(rapid moves is reduced to match the feedrate of cutting)
(moves, which can increase machining time. Unrestricted rapid)
(moves are available with a Fusion 360 Subscription.)

(2D Contour5)
S5000 M3
G54
G0 X-1 Y-1
Z10.25
G1 Z5.25 F1000
Z3.75 F333.3
Z-2.25
Y51 F1000
X26
Y34
X14
Y16
X25
X26
Y-1
X-1
Z-4.75 F333.3
Y51 F1000
X26
Y34
X14
Y16
X25
X26
Y-1
X-1
Z-6.25 F333.3
Y51 F1000
X26
Y34
X14
Y16
X25
X26
Y-1
X-1
Z5.25
X44
Z3.75 F333.3
Z-2.25
Y14 F1000
X33
X32
Y36
X44
Y50
Y51
X61
Y0
Y-1
X44
Z-4.75 F333.3
Y14 F1000
X33
X32
Y36
X44
Y50
Y51
X61
Y0
Y-1
X44
Z-6.25 F333.3
Y14 F1000
X33
X32
Y36
X44
Y50
Y51
X61
Y0
Y-1
X44
Z10.25
M5
M30
