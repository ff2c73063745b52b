"""End-to-end tests of `vorocrust quality` through the CLI.

  (a) Voronoi meshes of random seeds (written by `vorocrust voronoi`, zlib
      and raw): cell, vertex and face counts against VTK's reader, total
      volume and the volume statistics against VTK's vtkCellSizeFilter, the
      boundary (faces of one cell) against a count made here;
  (b) a cubic lattice: every figure known exactly (fatness sqrt 3, shortest
      edge / enclosing radius 2 / sqrt 3, smallest face / enclosing radius^2
      4 / 3, no cell with a short edge, square faces fanned into
      right isosceles triangles), and the Hausdorff distance to a cube
      surface (0 for the same cube; for a cube 10% larger, the corner
      distance 0.05 sqrt 3, normalised by the larger cube's diagonal);
  (c) a tetrahedral mesh made by VTK (vtkDelaunay3D of random points) and
      written by vtkXMLUnstructuredGridWriter in every mode (ascii, inline
      binary, appended raw and base64, zlib or not, UInt32 or UInt64
      headers, Int32 or Int64 ids): every file gives the same report, and
      volumes, dihedral angles, fatness (inradius 3V / area, minimum
      enclosing ball by brute force), smallest face over the enclosing
      radius squared, the share of short edges, boundary triangle quality and angle
      percentages agree with an independent computation in Python;
  (d) mixed cells (a polyhedron, a tetrahedron and a skipped hexahedron),
      inward cells (counted, measured the same), open or inconsistently
      oriented cells (counted), thread-count independence;
  and bad input: exit 1 (2 for usage), one stderr line "vorocrust: ..."
  naming the file and the problem.

Environment: VC_BIN, VC_SOURCE, VC_TMP.
"""
import itertools
import math
import os
import random
import re
import sys

sys.path.insert(0, os.path.join(os.environ["VC_SOURCE"], "tests"))
import vtk  # noqa: E402
import e2eutil  # noqa: E402
import vtkcheck  # noqa: E402
from e2eutil import check, failures  # noqa: E402

BIN = os.environ["VC_BIN"]
TMP = e2eutil.fresh_tmp("e2e_quality")


def close(a, b, rel=1e-9, abs_=1e-12):
    return abs(a - b) <= max(abs_, rel * max(abs(a), abs(b)))


def path(name):
    return os.path.join(TMP, name)


def run(*args):
    return e2eutil.run([BIN, *args], timeout=600)


STAT_KEYS = ["min", "max", "mean", "p1", "p5", "p50", "p95", "p99"]


def quality(name, mesh, *opts):
    """Runs `vorocrust quality`; returns the report as a dict of lines, with
    statistics lines parsed into dicts of floats."""
    rc, so, se = run("quality", mesh, *opts)
    if not check(rc == 0, "%s: exit %d, stderr %r" % (name, rc, se)):
        return None
    rep = {}
    for line in so.splitlines():
        key, _, val = line.partition(": ")
        rep[key] = val
        fields = re.findall(r"(min|max|mean|p1|p5|p50|p95|p99) (\S+?),?(?=\s|$)", val)
        if len(fields) == 8 and key not in ("cells",):
            rep[key] = {k: float(v) for k, v in fields}
    rep["_stdout"] = so
    rep["_stderr"] = se
    return rep


def percentile(sorted_values, q):
    """numpy.percentile's default (linear between closest ranks)."""
    n = len(sorted_values)
    h = (n - 1) * q / 100.0
    lo = int(math.floor(h))
    if lo >= n - 1:
        return sorted_values[-1]
    return sorted_values[lo] + (h - lo) * (sorted_values[lo + 1] - sorted_values[lo])


def stats(values):
    s = sorted(values)
    return {"min": s[0], "max": s[-1], "mean": sum(s) / len(s),
            **{"p%d" % q: percentile(s, q) for q in (1, 5, 50, 95, 99)}}


def check_stats(name, what, got, expected, rel):
    """The CLI prints 6 significant digits."""
    if not check(isinstance(got, dict), "%s: no statistics line for %s" % (name, what)):
        return
    for k in STAT_KEYS:
        check(close(got[k], expected[k], rel=rel, abs_=1e-300),
              "%s: %s %s = %r, expected %r" % (name, what, k, got[k], expected[k]))


