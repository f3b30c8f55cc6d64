(LinuxCNC: peck a row of holes)
#<_depth> = -3
#<_pitch> = 12
G21 G90 G17 G64 P0.01
T1 M6 G43
S3000 M3
o100 sub
  G0 X#1 Y0 Z2
  G1 Z#<_depth> F150
  G0 Z2
o100 endsub
#<i> = 0
o101 while [#<i> LT 5]
  o100 call [#<i> * #<_pitch>]
  #<i> = [#<i> + 1]
o101 endwhile
M5
M2
