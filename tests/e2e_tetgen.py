"""End-to-end tests of vc-tetgen, the TetGen baseline of `vorocrust compare`.

  (a) models/icosphere.obj with --target-cells: VTK 9.1 reads the .vtu, every
      cell is a VTK_TETRA that vtkCellValidator finds valid, with a positive
      volume (vtkCellSizeFilter) equal to the file's "volume" array; the
      volumes sum to the volume the input encloses (computed here from the
      OBJ); the boundary (faces of one tetrahedron) has the input's area and
      every boundary point lies on the input sphere's triangles (TetGen only
      splits them); the cell count is near the target;
  (b) --max-volume: no tetrahedron exceeds the bound; a smaller bound gives
      more tetrahedra;
  (c) the same on the reference sphere.obj (VC_MODELS), when present;
  (d) nested shells: a box with a cavity (its inner box inward) holding an
      inclusion: the tetrahedra fill the solid only (TetGen's hole point in
      the cavity), their volume the shells' signed sum;
  and bad input: exit 1 (2 for usage), one stderr line "vc-tetgen: ..."
  naming the file and the problem, no output file left behind.

Environment: VC_TETGEN, VC_SOURCE, VC_MODELS, VC_TMP.
"""
import math
import os
import re
import sys

sys.path.insert(0, os.path.join(os.environ["VC_SOURCE"], "tests"))
import vtk  # noqa: E402
import e2eutil  # noqa: E402
import vtkcheck  # noqa: E402
from e2eutil import check, failures  # noqa: E402

TETGEN = os.environ.get("VC_TETGEN", "")
if not os.path.isfile(TETGEN):
    print("FAIL: vc-tetgen was not built (TetGen, Debian's libtet1.5-dev, is missing)", file=sys.stderr)
    sys.exit(1)
SOURCE = os.environ["VC_SOURCE"]
MODELS = os.environ.get("VC_MODELS", "")
TMP = e2eutil.fresh_tmp("e2e_tetgen")


def path(name):
    return os.path.join(TMP, name)


def run(*args):
    return e2eutil.run([TETGEN, *args], timeout=600)


def read_obj(fname):
    verts, tris = [], []
    with open(fname) as fh:
        for line in fh:
            w = line.split()
            if w and w[0] == "v":
                verts.append(tuple(float(x) for x in w[1:4]))
            elif w and w[0] == "f":
                tris.append(tuple(int(x.split("/")[0]) - 1 for x in w[1:4]))
    return verts, tris


def write_obj(name, verts, tris):
    with open(path(name), "w") as fh:
        for v in verts:
            fh.write("v %.17g %.17g %.17g\n" % v)
        for t in tris:
            fh.write("f %d %d %d\n" % (t[0] + 1, t[1] + 1, t[2] + 1))
    return path(name)


def sub(a, b):
    return [a[0] - b[0], a[1] - b[1], a[2] - b[2]]


def cross(a, b):
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def enclosed_volume(verts, tris):
    return math.fsum(dot(verts[a], cross(verts[b], verts[c])) for a, b, c in tris) / 6.0


def triangle_area(a, b, c):
    n = cross(sub(b, a), sub(c, a))
    return 0.5 * math.sqrt(dot(n, n))


def tetra_boundary(grid):
    """The faces of exactly one tetrahedron, as sorted point-id triples."""
    count = {}
    for c in range(grid.GetNumberOfCells()):
        ids = grid.GetCell(c).GetPointIds()
        p = [ids.GetId(k) for k in range(4)]
        for f in ((p[1], p[2], p[3]), (p[0], p[2], p[3]), (p[0], p[1], p[3]), (p[0], p[1], p[2])):
            key = tuple(sorted(f))
            count[key] = count.get(key, 0) + 1
    return [f for f, n in count.items() if n == 1]