def read_grid(fname):
    r = vtk.vtkXMLUnstructuredGridReader()
    r.SetFileName(fname)
    r.Update()
    return r.GetOutput()


def cell_faces(grid, c):
    """A cell's faces as point-id tuples (tetrahedra: their 4 triangles)."""
    cell = grid.GetCell(c)
    out = []
    for k in range(cell.GetNumberOfFaces()):
        f = cell.GetFace(k)
        out.append(tuple(f.GetPointId(i) for i in range(f.GetNumberOfPoints())))
    return out


def boundary_faces(grid):
    uses = {}
    for c in range(grid.GetNumberOfCells()):
        if grid.GetCellType(c) not in (10, 42):
            continue
        for f in cell_faces(grid, c):
            key = tuple(sorted(f))
            uses.setdefault(key, [0, f])
            uses[key][0] += 1
    return len(uses), [f for n, f in uses.values() if n == 1]


def vsub(a, b):
    return [a[0] - b[0], a[1] - b[1], a[2] - b[2]]


def cross(a, b):
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def norm(a):
    return math.sqrt(dot(a, a))


def angle(u, v):
    return math.degrees(math.atan2(norm(cross(u, v)), dot(u, v)))


def triangle_quality(a, b, c):
    la, lb, lc = norm(vsub(b, a)), norm(vsub(c, b)), norm(vsub(a, c))
    h = max(la, lb, lc)
    s = 0.5 * norm(cross(vsub(b, a), vsub(c, a)))
    return 6 * s / (math.sqrt(3) * h * 0.5 * (la + lb + lc))


def boundary_triangles(grid, faces):
    pts = [grid.GetPoint(i) for i in range(grid.GetNumberOfPoints())]
    tris = []
    for f in faces:
        if len(f) == 3:
            tris.append([pts[i] for i in f])
            continue
        c = [sum(pts[i][d] for i in f) / len(f) for d in range(3)]
        for k in range(len(f)):
            tris.append([c, pts[f[k]], pts[f[(k + 1) % len(f)]]])
    return tris


def check_boundary(name, rep, grid):
    """Face counts, triangle quality and angle percentages, computed here."""
    n_faces, bfaces = boundary_faces(grid)
    check(rep.get("faces") == "%d (%d boundary)" % (n_faces, len(bfaces)),
          "%s: faces line %r, expected %d (%d boundary)" % (name, rep.get("faces"), n_faces, len(bfaces)))
    tris = boundary_triangles(grid, bfaces)
    check(rep.get("boundary triangles") == str(len(tris)),
          "%s: boundary triangles %r, expected %d" % (name, rep.get("boundary triangles"), len(tris)))
    check_stats(name, "triangle quality", rep.get("triangle quality"),
                stats([triangle_quality(*t) for t in tris]), 2e-5)
    below = above = 0
    for a, b, c in tris:
        for p, q, r in ((a, b, c), (b, c, a), (c, a, b)):
            ang = angle(vsub(q, p), vsub(r, p))
            below += ang < 30
            above += ang > 90
    for key, n in (("angles below 30 degrees", below), ("angles above 90 degrees", above)):
        got = float(rep.get(key, "nan%").rstrip("%"))
        check(abs(got - 100.0 * n / (3 * len(tris))) < 6e-5,
              "%s: %s %r, expected %.4f%%" % (name, key, rep.get(key), 100.0 * n / (3 * len(tris))))


def cell_size_volumes(grid):
    return [abs(v) for v in vtkcheck.vtk_volumes(grid)]


def vtk_reference_volumes(grid):
    """vtkCellSizeFilter's volumes; where it loses volume on a polyhedron
    (see vtkcheck: its Delaunay tetrahedralization drops tetrahedra of
    nearly co-spherical points), vtkMassProperties on the cell's faces.
    Returns the volumes and the number of cells that needed the fallback."""
    vols = cell_size_volumes(grid)
    fallback = 0
    for c in range(len(vols)):
        if grid.GetCellType(c) != 42:
            continue
        mp = vtkcheck.cell_mass_volume(grid, c)
        if abs(vols[c] - mp) > 1e-6 * mp:
            check(vols[c] < mp, "cell %d: vtkCellSizeFilter %r above vtkMassProperties %r" % (c, vols[c], mp))
            vols[c] = mp
            fallback += 1
    return vols, fallback


