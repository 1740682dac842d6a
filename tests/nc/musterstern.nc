%musterstern.nc
(The manual's first block, G74 X1Y2Z3, is left out: this controller has no reference run.)
N2 G17 G00 X0Y0Z0 G90
N4 F10000
(Display of contour)
N100 G01 X0 Y100
N110 X-20 Y20
N120 X-100 Y0
N130 X-20 Y-20
N140 X0 Y-100
N150 X20 Y-20
N160 X100 Y0
N170 X20 Y20
N180 G01 X0 Y100
N200 G00 X0Y0
(Path display)
N210 G238 (Inside corner selection activated)
N220 V.G.WZR = 10 (Define tool radius)
N230 G41     (Select TRC left of contour)
N240 G01 X0 Y100   (Approach block)
N310 X-20 Y20
N320 X-100 Y0
N330 X-20 Y-20
N340 X0 Y-100
N350 X20 Y-20
N360 X100 Y0
N370 X20 Y20
N380 G01 X0 Y100
N390 G40 (Deselect TRC)
N400 G00 X0Y0
N999 M30
