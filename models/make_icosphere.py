#!/usr/bin/python3
"""Writes models/icosphere.obj: a unit sphere as an icosahedron subdivided
three times (642 vertices, 1,280 triangles, outward-oriented), the
surface the README's first command meshes with `vorocrust mesh`.
Run from the repository root: /usr/bin/python3 models/make_icosphere.py"""
import math
import os

t = (1 + math.sqrt(5)) / 2
verts = [(-1, t, 0), (1, t, 0), (-1, -t, 0), (1, -t, 0), (0, -1, t), (0, 1, t), (0, -1, -t),
         (0, 1, -t), (t, 0, -1), (t, 0, 1), (-t, 0, -1), (-t, 0, 1)]
verts = [tuple(c / math.sqrt(sum(x * x for x in v)) for c in v) for v in verts]
faces = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4),
         (11, 10, 2), (10, 7, 6), (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8),
         (3, 8, 9), (4, 9, 5), (2, 4, 11), (6, 2, 10), (8, 6, 7), (9, 8, 1)]
for _ in range(3):
    mid = {}

    def midpoint(a, b):
        key = (min(a, b), max(a, b))
        if key not in mid:
            m = [(verts[a][k] + verts[b][k]) / 2 for k in range(3)]
            n = math.sqrt(sum(x * x for x in m))
            verts.append(tuple(x / n for x in m))
            mid[key] = len(verts) - 1
        return mid[key]

    nf = []
    for a, b, c in faces:
        ab, bc, ca = midpoint(a, b), midpoint(b, c), midpoint(c, a)
        nf += [(a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca)]
    faces = nf
out = os.path.join(os.path.dirname(os.path.abspath(__file__)), "icosphere.obj")
with open(out, "w") as f:
    f.write("# unit icosphere, 3 subdivisions (models/make_icosphere.py)\n")
    for v in verts:
        f.write("v %.17g %.17g %.17g\n" % v)
    for a, b, c in faces:
        f.write("f %d %d %d\n" % (a + 1, b + 1, c + 1))
