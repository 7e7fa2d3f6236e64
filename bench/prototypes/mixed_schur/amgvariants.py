"""Does a stronger AMG on S_aL close the gap to exact S_aL^-1? (V(1,1) vs 2 V-cycles vs theta)"""
import numpy as np, time
from fem import *
from sa_amg import SA, near_null
for nx, ny in [(64,16),(128,32)]:
    P = Problem(nx, ny, 0.05); B, blk = near_null(P)
    for theta in [0.0, 0.08]:
        amg = SA(P.SLf, B, blk, theta=theta)
        _, it1 = pcg(P.S, P.b, amg)
        def two(r, amg=amg):
            x = amg(r); return x + amg(r - P.SLf @ x)
        _, it2 = pcg(P.S, P.b, two)
        def three(r, amg=amg):
            x = amg(r); x = x + amg(r - P.SLf @ x); return x + amg(r - P.SLf @ x)
        _, it3 = pcg(P.S, P.b, three)
        print(f"{nx}x{ny} theta={theta} opc {amg.opc:.2f}: CG on S_a with 1 V-cycle(S_aL): {it1} it; 2 V-cycles: {it2} it ({2*it2} V); 3 V-cycles: {it3} it ({3*it3} V)", flush=True)