def check_tet_mesh(name, out, verts, tris, stderr, target=None, max_volume=None, on_surface=True):
    """Every property of a vc-tetgen mesh of the surface (verts, tris)."""
    try:
        grid = vtkcheck.read_vtu(out)
    except vtkcheck.CheckError as e:
        check(False, "%s: %s" % (name, e))
        return None
    n = grid.GetNumberOfCells()
    check(n > 0, "%s: no cells" % name)
    types = {grid.GetCellType(c) for c in range(n)}
    check(types == {vtk.VTK_TETRA}, "%s: cell types %r, expected only VTK_TETRA" % (name, types))
    states = vtkcheck.validity_states(grid)
    bad = [c for c, s in enumerate(states) if s]
    check(not bad, "%s: %d cells invalid for vtkCellValidator (first %r: %s)"
          % (name, len(bad), bad[:1], vtkcheck.state_text(states[bad[0]]) if bad else ""))
    vols = vtkcheck.vtk_volumes(grid)
    check(min(vols) > 0, "%s: smallest tetrahedron volume %r (inverted or flat)" % (name, min(vols)))
    stored = vtkcheck.cell_array(grid, "volume")
    check(stored is not None and all(abs(a - b) <= 1e-9 * abs(b) + 1e-300 for a, b in zip(stored, vols)),
          "%s: the 'volume' array differs from vtkCellSizeFilter" % name)
    expected = enclosed_volume(verts, tris)
    total = math.fsum(vols)
    check(abs(total - expected) <= 1e-8 * abs(expected),
          "%s: tetrahedra volume %.15g, the input encloses %.15g" % (name, total, expected))
    # The boundary is the input surface, its triangles at most split.
    faces = tetra_boundary(grid)
    area = math.fsum(triangle_area(*(grid.GetPoint(i) for i in f)) for f in faces)
    in_area = math.fsum(triangle_area(verts[a], verts[b], verts[c]) for a, b, c in tris)
    check(abs(area - in_area) <= 1e-8 * in_area,
          "%s: boundary area %.15g, input area %.15g" % (name, area, in_area))
    if on_surface:
        # every boundary point on the input, by VTK's cell locator
        pd = vtk.vtkPolyData()
        pts = vtk.vtkPoints()
        for v in verts:
            pts.InsertNextPoint(v)
        polys = vtk.vtkCellArray()
        for t in tris:
            polys.InsertNextCell(3, t)
        pd.SetPoints(pts)
        pd.SetPolys(polys)
        loc = vtk.vtkCellLocator()
        loc.SetDataSet(pd)
        loc.BuildLocator()
        worst = 0.0
        closest, cell_id, sub_id, d2 = [0.0, 0.0, 0.0], vtk.reference(0), vtk.reference(0), vtk.reference(0.0)
        for i in sorted({i for f in faces for i in f}):
            loc.FindClosestPoint(grid.GetPoint(i), closest, cell_id, sub_id, d2)
            worst = max(worst, math.sqrt(float(d2)))
        diag = math.dist([min(v[k] for v in verts) for k in range(3)],
                         [max(v[k] for v in verts) for k in range(3)])
        # (the locator's squared distances carry rounding of ~1e-16 diag^2)
        check(worst <= 1e-6 * diag, "%s: a boundary point is %g off the input surface" % (name, worst))
    if target is not None:
        check(0.8 * target <= n <= 1.25 * target, "%s: %d tetrahedra for a target of %d" % (name, n, target))
        check(re.search(r"\b%d tetrahedra \(target %d, \d+ TetGen runs\)" % (n, target), stderr),
              "%s: summary does not give the count and target: %r" % (name, stderr))
    if max_volume is not None:
        check(max(vols) <= max_volume * (1 + 1e-9),
              "%s: largest tetrahedron %.6g above the bound %.6g" % (name, max(vols), max_volume))
    return n


# (a) the bundled icosphere, a target cell count
ico = os.path.join(SOURCE, "models", "icosphere.obj")
iv, it = read_obj(ico)
rc, so, se = run(ico, "-o", path("ico.vtu"), "--target-cells", "3000")
if check(rc == 0, "icosphere: exit %d, stderr %r" % (rc, se)):
    check("switches -pq1.414a" in se, "icosphere: summary lacks the switches: %r" % se)
    check_tet_mesh("icosphere", path("ico.vtu"), iv, it, se, target=3000)
    check(not [f for f in os.listdir(TMP) if ".tmp." in f], "icosphere: temporary file left behind")

# (b) an explicit volume bound; a smaller bound gives more tetrahedra
counts = []
for bound in (0.01, 0.002):
    out = path("ico-a%g.vtu" % bound)
    rc, so, se = run(ico, "-o", out, "--max-volume", str(bound), "--quiet")
    if check(rc == 0, "max-volume %g: exit %d, stderr %r" % (bound, rc, se)):
        check(se == "", "max-volume %g: --quiet printed %r" % (bound, se))
        counts.append(check_tet_mesh("max-volume %g" % bound, out, iv, it, se, max_volume=bound,
                                     on_surface=False))
if len(counts) == 2 and None not in counts:
    check(counts[1] > counts[0], "max-volume: %d tetrahedra for 0.002, %d for 0.01" % (counts[1], counts[0]))

# (c) the reference sphere
sphere = os.path.join(MODELS, "sphere.obj")
if not os.path.isfile(sphere):
    print("(c) skipped: %s not found (the shared reference models directory is missing)" % sphere)
else:
    sv, st = read_obj(sphere)
    rc, so, se = run(sphere, "-o", path("sphere.vtu"), "--target-cells", "5000")
    if check(rc == 0, "sphere.obj: exit %d, stderr %r" % (rc, se)):
        check_tet_mesh("sphere.obj", path("sphere.vtu"), sv, st, se, target=5000, on_surface=False)


