"""End-to-end test of the refusal of surfaces that cannot bound a volume
(issue 16, and issue 17's offset cube): `vorocrust mesh F -o OUT.vtu` on
each of the six reproducers of ../shared/repro/hangs (their contents are
copied here) exits 1 in under 1 s (10 s under the sanitizers) with one
stderr line "vorocrust: F: ..." naming the problem, and leaves no OUT.vtu
and no temporary file. `vorocrust info` reports the counts, and
--require-closed fails on them (cubes_overlap: its union cannot be formed,
a degenerate contact). Two boxes overlapping in general position mesh as
their union by default (its volume), and are refused naming --no-union
with it; three boxes with triple points mesh as their union (its volume,
the summary's and the .vtu's "volume" array). A prism twisted 80 degrees
per slice (creased at nearly every edge) is refused before sampling, the
line counting the edges that fold beyond the sharp angle. Environment: VC_BIN, VC_TMP, VC_SOURCE,
VC_SANITIZED."""
import math
import os
import re
import sys
import time

sys.path.insert(0, os.path.join(os.environ["VC_SOURCE"], "tests"))
import e2eutil  # noqa: E402
from e2eutil import check, failures, field  # noqa: E402

BIN = os.environ["VC_BIN"]
TMP = e2eutil.fresh_tmp("e2e_refusal")
LIMIT = 10.0 if os.environ.get("VC_SANITIZED", "0") in ("1", "ON", "TRUE", "true") else 1.0

CUBE_V = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n"
CUBE_F = ("f 1 3 2\nf 1 4 3\nf 5 6 7\nf 5 7 8\nf 1 2 6\nf 1 6 5\n"
          "f 2 3 7\nf 2 7 6\nf 3 4 8\nf 3 8 7\nf 4 1 5\nf 4 5 8\n")
BIG = "1.0000000000000001e+300"

# name: (contents, words the line must contain)
CASES = {
    "cube_dup.obj": (CUBE_V + CUBE_F + "f 1 3 2\nf 1 4 3\n",
                     ["2 triangles repeat an earlier one with the same orientation", "triangles 1 and 13"]),
    "cube_zeroarea.obj": (CUBE_V + "v 0.5 0 0\n" + "f 1 3 2\nf 1 4 3\nf 5 6 7\nf 5 7 8\nf 1 9 2\nf 1 2 6\n"
                          "f 1 6 5\nf 2 3 7\nf 2 7 6\nf 3 4 8\nf 3 8 7\nf 4 1 5\nf 4 5 8\nf 1 2 9\n",
                          ["2 zero-area triangles", "triangle 5"]),
    "cubes_overlap.obj": (CUBE_V + "".join("v %g %g %g\n" % (x + 0.5, y + 0.5, z + 0.5)
                                           for x, y, z in [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0),
                                                           (0, 0, 1), (1, 0, 1), (1, 1, 1), (0, 1, 1)])
                          + CUBE_F + "".join("f %s\n" % " ".join(str(int(i) + 8) for i in l.split()[1:])
                                             for l in CUBE_F.splitlines()),
                          ["intersects itself", "pairs of triangles"]),
    "flat.obj": ("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3\nf 1 3 4\nf 1 3 2\nf 1 4 3\n",
                 ["plane z = 0", "encloses no volume"]),
    "flat_box_zero_h.obj": ("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n" * 2 + CUBE_F,
                            ["plane z = 0", "encloses no volume"]),
    # a fin inside the cube, given once per side: a wall of zero thickness
    # (its two sides in one region; vc_surface_regions tells it from an
    # interface between two regions)
    "cube_fin.obj": (CUBE_V + "v 0.25 0.25 0.5\nv 0.75 0.25 0.5\nv 0.75 0.75 0.5\n" + CUBE_F
                     + "f 9 10 11\nf 9 11 10\n", ["the same region on both sides", "zero thickness"]),
    "cube_offset_1e300.obj": ("".join("v %s %s %s\n" % (BIG, y, z)
                                      for y, z in [(0, 0), (0, 0), (1, 0), (1, 0), (0, 1), (0, 1), (1, 1), (1, 1)])
                              + CUBE_F, ["double precision", "near the origin"]),
}