def write_seeds(name, rows):
    p = path(name)
    with open(p, "w") as f:
        f.write("x,y,z\n")
        for r in rows:
            f.write(",".join(repr(float(v)) for v in r) + "\n")
    return p


def voronoi(name, seeds, *opts):
    out = path(name + ".vtu")
    rc, so, se = run("voronoi", seeds, "-o", out, "--quiet", *opts)
    check(rc == 0, "%s: voronoi exit %d: %s" % (name, rc, se))
    return out


def write_obj(name, verts, tris):
    p = path(name)
    with open(p, "w") as f:
        for v in verts:
            f.write("v %r %r %r\n" % tuple(float(x) for x in v))
        for t in tris:
            f.write("f %d %d %d\n" % tuple(i + 1 for i in t))
    return p


def cube_obj(name, lo, hi):
    v = [(x, y, z) for z in (lo, hi) for y in (lo, hi) for x in (lo, hi)]
    quads = [(0, 2, 3, 1), (4, 5, 7, 6), (0, 1, 5, 4), (2, 6, 7, 3), (1, 3, 7, 5), (0, 4, 6, 2)]
    tris = [t for q in quads for t in ((q[0], q[1], q[2]), (q[0], q[2], q[3]))]
    return write_obj(name, v, tris)


# ---- (a) random seeds ----------------------------------------------------------

