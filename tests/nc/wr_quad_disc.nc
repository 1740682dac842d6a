%wr_quad_disc.nc
N20 G17G90
N22 D1 G25          (Linear transition block)
N40 G1 X0Y0Z0 F600

N50 #OTC ON[RADIUS DISC]
N55 G42
N60 G1 X2
N70 G1 X102
N80 G26 Y100        (Circular transition block)

N90 X2
N95 Y0

N100 G40 G1 X0
N110 #OTC OFF

N99999 M30
