(The manual's #TANGFEED example, with a tool radius of 2 instead of 5:)
(with 5 the arc of N90, radius 5 with the tool inside it, is cut to radius 0, a CalcError.)
N10 V.G.WZR=2
N20 #TANGFEED [RMIN=3] (Define minimum radius rmin = 3mm)
N30 G41 G01 X0 Y20 G11 F600 (Select TRC and feed adaptation)
N40 X20 Y20
N50 G03 X40 R10 (Feed adaptation)
N60 G01 Y40
N70 G02 X44 R2 (No feed adaptation: rprg < rmin)
N80 G01 Y20
N20 #TANGFEED [RMIN=6] (Define new minimum radius rmin = 6mm)
N90 G03 X54 R5 (No feed adaptation: rprg < rmin)
N100 G01 Y50
G40 Y20 G11
N999 M30