for name, (text, words) in CASES.items():
    path = os.path.join(TMP, name)
    with open(path, "w") as f:
        f.write(text)
    out = os.path.join(TMP, name + ".vtu")
    t0 = time.monotonic()
    rc, _, err = e2eutil.run([BIN, "mesh", path, "-o", out], timeout=120)
    dt = time.monotonic() - t0
    lines = err.strip().splitlines()
    check(rc == 1, "%s: exit %d (stderr %r)" % (name, rc, err))
    check(dt < LIMIT, "%s: %.2f s (limit %g s)" % (name, dt, LIMIT))
    check(len(lines) == 1 and lines[0].startswith("vorocrust: %s: " % path),
          "%s: stderr is not one 'vorocrust: %s: ...' line: %r" % (name, path, err))
    for w in words:
        check(w in err, "%s: stderr lacks %r: %r" % (name, w, err))
    left = sorted(f for f in os.listdir(TMP) if f.startswith(name + ".vtu"))
    check(not left, "%s: left %r" % (name, left))
    print("%s: exit %d, %.3f s: %s" % (name, rc, dt, lines[0] if lines else ""))

    if name == "cube_fin.obj":
        continue  # a solid for info's checks: its regions line counts the wall
    # info: the counts, a warning, exit 0; with --require-closed exit 1.
    rc, out_text, err = e2eutil.run([BIN, "info", path], timeout=60)
    check(rc == 0, "info %s: exit %d" % (name, rc))
    check(field(out_text, "solid") is not None and field(out_text, "solid").startswith("no ("),
          "info %s: solid %r" % (name, field(out_text, "solid")))
    check(field(out_text, "repeated triangles") is not None and field(out_text, "self-intersections") is not None,
          "info %s: no repeated/self-intersection lines" % name)
    rc, _, err = e2eutil.run([BIN, "info", path, "--require-closed"], timeout=60)
    lines = err.strip().splitlines()
    check(rc == 1 and lines and lines[-1].startswith("vorocrust: %s: " % path) and words[0] in lines[-1],
          "info --require-closed %s: exit %d, stderr %r" % (name, rc, err))
    check(not any(l.startswith("vorocrust: warning: ") and words[0] in l for l in lines),
          "info --require-closed %s: the problem printed twice: %r" % (name, err))

# A square prism twisted by 80 degrees per slice, 60 slices 0.05 apart:
# creased at nearly every edge, the radius bounds 1e-4 of the bound's
# size: refused before sampling (the prediction above --max-balls' default),
# the line saying how many edges fold beyond the sharp angle.
path = os.path.join(TMP, "twisted_prism.obj")
with open(path, "w") as f:
    n_sl = 60
    for j in range(n_sl + 1):
        a = math.radians(80.0 * j)
        for x, y in [(1, 0), (0, 1), (-1, 0), (0, -1)]:
            f.write("v %.17g %.17g %.17g\n" % (x * math.cos(a) - y * math.sin(a),
                                                x * math.sin(a) + y * math.cos(a), 0.05 * j))
    for j in range(n_sl):
        for k in range(4):
            a, b = 4 * j + k + 1, 4 * j + (k + 1) % 4 + 1
            c, d = 4 * (j + 1) + (k + 1) % 4 + 1, 4 * (j + 1) + k + 1
            f.write("f %d %d %d\nf %d %d %d\n" % (a, b, c, a, c, d))
    t = 4 * n_sl + 1
    f.write("f 1 3 2\nf 1 4 3\nf %d %d %d\nf %d %d %d\n" % (t, t + 1, t + 2, t, t + 2, t + 3))