rng = random.Random(20261124)
seeds = write_seeds("random.csv", [[rng.random() for _ in range(3)] for _ in range(400)])
for enc in ("zlib", "raw"):
    name = "random_" + enc
    mesh = voronoi(name, seeds, "--box", "0", "0", "0", "1", "1", "1", "--encoding", enc)
    rep = quality(name, mesh)
    if rep is None:
        continue
    grid = read_grid(mesh)
    check(rep["cells"] == "%d (%d polyhedra, 0 tetrahedra)" % (grid.GetNumberOfCells(), grid.GetNumberOfCells()),
          "%s: cells line %r" % (name, rep["cells"]))
    check(rep["vertices"] == str(grid.GetNumberOfPoints()), "%s: vertices %r" % (name, rep["vertices"]))
    vols, fallback = vtk_reference_volumes(grid)
    check(fallback < len(vols) // 10, "%s: vtkCellSizeFilter lost volume on %d of %d cells" % (name, fallback, len(vols)))
    # cells vtkCellSizeFilter gets within 1e-6 keep their small error
    check(close(float(rep["total volume"]), sum(vols), 1e-7), "%s: total volume %s vs VTK %r" % (
        name, rep["total volume"], sum(vols)))
    check(close(float(rep["total volume"]), 1.0, 1e-12), "%s: total volume %s, box is 1" % (name, rep["total volume"]))
    check_stats(name, "volume", rep.get("volume"), stats(vols), 2e-5)
    fat = rep.get("fatness")
    if check(isinstance(fat, dict), "%s: no fatness line" % name):
        check(1.0 < fat["min"] <= fat["p50"] <= fat["max"] < 20, "%s: fatness %r" % (name, fat))
    rel = rep.get("shortest relative edge")
    if check(isinstance(rel, dict), "%s: no shortest relative edge line" % name):
        check(0 < rel["min"] <= rel["max"] <= 2, "%s: shortest relative edge %r" % (name, rel))
    check("dihedral angle min" not in rep, "%s: dihedral angles printed for polyhedra" % name)
    # every cell's seed, as VTK reads it, is its row of the seeds CSV
    sp = grid.GetCellData().GetArray("seed_point")
    sid = grid.GetCellData().GetArray("seed")
    if check(sp is not None and sp.GetNumberOfComponents() == 3 and sid is not None,
             "%s: no 3-component seed_point array" % name):
        with open(seeds) as f:
            rows = [tuple(map(float, r.split(","))) for r in f.read().splitlines()[1:]]
        bad = [c for c in range(grid.GetNumberOfCells())
               if sp.GetTuple3(c) != rows[int(sid.GetTuple1(c))]]
        check(not bad, "%s: seed_point differs from the seeds CSV in %d cells" % (name, len(bad)))
    conn = rep.get("seed distance / mean enclosing radius")
    if check(isinstance(conn, dict), "%s: no seed distance line" % name):
        check(0 < conn["min"] <= conn["p50"] <= conn["max"] < 4, "%s: seed distance %r" % (name, conn))
    check_boundary(name, rep, grid)
    if enc == "zlib":
        random_zlib_report = rep
    else:
        strip = lambda r: {k: v for k, v in r.items() if k not in ("file", "time", "_stdout", "_stderr")}
        check(strip(rep) == strip(random_zlib_report), "raw and zlib files give different reports")

# thread-count independence (everything but the file and time lines)
outs = []
for t in ("1", "2"):
    rc, so, se = run("quality", path("random_zlib.vtu"), "--threads", t, "--input", cube_obj("unit_cube.obj", 0, 1))
    check(rc == 0, "threads %s: exit %d %s" % (t, rc, se))
    outs.append([l for l in so.splitlines() if not l.startswith("time:")])
check(outs[0] == outs[1], "--threads 1 and 2 differ:\n%s\n%s" % (outs[0], outs[1]))

# ---- (b) cubic lattice -----------------------------------------------------------

n = 4
lattice = write_seeds("lattice.csv", [[(i + 0.5) / n, (j + 0.5) / n, (k + 0.5) / n]
                                      for i in range(n) for j in range(n) for k in range(n)])
mesh = voronoi("lattice", lattice, "--box", "0", "0", "0", "1", "1", "1")
rep = quality("lattice", mesh, "--input", cube_obj("cube_same.obj", 0.0, 1.0))
if rep:
    h = 1.0 / n
    # smallest face h^2 over the enclosing radius squared 3 h^2 / 4
    # seeds h apart, enclosing radii sqrt(3) h / 2
    exact = {"fatness": math.sqrt(3), "shortest relative edge": 2 / math.sqrt(3), "volume": h ** 3,
             "smallest face / enclosing radius^2": 4.0 / 3.0,
             "seed distance / mean enclosing radius": 2 / math.sqrt(3)}
    for key, val in exact.items():
        check_stats("lattice", key, rep.get(key), {k: val for k in STAT_KEYS}, 1e-5)
    check(rep.get("cells with a shortest relative edge below 1e-2") == "0.00%",
          "lattice: short-edge share %r" % rep.get("cells with a shortest relative edge below 1e-2"))
    check(rep["cells"] == "64 (64 polyhedra, 0 tetrahedra)", "lattice: cells %r" % rep["cells"])
    check(rep["vertices"] == "125", "lattice: vertices %r" % rep["vertices"])
    check(rep["faces"] == "240 (96 boundary)", "lattice: faces %r" % rep["faces"])
    check(rep["boundary triangles"] == "384", "lattice: boundary triangles %r" % rep["boundary triangles"])
    q_right = 3.0 / (math.sqrt(3) * math.sqrt(2) * (1 + math.sqrt(2) / 2))  # right isosceles
    check_stats("lattice", "triangle quality", rep.get("triangle quality"), {k: q_right for k in STAT_KEYS}, 1e-5)
    check(rep.get("angles below 30 degrees") == "0.0000%", "lattice: %r" % rep.get("angles below 30 degrees"))
    check(rep.get("angles above 90 degrees") == "0.0000%", "lattice: %r" % rep.get("angles above 90 degrees"))
    m = re.match(r"(\S+) \(normalised by the input's bounding-box diagonal (\S+): (\S+)\)", rep.get("hausdorff distance", ""))
    check(m and float(m.group(1)) < 1e-12, "lattice vs the same cube: %r" % rep.get("hausdorff distance"))
rep = quality("lattice_big", mesh, "--input", cube_obj("cube_big.obj", -0.05, 1.05))
if rep:
    m = re.match(r"(\S+) \(normalised by the input's bounding-box diagonal (\S+): (\S+)\)", rep.get("hausdorff distance", ""))
    if check(m, "lattice vs a larger cube: %r" % rep.get("hausdorff distance")):
        d = 0.05 * math.sqrt(3)
        check(close(float(m.group(1)), d, 1e-5), "lattice vs larger cube: %s, expected %r" % (m.group(1), d))
        check(close(float(m.group(2)), 1.1 * math.sqrt(3), 1e-5), "diagonal %s" % m.group(2))
        check(close(float(m.group(3)), d / (1.1 * math.sqrt(3)), 1e-5), "normalised %s" % m.group(3))

# ---- (c) tetrahedra written by VTK ---------------------------------------------------

points = vtk.vtkPoints()
points.SetDataTypeToDouble()
for _ in range(120):
    points.InsertNextPoint(rng.random(), rng.random(), 0.5 * rng.random())
poly = vtk.vtkPolyData()
poly.SetPoints(points)
delaunay = vtk.vtkDelaunay3D()
delaunay.SetInputData(poly)
delaunay.Update()
tets = delaunay.GetOutput()

variants = []
for mode, mname in ((0, "ascii"), (1, "binary"), (2, "appended")):
    for comp in (0, 1):
        for header in (32, 64):
            for ids in (32, 64):
                for enc_app in ((0, 1) if mode == 2 else (1,)):
                    w = vtk.vtkXMLUnstructuredGridWriter()
                    fname = path("tets_%s_%s_h%d_i%d%s.vtu" % (mname, "zlib" if comp else "none", header, ids,
                                                               "" if mode != 2 else ("_b64" if enc_app else "_raw")))
                    w.SetFileName(fname)
                    w.SetInputData(tets)
                    w.SetDataMode(mode)
                    w.SetEncodeAppendedData(enc_app)
                    w.SetCompressorTypeToZLib() if comp else w.SetCompressorTypeToNone()
                    w.SetHeaderTypeToUInt32() if header == 32 else w.SetHeaderTypeToUInt64()
                    w.SetIdTypeToInt32() if ids == 32 else w.SetIdTypeToInt64()
                    check(w.Write() == 1, "VTK could not write %s" % fname)
                    variants.append(fname)

# independent figures
P = [tets.GetPoint(i) for i in range(tets.GetNumberOfPoints())]
T = [[tets.GetCell(c).GetPointId(k) for k in range(4)] for c in range(tets.GetNumberOfCells())]


def tet_volume(t):
    a, b, c, d = (P[i] for i in t)
    return abs(dot(vsub(b, a), cross(vsub(c, a), vsub(d, a)))) / 6


def tet_dihedrals(t):
    out = []
    for i, j in itertools.combinations(range(4), 2):
        k, l = [m for m in range(4) if m not in (i, j)]
        e = vsub(P[t[j]], P[t[i]])
        u = cross(e, vsub(P[t[k]], P[t[i]]))
        v = cross(e, vsub(P[t[l]], P[t[i]]))
        out.append(angle(u, v))
    return out


def min_ball_radius(pts):
    """Smallest ball through 2, 3 or 4 of the points containing them all."""
    best = math.inf
    for k in (2, 3, 4):
        for sub in itertools.combinations(pts, k):
            q0 = sub[0]
            v = [vsub(q, q0) for q in sub[1:]]
            m = len(v)
            g = [[2 * dot(v[i], v[j]) for j in range(m)] + [dot(v[i], v[i])] for i in range(m)]
            ok = True
            for c in range(m):  # Gauss-Jordan
                piv = max(range(c, m), key=lambda r: abs(g[r][c]))
                if abs(g[piv][c]) < 1e-14:
                    ok = False
                    break
                g[c], g[piv] = g[piv], g[c]
                for r in range(m):
                    if r != c:
                        f = g[r][c] / g[c][c]
                        g[r] = [x - f * y for x, y in zip(g[r], g[c])]
            if not ok:
                continue
            lam = [g[r][m] / g[r][r] for r in range(m)]
            center = [q0[d] + sum(lam[j] * v[j][d] for j in range(m)) for d in range(3)]
            r = norm(vsub(center, q0))
            if r < best and all(norm(vsub(p, center)) <= r * (1 + 1e-9) for p in pts):
                best = r
    return best


def tet_fatness(t):
    pts = [P[i] for i in t]
    area = 0
    for f in itertools.combinations(pts, 3):
        area += 0.5 * norm(cross(vsub(f[1], f[0]), vsub(f[2], f[0])))
    inradius = 3 * tet_volume(t) / area
    return min_ball_radius(pts) / inradius


def tet_shortest_rel(t):
    pts = [P[i] for i in t]
    return min(norm(vsub(a, b)) for a, b in itertools.combinations(pts, 2)) / min_ball_radius(pts)


def tet_small_face_rel(t):
    pts = [P[i] for i in t]
    area = min(0.5 * norm(cross(vsub(b, a), vsub(c, a))) for a, b, c in itertools.combinations(pts, 3))
    return area / min_ball_radius(pts) ** 2


vols = [tet_volume(t) for t in T]
dih = [tet_dihedrals(t) for t in T]
expected = {
    "volume": stats(vols),
    "dihedral angle min": stats([min(d) for d in dih]),
    "dihedral angle max": stats([max(d) for d in dih]),
    "fatness": stats([tet_fatness(t) for t in T]),
    "shortest relative edge": stats([tet_shortest_rel(t) for t in T]),
    "smallest face / enclosing radius^2": stats([tet_small_face_rel(t) for t in T]),
}
short_share = 100.0 * sum(tet_shortest_rel(t) < 1e-2 for t in T) / len(T)
reports = []
for fname in variants:
    name = os.path.basename(fname)
    rep = quality(name, fname)
    if rep is None:
        continue
    reports.append((name, {k: v for k, v in rep.items() if k not in ("file", "time", "_stdout", "_stderr")}))
    check(rep["cells"] == "%d (0 polyhedra, %d tetrahedra)" % (len(T), len(T)), "%s: cells %r" % (name, rep["cells"]))
    check(rep["vertices"] == str(len(P)), "%s: vertices %r" % (name, rep["vertices"]))
for name, r in reports[1:]:
    check(r == reports[0][1], "%s: report differs from %s" % (name, reports[0][0]))
if reports:
    name, rep = reports[0]
    # ascii files hold 6 digits: compare on a binary file
    rep = quality("tets_binary", path("tets_binary_none_h64_i64.vtu"))
    check(close(float(rep["total volume"]), sum(vols), 1e-12), "tets: total volume %s vs %r" % (rep["total volume"], sum(vols)))
    check(close(float(rep["total volume"]), sum(cell_size_volumes(tets)), 1e-12), "tets: total volume vs vtkCellSizeFilter")
    for key, exp in expected.items():
        check_stats("tets", key, rep.get(key), exp, 2e-5)
    got_share = rep.get("cells with a shortest relative edge below 1e-2", "?%").rstrip("%")
    check(abs(float(got_share) - short_share) < 0.006 if got_share != "?" else False,
          "tets: short-edge share %r%%, expected %.4f%%" % (got_share, short_share))
    check_boundary("tets", rep, tets)
    check("seed distance / mean enclosing radius" not in rep,
          "tets: a seed distance line without seeds in the file")

# the tets with each one's centroid as its seed (CellData "seed_point", written
# by VTK, zlib appended): the connections of the tets sharing a face, their
# seeds' distance over the mean of the two minimum enclosing radii
centroids = vtk.vtkDoubleArray()
centroids.SetName("seed_point")
centroids.SetNumberOfComponents(3)
for t in T:
    centroids.InsertNextTuple3(*[sum(P[i][d] for i in t) / 4 for d in range(3)])
tets.GetCellData().AddArray(centroids)
w = vtk.vtkXMLUnstructuredGridWriter()
w.SetFileName(path("tets_seeds.vtu"))
w.SetInputData(tets)
w.SetCompressorTypeToZLib()
check(w.Write() == 1, "VTK could not write tets_seeds.vtu")
by_face = {}
for c, t in enumerate(T):
    for f in itertools.combinations(sorted(t), 3):
        by_face.setdefault(f, []).append(c)
radius = [min_ball_radius([P[i] for i in t]) for t in T]
seed = [centroids.GetTuple3(c) for c in range(len(T))]
expected_conn = [norm(vsub(seed[a], seed[b])) / (0.5 * (radius[a] + radius[b]))
                 for cells in by_face.values() if len(cells) == 2 for a, b in [cells]]
rep = quality("tets_seeds", path("tets_seeds.vtu"))
if rep:
    check_stats("tets_seeds", "seed distance / mean enclosing radius",
                rep.get("seed distance / mean enclosing radius"), stats(expected_conn), 2e-5)

# ---- (d) mixed cells ------------------------------------------------------------------

pts = vtk.vtkPoints()
for p in [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0), (0, 0, 1), (1, 0, 1), (1, 1, 1), (0, 1, 1), (2, 0, 0), (3, 0, 0)]:
    pts.InsertNextPoint(p)
