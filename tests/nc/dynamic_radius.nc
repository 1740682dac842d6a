N00 G1 G90 X0 D6 F5
N10 G41 G26 (Select TRC)
N20 X0 Y250                    (Starting point)
N30 V.P.VERSCHLEISS = 0.010
N100 $FOR V.P.LAUF = 0,100,10  (Grinding cycle)
N110 X300
N120 Y200
N130 X0
N140 Y250                      (Tool radius gradually becomes smaller)
N150 V.G.WZ_AKT.R = V.G.WZ_AKT.R - V.P.VERSCHLEISS
(N150 is printed with a typographic dash; typed here as the minus it stands for)
N160 $ENDFOR
N200 G40 X300                  (Deselect TRC)
N999 M30
