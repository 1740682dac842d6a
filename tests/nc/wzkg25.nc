%WZKG25 (Contour for G25)
N1 G00 G90 T1 D1 X0 Y0 Z0 G17
(Display of contour)
N15 G01 X20 Y20 F1000
N20 G91
N25 G1 X10
N30 X5 Y-5
N35 Y-5
N40 X-5 Y-3
N45 G01 G90 X0 Y0 F1000
(Path 1)
N100 G138 G41            (Select directly and TRC left of contour)
N105 G01 X20 Y20 F1000   (Required compensation motion after G41)
N110 G25                 (G25 linear transitions)
N115 G1 G91 X10
N120 X5 Y-5
N125 Y-5
N130 X-5 Y-3
N135 G138 G40            (Deselect directly and deselect TRC)
N140 G01 G90 X0 Y0 F1000 (Required compensation motion after G40)
(Path 2)
N200 G139 G41            (Select directly and TRC left of contour)
N205 G01 X20 Y20 F1000   (Required compensation motion after G41)
N210 G25                 (G25 linear transitions)
N215 G1 G91 X10
N220 X5 Y-5
N225 Y-5
N230 X-5 Y-3
N235 G139 G40            (Deselect indirectly and deselect TRC)
N240 G01 G90 X0 Y0 F1000 (Required compensation motion after G40)
(Path 3)
N300 G05 G41             (Tangential selection and TRC left of contour)
N305 G01 X20 Y20 F1000   (Required compensation motion after G41)
N310 G25                 (G25 linear transitions)
N315 G1 G91X10
N320X5 Y-5
N325 Y-5
N330 X-5 Y-3
N335 G05 G40             (Tangential deselection and deselect TRC)
N340 G01 X20 Y20 F1000   (Required compensation motion after G41)
N999 M30
