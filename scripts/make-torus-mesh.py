#!/usr/bin/env python3
"""make-torus-mesh.py OUT.obj: the torus mesh of the issues' targets (R 1, r 0.42, 64 x 32 quads as triangles, about
z), which the doc pictures draw (scripts/make-doc-images.sh, make-contour-images.sh). Deterministic."""
import math
import sys

R, r, nu, nv = 1.0, 0.42, 64, 32
with open(sys.argv[1], "w") as f:
    for i in range(nu):
        for j in range(nv):
            u, v = 2 * math.pi * i / nu, 2 * math.pi * j / nv
            f.write("v %.7f %.7f %.7f\n" % ((R + r * math.cos(v)) * math.cos(u), (R + r * math.cos(v)) * math.sin(u),
                                            r * math.sin(v)))
    for i in range(nu):
        for j in range(nv):
            a, b = i * nv + j + 1, (i + 1) % nu * nv + j + 1
            c, d = (i + 1) % nu * nv + (j + 1) % nv + 1, i * nv + (j + 1) % nv + 1
            f.write("f %d %d %d\nf %d %d %d\n" % (a, b, c, a, c, d))