mixed = vtk.vtkUnstructuredGrid()
mixed.SetPoints(pts)
faces = [[0, 3, 2, 1], [4, 5, 6, 7], [0, 1, 5, 4], [2, 3, 7, 6], [1, 2, 6, 5], [0, 4, 7, 3]]
fl = vtk.vtkIdList()
fl.InsertNextId(6)
for f in faces:
    fl.InsertNextId(len(f))
    for i in f:
        fl.InsertNextId(i)
mixed.InsertNextCell(42, fl)
ids = vtk.vtkIdList()
for i in (1, 8, 2, 5):
    ids.InsertNextId(i)
mixed.InsertNextCell(10, ids)
hexa = vtk.vtkIdList()
for i in range(8):
    hexa.InsertNextId(i)
mixed.InsertNextCell(12, hexa)
w = vtk.vtkXMLUnstructuredGridWriter()
w.SetFileName(path("mixed.vtu"))
w.SetInputData(mixed)
w.Write()
rep = quality("mixed", path("mixed.vtu"))
if rep:
    check(rep["cells"] == "2 (1 polyhedra, 1 tetrahedra)", "mixed: cells %r" % rep["cells"])
    check(rep.get("skipped cells") == "1 (other cell types)", "mixed: skipped %r" % rep.get("skipped cells"))
    check(re.search(r"^vorocrust: warning: .*mixed\.vtu: 1 cells of other types skipped \(first: VTK cell type 12\)",
                    rep["_stderr"], re.M), "mixed: warning %r" % rep["_stderr"])
    check(close(float(rep["total volume"]), 1 + 1 / 6, 1e-14), "mixed: volume %r" % rep["total volume"])
    # the corner tetrahedron's smallest enclosing ball is its slanted face's circumcircle
    r_in = 1 / (3 + math.sqrt(3))
    check_stats("mixed", "fatness", rep.get("fatness"), stats([math.sqrt(3), math.sqrt(2 / 3) / r_in]), 1e-5)