out = os.path.join(TMP, "twisted_prism.vtu")
rc, _, err = e2eutil.run([BIN, "mesh", path, "-o", out], timeout=120)
lines = err.strip().splitlines()
m = re.search(r"balls predicted from the sizing, above the limit of \d+: .*; (\d+) of its (\d+) edges fold by "
              r"more than the sharp angle", lines[-1] if lines else "")
check(rc == 1 and m is not None and int(m.group(1)) * 2 > int(m.group(2)) and not os.path.exists(out),
      "twisted_prism: exit %d, no folded-edge count in the refusal, or output left: %r" % (rc, err[-600:]))
print("twisted_prism: exit %d: %s" % (rc, lines[-1] if lines else ""))

# The counts info prints.
_, out_text, _ = e2eutil.run([BIN, "info", os.path.join(TMP, "cube_dup.obj")], timeout=60)
check(field(out_text, "repeated triangles") == "2 (2 with the same orientation, 0 reversed)",
      "cube_dup repeated triangles %r" % field(out_text, "repeated triangles"))
_, out_text, _ = e2eutil.run([BIN, "info", os.path.join(TMP, "cubes_overlap.obj")], timeout=60)
n = field(out_text, "self-intersections")
check(n is not None and int(n) > 0, "cubes_overlap self-intersections %r" % n)
u = field(out_text, "union") or ""
check(u.startswith("cannot be formed: ") and "degenerate" in u, "cubes_overlap union %r" % u)

# Two boxes that overlap in general position: by default (since session
# 30) the union is meshed and its cells' volumes (VTK's own measure) sum to
# the closed-form union volume; with --no-union they are refused, the line
# saying how to mesh the union.
OX, OY, OZ = 0.5123, 0.3217, 0.2731
boxes = os.path.join(TMP, "boxes.obj")
with open(boxes, "w") as f:
    f.write(CUBE_V + "".join("v %r %r %r\n" % (x + OX, y + OY, z + OZ)
                             for x, y, z in ((0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0),
                                             (0, 0, 1), (1, 0, 1), (1, 1, 1), (0, 1, 1))))
    f.write(CUBE_F + "".join("f %s\n" % " ".join(str(int(i) + 8) for i in l.split()[1:])
                             for l in CUBE_F.splitlines()))
union_vtu = os.path.join(TMP, "boxes.vtu")
_, out_text, _ = e2eutil.run([BIN, "info", boxes], timeout=60)
u = field(out_text, "union") or ""
union_volume = 2 - (1 - OX) * (1 - OY) * (1 - OZ)
words = u.split()
check(len(words) > 3 and words[2] == "volume" and abs(float(words[3]) - union_volume) < 1e-8 and
      "(2 of 4 patches" in u, "boxes: info union %r, volume %.9g" % (u, union_volume))
rc, _, err = e2eutil.run([BIN, "mesh", boxes, "-o", union_vtu, "--quiet", "--no-union"], timeout=120)
check(rc == 1 and "intersects itself" in err and "without --no-union" in err and not os.path.exists(union_vtu),
      "boxes with --no-union: exit %d, stderr %r" % (rc, err))
rc, _, err = e2eutil.run([BIN, "mesh", boxes, "-o", union_vtu], timeout=300)
check(rc == 0 and "meshing the union of its parts" in err, "boxes: exit %d, stderr %r" % (rc, err[-2000:]))
if rc == 0:
    import vtk
    reader = vtk.vtkXMLUnstructuredGridReader()
    reader.SetFileName(union_vtu)
    reader.Update()
    grid = reader.GetOutput()
    sizes = vtk.vtkCellSizeFilter()
    sizes.SetInputData(grid)
    sizes.ComputeVolumeOn()
    sizes.Update()
    vol = sizes.GetOutput().GetCellData().GetArray("Volume")
    total = sum(vol.GetValue(i) for i in range(vol.GetNumberOfTuples()))
    check(grid.GetNumberOfCells() > 1000 and abs(total - union_volume) < 0.005 * union_volume,
          "boxes --union: %d cells, volume %.6g, union %.6g" % (grid.GetNumberOfCells(), total, union_volume))

