N30 D1                (Select record for grinding disc)
N40 G00 X0 Y0 Z0
N50 #OTC ON [LENGTH]  (Select OTC)
N60 G1 X1000 F10000
N70 #OTC OFF           (Deselect OTC)