# a cube with its faces listed inward, and a cube missing a face
def cube_grid(face_lists):
    g = vtk.vtkUnstructuredGrid()
    g.SetPoints(pts)
    for fs in face_lists:
        g.InsertNextCell(vtkcheck.VTK_POLYHEDRON, vtkcheck.face_stream(fs))
    w = vtk.vtkXMLUnstructuredGridWriter()
    w.SetFileName(path("cubes.vtu"))
    w.SetInputData(g)
    w.Write()
    return path("cubes.vtu")


rep = quality("inward", cube_grid([[f[::-1] for f in faces]]))
if rep:
    check(rep.get("inverted cells") == "1 (faces listed inward)", "inward cube: %r" % rep.get("inverted cells"))
    check("open cells" not in rep, "inward cube reported open")
    check(close(float(rep["total volume"]), 1.0, 1e-14), "inward cube: volume %r" % rep["total volume"])
    check_stats("inward", "fatness", rep.get("fatness"), {k: math.sqrt(3) for k in STAT_KEYS}, 1e-5)
rep = quality("open", cube_grid([faces, faces[:5]]))
if rep:
    check(re.match(r"1 \(an edge not shared by exactly two faces in opposite directions: .*; first: cell 1\)$",
                   rep.get("open cells", "")), "open cube: %r" % rep.get("open cells"))