# (d) a box of side 3 with a cavity of side 2 (inward) holding a box of side 1
def box(lo, size, inward=False):
    v = [(lo[0] + size * x, lo[1] + size * y, lo[2] + size * z) for x in (0, 1) for y in (0, 1) for z in (0, 1)]
    f = [(0, 1, 3), (0, 3, 2), (4, 6, 7), (4, 7, 5), (0, 4, 5), (0, 5, 1), (2, 3, 7), (2, 7, 6),
         (0, 2, 6), (0, 6, 4), (1, 5, 7), (1, 7, 3)]
    return v, [(a, c, b) for a, b, c in f] if inward else f


nv, nt = [], []
for lo, size, inward in (((0, 0, 0), 3.0, False), ((0.5, 0.5, 0.5), 2.0, True), ((1.0, 1.0, 1.0), 1.0, False)):
    v, f = box(lo, size, inward)
    nt += [(a + len(nv), b + len(nv), c + len(nv)) for a, b, c in f]
    nv += v
nested = write_obj("nested.obj", nv, nt)
check(abs(enclosed_volume(nv, nt) - 20.0) < 1e-12, "nested: the shells enclose %r, not 27 - 8 + 1" % enclosed_volume(nv, nt))
rc, so, se = run(nested, "-o", path("nested.vtu"), "--max-volume", "0.05")
if check(rc == 0, "nested boxes: exit %d, stderr %r" % (rc, se)):
    check_tet_mesh("nested boxes", path("nested.vtu"), nv, nt, se, max_volume=0.05)


# bad input
def bad(name, args, code, pattern):
    out = path("bad.vtu")
    if os.path.exists(out):
        os.remove(out)
    rc, so, se = run(*args)
    lines = se.strip().splitlines()
    check(rc == code, "%s: exit %d, expected %d (stderr %r)" % (name, rc, code, se))
    check(len(lines) == 1 and lines[0].startswith("vc-tetgen: ") and re.search(pattern, lines[0]),
          "%s: stderr %r does not match %r in one line" % (name, se, pattern))
    check(not os.path.exists(out), "%s: an output file was written" % name)
    check(not [f for f in os.listdir(TMP) if ".tmp." in f], "%s: temporary file left behind" % name)


def cube(o):
    v = [(o[0] + x, o[1] + y, o[2] + z) for x in (0, 1) for y in (0, 1) for z in (0, 1)]
    f = [(0, 1, 3), (0, 3, 2), (4, 6, 7), (4, 7, 5), (0, 4, 5), (0, 5, 1), (2, 3, 7), (2, 7, 6),
         (0, 2, 6), (0, 6, 4), (1, 5, 7), (1, 7, 3)]
    return v, f


cv, cf = cube((0, 0, 0))
dv, df = cube((0.5, 0.5, 0.5))
crossing = write_obj("crossing.obj", cv + dv, cf + [(a + 8, b + 8, c + 8) for a, b, c in df])
open_surface = write_obj("open.obj", cv, cf[:-1])
with open(path("empty.obj"), "w"):
    pass
out = path("bad.vtu")
bad("missing input", [path("nope.obj"), "-o", out], 1, r"nope\.obj: cannot open")
bad("empty input", [path("empty.obj"), "-o", out], 1, r"empty\.obj")
bad("open surface", [open_surface, "-o", out], 1, r"open\.obj: 3 open boundary edges")
bad("self-intersecting", [crossing, "-o", out], 1, r"crossing\.obj: the surface intersects itself")
bad("no output", [ico], 2, r"missing -o")
bad("no input", ["-o", out], 2, r"missing the INPUT")
bad("output directory missing", [ico, "-o", path("nodir/x.vtu")], 1, r"nodir/x\.vtu: cannot write")
bad("output is a directory", [ico, "-o", TMP], 1, r"Is a directory")
bad("target zero", [ico, "-o", out, "--target-cells", "0"], 2, r"--target-cells: '0'")
bad("target not a number", [ico, "-o", out, "--target-cells", "many"], 2, r"--target-cells: 'many'")
bad("negative volume", [ico, "-o", out, "--max-volume", "-1"], 2, r"--max-volume: '-1'")
bad("both bounds", [ico, "-o", out, "--max-volume", "1", "--target-cells", "10"], 2, r"exclude each other")
bad("radius-edge too small", [ico, "-o", out, "--radius-edge", "1.0"], 2, r"--radius-edge: '1.0'")
bad("unknown option", [ico, "-o", out, "--frobnicate"], 2, r"unknown option '--frobnicate'")
bad("two inputs", [ico, ico, "-o", out], 2, r"unexpected argument")

if failures:
    print("%d failure(s)" % len(failures), file=sys.stderr)
    sys.exit(1)
print("e2e_tetgen: all checks passed")
