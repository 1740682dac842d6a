%bsp01.nc
N10 G00 X0 Y0 Z0 G17
N20 X10Y10
N30 V.G.WZ_AKT.R=5 (Tool radius)
N40 G237 (Activation of perpendicular selection)
; Corrected path
N50 G42 (Selection of TRC on the right)
N60 G03 X60Y60J50F1000
N70 G01 Y100
N80 G03 X10Y150J50
N90 G40 (Deselection of TRC)
; Presentation of the original contour
N100 G00 X0Y0
N110 X10Y10
N120 G03 X60Y60J50F1000
N130 G01 Y100
N140 G03 X10Y150J50
N150 G00 X0Y0
N999 M30