rep = quality("mixed orientation", cube_grid([faces[:3] + [f[::-1] for f in faces[3:]]]))
if rep:
    check(rep.get("open cells", "").startswith("1 "), "cube with mixed orientations: %r" % rep.get("open cells"))

# ---- bad input ----------------------------------------------------------------------

def bad(name, args, code, pattern):
    rc, so, se = run(*args)
    lines = se.strip().splitlines()
    check(rc == code, "%s: exit %d, expected %d (stderr %r)" % (name, rc, code, se))
    check(len(lines) >= 1 and lines[0].startswith("vorocrust: "), "%s: stderr %r" % (name, se))
    check(re.search(pattern, se), "%s: stderr %r does not match %r" % (name, se, pattern))


def write_bytes(name, data):
    p = path(name)
    with open(p, "wb") as f:
        f.write(data)
    return p


good = open(path("random_zlib.vtu"), "rb").read()
raw = open(path("random_raw.vtu"), "rb").read()
bad("missing", ["quality", path("nope.vtu")], 1, r"nope\.vtu: cannot open")
bad("empty", ["quality", write_bytes("empty.vtu", b"")], 1, r"empty\.vtu: empty file")
bad("not xml", ["quality", write_bytes("text.vtu", b"hello world\n")], 1, r"text\.vtu: not a VTK XML file")
bad("polydata", ["quality", write_bytes("poly.vtu", b'<?xml version="1.0"?>\n<VTKFile type="PolyData" version="1.0">\n</VTKFile>\n')],
    1, r"poly\.vtu: not an UnstructuredGrid")
