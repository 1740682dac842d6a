N30 G0 D0 X0 Y0 Z0 G17  (X-Y plane)
N40 G0 D100 X10 Y10     (Select TLC)
N50 G1 Z0
N60 G0 Z100
N70 G41                 (Select TRC with data block D100)
N80 G1 Z0
N90 G2 X10 Y10 I-15     (Full circle with radius 15)
N100 G0 Z100
N110 D2 Z200            (Other compensation data block, i.e.)
(other values for TLC and TRC)
N120 G1 Z0              (Compensating motion)
                        (motion of TLC takes place here)
N130 G1 X20 Y20         (Compensating motion of TRC)
N140 G02 X10 Y10 I-15   (TRC is now executed with data)
                        (block D2)
N150 G0 Z100
N160 G40                (Deselect TRC)
N170 X0