# Three boxes, each pair overlapping, all three sharing a block, their
# coordinates all distinct: faces of the three meet at isolated points
# inside a triangle of each (two curves cross there: a triple point, refused
# until session 47). The union meshes; its volume by inclusion and
# exclusion, the summary's and VTK's.
BOXES3 = [(0, 0, 0, 2, 2, 2), (1.1, 0.37, 0.29, 3.05, 1.63, 1.71), (0.53, 1.09, 0.61, 2.47, 3.01, 2.57)]
boxes3 = os.path.join(TMP, "boxes3.obj")
with open(boxes3, "w") as f:
    for b in BOXES3:
        f.write("".join("v %r %r %r\n" % (b[3] if k & 1 else b[0], b[4] if (k >> 1) & 1 else b[1],
                                            b[5] if (k >> 2) & 1 else b[2]) for k in range(8)))
    for i in range(3):
        for q in ((0, 2, 3, 1), (4, 5, 7, 6), (0, 1, 5, 4), (2, 6, 7, 3), (0, 4, 6, 2), (1, 3, 7, 5)):
            a, b, c, d = (8 * i + k + 1 for k in q)
            f.write("f %d %d %d\nf %d %d %d\n" % (a, b, c, a, c, d))


def box_meet(a, b):
    return tuple(max(a[k], b[k]) for k in range(3)) + tuple(min(a[k + 3], b[k + 3]) for k in range(3))


def box_volume(b):
    return max(0, b[3] - b[0]) * max(0, b[4] - b[1]) * max(0, b[5] - b[2])


A3, B3, C3 = BOXES3
union3 = (sum(box_volume(b) for b in BOXES3) - box_volume(box_meet(A3, B3)) - box_volume(box_meet(A3, C3))
          - box_volume(box_meet(B3, C3)) + box_volume(box_meet(box_meet(A3, B3), C3)))
boxes3_vtu = os.path.join(TMP, "boxes3.vtu")
rc, _, err = e2eutil.run([BIN, "mesh", boxes3, "-o", boxes3_vtu, "--threads", "2"], timeout=300)
m = re.search(r"volume mesh: \d+ cells \(\d+ interior seeds\), volume ([0-9.e+-]+)", err)
check(rc == 0 and "meshing the union of its parts" in err and m is not None and
      abs(float(m.group(1)) - union3) <= 1e-9 * union3,
      "three boxes: exit %d, volume %s against the union's %.9g: %r" % (rc, m and m.group(1), union3, err[-1500:]))
if rc == 0:
    import vtk
    reader = vtk.vtkXMLUnstructuredGridReader()
    reader.SetFileName(boxes3_vtu)
    reader.Update()
    vol = reader.GetOutput().GetCellData().GetArray("volume")
    total = sum(vol.GetValue(i) for i in range(vol.GetNumberOfTuples()))
    check(abs(total - union3) <= 1e-9 * union3, "three boxes: the .vtu's volumes sum to %.12g, the union %.12g"
          % (total, union3))

# A good cube: solid, no warning.
good = os.path.join(TMP, "cube.obj")
with open(good, "w") as f:
    f.write(CUBE_V + CUBE_F)
rc, out_text, err = e2eutil.run([BIN, "info", good, "--require-closed"], timeout=60)
check(rc == 0 and err == "", "cube: exit %d, stderr %r" % (rc, err))
check(field(out_text, "solid") == "yes" and field(out_text, "repeated triangles") == "0" and
      field(out_text, "self-intersections") == "0", "cube: %r" % out_text)

if failures:
    print("e2e_refusal: %d failures" % len(failures), file=sys.stderr)
    sys.exit(1)
print("e2e_refusal: all passed")