bad("truncated", ["quality", write_bytes("trunc.vtu", raw[: len(raw) // 2])], 1, r"trunc\.vtu: .*truncated")
# corrupt the first compressed block of the last array
zpos = good.rfind(b"\x78\x01")
bad("corrupt zlib", ["quality", write_bytes("corrupt.vtu", good[:zpos + 2] + bytes(b ^ 0x5a for b in good[zpos + 2:zpos + 40]) + good[zpos + 40:])],
    1, r"corrupt\.vtu: array '\w+': corrupt zlib block")
bad("lz4", ["quality", write_bytes("lz4.vtu", good.replace(b"vtkZLibDataCompressor", b"vtkLZ4DataCompressor", 1))],
    1, r"lz4\.vtu: compressor 'vtkLZ4DataCompressor' is not supported")
bad("big endian", ["quality", write_bytes("be.vtu", good.replace(b"LittleEndian", b"BigEndian", 1))],
    1, r"be\.vtu: byte_order 'BigEndian' is not supported")
bad("no faces", ["quality", write_bytes("nofaces.vtu", raw.replace(b'Name="faces"', b'Name="xfaces"', 1))],
    1, r"nofaces\.vtu: missing the 'faces' array")
hexonly = vtk.vtkUnstructuredGrid()
hexonly.SetPoints(pts)
hexonly.InsertNextCell(12, hexa)
w = vtk.vtkXMLUnstructuredGridWriter()
w.SetFileName(path("hex.vtu"))
w.SetInputData(hexonly)
w.Write()
bad("only hexahedra", ["quality", path("hex.vtu")], 1, r"hex\.vtu: no polyhedron or tetrahedron")
ascii_tets = open(path("tets_ascii_none_h64_i64.vtu"), "rb").read()
bad("bad ascii number", ["quality", write_bytes("badnum.vtu", ascii_tets.replace(b"RangeMin", b"RangeMin", 1).replace(
    b'format="ascii"', b'format="ascii" x="1"', 1).replace(b"\n          0.", b"\n          zz.", 1))], 1, r"badnum\.vtu: array 'Points': 'zz")
# a point id out of range in the ascii connectivity
m = re.search(rb'Name="connectivity" format="ascii"[^>]*>\s*(\d+)', ascii_tets)
bad("id out of range", ["quality", write_bytes("badid.vtu", ascii_tets[:m.start(1)] + b"99999" + ascii_tets[m.end(1):])],
    1, r"badid\.vtu: cell 0 uses point 99999 out of range")
bad("bad input surface", ["quality", path("random_zlib.vtu"), "--input", path("nope.obj")], 1, r"nope\.obj")
bad("no args", ["quality"], 2, r"missing the mesh")
bad("unknown option", ["quality", path("random_zlib.vtu"), "--frobnicate"], 2, r"unknown option '--frobnicate'")
bad("threads 0", ["quality", path("random_zlib.vtu"), "--threads", "0"], 2, r"--threads: '0'")
bad("input without value", ["quality", path("random_zlib.vtu"), "--input"], 2, r"--input needs a value")
bad("two meshes", ["quality", path("random_zlib.vtu"), path("random_raw.vtu")], 2, r"unexpected argument")
rc, so, se = run("quality", "--help")
check(rc == 0 and "usage: vorocrust quality" in so, "--help: exit %d, %r" % (rc, so))

if failures:
    print("%d failures" % len(failures), file=sys.stderr)
    sys.exit(1)
print("e2e_quality: all checks passed")
