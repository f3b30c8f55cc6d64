(Router with a hand-set trim router: M3 switches the relay, the dial sets the speed)
G21
G90
G17
G0 Z10
M3
G0 X5 Y5
G1 Z-3 F300
G1 X295 Y5 F1800
G1 X295 Y195
G1 X5 Y195
G1 X5 Y5
G0 Z10
M5
G0 X0 Y0
M2
