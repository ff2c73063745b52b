#!/usr/bin/env python3
"""Writes models/ball-seeds.csv: the seeds of a ball meshed the VoroCrust way.

Surface samples q on the unit sphere (a Fibonacci spiral) each get a pair of
seeds q*(1 -/+ d) on both sides of the sphere; the inner one is kept (label
1), the outer one is not (label 0), so the Voronoi facets between the two
sides approximate the sphere. Interior seeds on a cubic lattice fill the
ball (label 1). Many seeds are co-spherical by construction, which is the
degenerate input the Voronoi engine must handle.

Usage: python3 models/make_ball_seeds.py [N_SURFACE] > models/ball-seeds.csv
"""
import math
import sys

n = int(sys.argv[1]) if len(sys.argv) > 1 else 1500
d = 0.06
golden = math.pi * (3.0 - math.sqrt(5.0))
rows = []
for i in range(n):
    z = 1.0 - 2.0 * (i + 0.5) / n
    r = math.sqrt(1.0 - z * z)
    x, y = r * math.cos(golden * i), r * math.sin(golden * i)
    for scale, label in ((1.0 - d, 1), (1.0 + d, 0)):
        rows.append((x * scale, y * scale, z * scale, label))
h = 0.12
k = int(1.0 / h) + 1
for i in range(-k, k + 1):
    for j in range(-k, k + 1):
        for m in range(-k, k + 1):
            p = (i * h + 0.013, j * h + 0.007, m * h + 0.011)
            if math.sqrt(p[0] ** 2 + p[1] ** 2 + p[2] ** 2) < 1.0 - 2.5 * d:
                rows.append((p[0], p[1], p[2], 1))
print("x,y,z,label")
for x, y, z, label in rows:
    print("%.12g,%.12g,%.12g,%d" % (x, y, z, label))
