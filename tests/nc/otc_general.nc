N10 F10000
N20 D1                (Data set selection for grinding wheel)
N30 G0 X0 Y0 Z0
N40 #OTC[RADIUS, AUTO] (define OTC processing type + mode)
N50 #OTC ON            (select OTC)
N60 G41 G01 X50        (select TRC, wear-free movement)
N70 X1000
N80 G40 X50           (deselect TRC with path motion to reduce TRC)
N90 #OTC OFF          (deselect OTC)
N100 G00 X50
N199 M30
