"""End-to-end tests of `vorocrust voronoi` through the CLI.

Every mesh is written by the `vorocrust` executable, read back with Debian's
VTK 9.1 (vtkcheck.check_vtu: every cell a valid convex VTK_POLYHEDRON,
volumes, shared faces, boundary volume) and checked against facts computed
here from the seeds alone:

  (a) random seeds in a box: cell count, box volume (1e-9), cell data
      (region = label, seed = input row, volume = what the faces enclose),
      the connections CSV (one row per shared face, seed distances, unit
      normals, areas and centroids equal to the .vtu faces) and the pyramid
      identity: a cell's volume is the sum over its faces of area * h / 3,
      h the distance from its seed to the face plane (distance / 2 for an
      interior face);
  (b) a cubic lattice: cubes with 6 quads and 8 points, points on the
      lattice, connections of area h^2 and distance h;
  (c) co-spherical seeds built the VoroCrust way (seed pairs at the
      intersections of three equal spheres centred on samples of the unit
      sphere; every sample equidistant to 10-14 seeds), and the bundled
      ball model: every sample is exactly one mesh vertex, the kept volume
      equals the volume enclosed by the mesh boundary (computed from the
      boundary faces, and by VTK's vtkMassProperties), every boundary face
      is the bisector between a kept seed and a label-0 seed;
  (d) labels: label-0 seeds have no cell, and the kept cells are exactly
      the cells of a run where every seed is kept;
  (e) a single seed: one cell filling the box;
  (f) zlib and raw encodings read back to the same mesh; 1 and 2 threads
      give byte-identical files;
  (g) nearly co-spherical seeds (VoroCrust seeds of torus.obj, bracket.obj
      and sphere.obj plus one seed just outside each ball, at 1e-9 to 1e-7
      of its radius): the validator passes, VTK reads every kept cell back;
  and bad input: non-zero exit, one stderr line "vorocrust: ..." naming the
  file and the problem, and no file left behind (not even a temporary).

Usage: e2e_voronoi.py PART (one ctest test per part, tests/CMakeLists.txt):
synthetic ((a) to (f) and the bad input: the repository alone), near_torus,
near_bracket, near_sphere ((g), one model each).

Environment: VC_BIN, VC_SOURCE, VC_TMP, VC_MODELS.
"""
import csv
import glob
import math
import os
import random
import re
import subprocess
import sys

sys.path.insert(0, os.path.join(os.environ["VC_SOURCE"], "tests"))
import vtk  # noqa: E402
import vtkcheck  # noqa: E402

BIN = os.environ["VC_BIN"]
SOURCE = os.environ["VC_SOURCE"]
from e2eutil import models_dir  # noqa: E402

# One part per ctest test (tests/CMakeLists.txt): "synthetic" ((a) to (f)
# and the bad input, from the repository alone) or one model of (g), which
# skips (exit 77) when the shared models are missing.
PARTS = ("synthetic", "near_torus", "near_bracket", "near_sphere")
if len(sys.argv) != 2 or sys.argv[1] not in PARTS:
    print("usage: e2e_voronoi.py PART, PART one of %s" % ", ".join(PARTS), file=sys.stderr)
    sys.exit(2)
PART = sys.argv[1]
TMP = os.path.join(os.environ.get("VC_TMP", "/tmp"), "e2e_voronoi", PART)
os.makedirs(TMP, exist_ok=True)
for old in os.listdir(TMP):
    if os.path.isfile(os.path.join(TMP, old)):
        os.remove(os.path.join(TMP, old))
failures = []

CONN_HEADER = ["cell_i", "cell_j", "seed_i", "seed_j", "area", "distance",
               "cx", "cy", "cz", "nx", "ny", "nz", "region_i", "region_j", "patch"]
BOUNDARY_ROWS = {}  # name -> the boundary rows of its connections


def check(cond, what):
    if not cond:
        failures.append(what)
        print("FAIL:", what, file=sys.stderr)
    return cond


def run(*args):
    p = subprocess.run([BIN, "voronoi", *args], capture_output=True, text=True, timeout=600)
    return p.returncode, p.stdout, p.stderr


def write_seeds(name, rows, labels=True):
    """Writes a seeds file; coordinates with repr() so the file holds exactly
    the doubles the test computes with."""
    path = os.path.join(TMP, name)
    with open(path, "w") as f:
        f.write("x,y,z,label\n" if labels else "x,y,z\n")
        for r in rows:
            xyz = ",".join(repr(float(v)) for v in r[:3])
            f.write(xyz + ("," + str(r[3]) if labels else "") + "\n")
    return path


def read_seeds(path):
    with open(path) as f:
        rows = list(csv.reader(f))[1:]
    return [(float(r[0]), float(r[1]), float(r[2]), int(r[3]) if len(r) > 3 else 1) for r in rows]


def read_connections(name, path):
    with open(path) as f:
        r = list(csv.reader(f))
    check(r and r[0] == CONN_HEADER, "%s: connections header %r" % (name, r[:1]))
    check(all(len(row) == 15 for row in r[1:]), "%s: a connections row has not 15 columns" % name)
    rows = [[int(x) for x in row[:4]] + [float(x) for x in row[4:12]] + [int(x) for x in row[12:14]]
            + [row[14]] for row in r[1:]]
    # interior faces first (patch empty), then the boundary faces (cell_j
    # -1, region_j 0, a patch name)
    inner = [row[:14] for row in rows if row[1] >= 0]
    outer = [row for row in rows if row[1] < 0]
    check(rows[:len(inner)] == [row for row in rows if row[1] >= 0] and
          all(row[14] == "" for row in rows[:len(inner)]) and
          all(row[1] == -1 and row[13] == 0 and row[14] and row[4] > 0 and row[5] > 0 for row in outer),
          "%s: connection rows: interior ones first with no patch, then boundary ones with cell_j -1, "
          "region_j 0, a patch, area and distance > 0" % name)
    BOUNDARY_ROWS[name] = outer
    return inner


def mesh(name, seeds_path, *opts, cells=None, volume=None, connections=False):
    """Runs the CLI and checks the exit code, the validator's verdict and the
    .vtu with VTK. Returns (figures, grid, connection rows) or Nones."""
    out = os.path.join(TMP, name + ".vtu")
    args = [seeds_path, "-o", out, *opts]
    conn = os.path.join(TMP, name + "_connections.csv")
    if connections:
        args += ["--connections", conn]
    rc, so, se = run(*args)
    if not check(rc == 0, "%s: exit %d, stderr %r" % (name, rc, se)):
        return None, None, None
    check("validation passed" in so + se, "%s: validator did not pass: %r" % (name, se))
    check_header(name, out)
    try:
        fig = vtkcheck.check_vtu(out, expected_cells=cells, expected_volume=volume)
    except vtkcheck.CheckError as e:
        check(False, "%s: %s" % (name, e))
        return None, None, None
    grid = vtkcheck.read_vtu(out)
    rows = read_connections(name, conn) if connections else None
    if rows is not None:
        check(len(BOUNDARY_ROWS[name]) == fig["n_faces_boundary"],
              "%s: %d boundary connection rows, VTK sees %d boundary faces"
              % (name, len(BOUNDARY_ROWS[name]), fig["n_faces_boundary"]))
    return fig, grid, rows


def check_header(name, path):
    """The XML header: file version 1.0, UInt64 headers, Int32 ids (every
    index of these meshes fits), the polyhedron arrays and the four
    cell-data arrays with their types."""
    with open(path, "rb") as f:
        head = f.read(8192).split(b"<AppendedData")[0].decode()
    check('version="1.0"' in head and 'header_type="UInt64"' in head,
          "%s: VTKFile header %r" % (name, head[:200]))
    arrays = dict((n, t) for t, n in re.findall(r'<DataArray type="(\w+)" Name="(\w+)"', head))
    want = {"region": "Int32", "seed": "Int64", "volume": "Float64", "seed_point": "Float64",
            "Points": "Float64", "connectivity": "Int32", "offsets": "Int32", "types": "UInt8",
            "faces": "Int32", "faceoffsets": "Int32"}
    check(arrays == want, "%s: arrays %r, expected %r" % (name, arrays, want))


# ---- geometry of the faces in a .vtu ----

def face_geometry(grid, face):
    """(area, centroid, unit normal) of a planar polygon given as point ids,
    the normal following the vertex order (Newell), the centroid the area
    centroid of a fan around the vertex mean."""
    p = [grid.GetPoint(i) for i in face]
    m = [sum(x[k] for x in p) / len(p) for k in range(3)]
    n = [0.0, 0.0, 0.0]
    c = [0.0, 0.0, 0.0]
    area = 0.0
    for a, b in zip(p, p[1:] + p[:1]):
        u = [a[k] - m[k] for k in range(3)]
        v = [b[k] - m[k] for k in range(3)]
        t = [u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]]
        n = [n[k] + t[k] for k in range(3)]
        ta = math.sqrt(sum(x * x for x in t)) / 2
        area += ta
        c = [c[k] + ta * (m[k] + a[k] + b[k]) / 3 for k in range(3)]
    ln = math.sqrt(sum(x * x for x in n))
    return ln / 2, [x / area for x in c], [x / ln for x in n]


class Faces:
    """The faces of a .vtu mesh: per_cell[c] = c's faces (point-id lists,
    outward for c); shared[(a, b)] = the face between cells a < b, as seen
    from a; boundary[c] = c's faces that belong to no other cell."""

    def __init__(self, name, grid):
        ids = vtk.vtkIdList()
        n = grid.GetNumberOfCells()
        self.per_cell = [vtkcheck.cell_faces(grid, c, ids) for c in range(n)]
        first = {}
        self.shared = {}
        for c, faces in enumerate(self.per_cell):
            for f in faces:
                key = tuple(sorted(f))
                if key not in first:
                    first[key] = (c, f)
                    continue
                a, fa = first.pop(key)
                check((a, c) not in self.shared, "%s: cells %d and %d share two faces" % (name, a, c))
                self.shared[(a, c)] = fa  # a < c: cells are visited in order
        self.boundary = [[] for _ in range(n)]
        for c, f in first.values():
            self.boundary[c].append(f)


def check_cell_data(name, grid, seeds):
    """seed = rows of the kept seeds in input order; region = their labels."""
    seed_ids = vtkcheck.cell_array(grid, "seed")
    region = vtkcheck.cell_array(grid, "region")
    want = [i for i, s in enumerate(seeds) if s[3] != 0]
    check(seed_ids == want, "%s: seed ids are not the kept rows in order (%d cells, %d kept)"
          % (name, len(seed_ids or []), len(want)))
    if seed_ids == want:
        check(region == [seeds[i][3] for i in seed_ids], "%s: region is not the seed's label" % name)
    return seed_ids


def check_connections(name, seeds, grid, rows, fig, faces):
    """The connections CSV against the seeds file and the .vtu: one row per
    shared face; cells and seeds consistent with the cell data; area,
    centroid and normal equal to the .vtu face's; distance = the seed
    distance (recomputed here); unit normal along the seed pair."""
    seed_ids = vtkcheck.cell_array(grid, "seed")
    check(len(rows) == fig["n_faces_shared"] == len(faces.shared),
          "%s: %d connections, VTK sees %d shared faces" % (name, len(rows), fig["n_faces_shared"]))
    seen = set()
    worst = {"distance": 0.0, "normal length": 0.0, "normal vs seeds": 0.0,
             "normal vs face": 0.0, "area vs face": 0.0, "centroid vs face": 0.0,
             "centroid off bisector": 0.0}
    region = vtkcheck.cell_array(grid, "region")
    for ci, cj, si, sj, area, dist, cx, cy, cz, nx, ny, nz, ri, rj in rows:
        if not check(0 <= ci < cj < len(seed_ids) and (ci, cj) not in seen and area > 0,
                     "%s: row %d,%d area %r (order, range, repeat or area)" % (name, ci, cj, area)):
            return
        seen.add((ci, cj))
        if not check(ri == region[ci] and rj == region[cj],
                     "%s: row %d,%d has regions %d,%d, the .vtu says %d,%d"
                     % (name, ci, cj, ri, rj, region[ci], region[cj])):
            return
        if not check(si == seed_ids[ci] and sj == seed_ids[cj],
                     "%s: row %d,%d has seeds %d,%d, the .vtu says %d,%d"
                     % (name, ci, cj, si, sj, seed_ids[ci], seed_ids[cj])):
            return
        a, b = seeds[si], seeds[sj]
        d = [b[k] - a[k] for k in range(3)]
        dn = math.sqrt(sum(x * x for x in d))
        n = (nx, ny, nz)
        c = (cx, cy, cz)
        worst["distance"] = max(worst["distance"], abs(dist - dn) / dn)
        worst["normal length"] = max(worst["normal length"], abs(math.hypot(*n) - 1.0))
        worst["normal vs seeds"] = max(worst["normal vs seeds"],
                                       max(abs(n[k] - d[k] / dn) for k in range(3)))
        face = faces.shared.get((ci, cj))
        if not check(face is not None, "%s: row %d,%d: no face between these cells" % (name, ci, cj)):
            return
        fa, fc, fn = face_geometry(grid, face)  # outward for ci: from ci to cj
        worst["normal vs face"] = max(worst["normal vs face"], 1.0 - sum(x * y for x, y in zip(n, fn)))
        worst["area vs face"] = max(worst["area vs face"], abs(area - fa) / fa)
        worst["centroid vs face"] = max(worst["centroid vs face"], math.dist(c, fc) / math.sqrt(fa))
        mid = [(a[k] + b[k]) / 2 for k in range(3)]
        worst["centroid off bisector"] = max(
            worst["centroid off bisector"], abs(sum((c[k] - mid[k]) * d[k] for k in range(3))) / dn ** 2)
    # Distances and normals come from the seeds and are exact; the rest is
    # face geometry after the vertex merge (1e-8 of the cell size or finer).
    limits = {"distance": 1e-12, "normal length": 1e-12, "normal vs seeds": 1e-12,
              "normal vs face": 1e-9, "area vs face": 1e-9, "centroid vs face": 1e-9,
              "centroid off bisector": 1e-9}
    bad = {k: v for k, v in worst.items() if not v <= limits[k]}
    check(not bad, "%s: connection figures off (worst relative errors): %r" % (name, bad))
    print("%s: connections, worst relative errors %s" % (
        name, ", ".join("%s %.2g" % kv for kv in worst.items())))


def check_pyramids(name, seeds, grid, rows, faces):
    """Pyramid identity: a cell's volume = sum over its faces of
    area * h / 3, h the distance from its seed to the face plane. For an
    interior face h = distance / 2 and the area is the connection's (no .vtu
    geometry enters); boundary faces are measured in the .vtu."""
    seed_ids = vtkcheck.cell_array(grid, "seed")
    vols = vtkcheck.cell_array(grid, "volume")
    terms = [[] for _ in seed_ids]
    for ci, cj, si, sj, area, dist, *_ in rows:
        terms[ci].append(area * dist / 6)
        terms[cj].append(area * dist / 6)
    worst = [0.0, 0.0]  # cells with only interior faces, the others
    for c, s in enumerate(seed_ids):
        for f in faces.boundary[c]:
            fa, fc, fn = face_geometry(grid, f)
            h = sum((fc[k] - seeds[s][k]) * fn[k] for k in range(3))
            check(h > 0, "%s: cell %d: its seed is not inside boundary face %s" % (name, c, f))
            terms[c].append(fa * h / 3)
        k = 1 if faces.boundary[c] else 0
        worst[k] = max(worst[k], abs(math.fsum(terms[c]) - vols[c]) / vols[c])
    inner = sum(1 for b in faces.boundary if not b)
    check(max(worst) <= 1e-9, "%s: pyramid identity off by %.3g (interior cells), %.3g (others)"
          % (name, worst[0], worst[1]))
    print("%s: pyramid identity: %d interior cells within %.2g, %d others within %.2g"
          % (name, inner, worst[0], len(seed_ids) - inner, worst[1]))
    return inner


def on_box(grid, face, box):
    """Whether every point of face lies on one side of box (1e-12)."""
    if box is None:
        return False
    for k in range(3):
        for side in (0, 3):
            if all(abs(grid.GetPoint(p)[k] - box[k + side]) <= 1e-12 * (box[k + 3] - box[k])
                   for p in face):
                return True
    return False


def check_boundary_mirrors(name, seeds, grid, faces, box=None):
    """Every boundary face off the box is the bisector between its cell's
    seed and a label-0 seed: the seed reflected across the face plane is a
    label-0 seed. Returns the number of such faces."""
    seed_ids = vtkcheck.cell_array(grid, "seed")
    dropped = [s for s in seeds if s[3] == 0]
    loc = None
    if dropped:
        pts = vtk.vtkPoints()
        for s in dropped:
            pts.InsertNextPoint(s[:3])
        pd = vtk.vtkPolyData()
        pd.SetPoints(pts)
        loc = vtk.vtkPointLocator()
        loc.SetDataSet(pd)
        loc.BuildLocator()
    n = 0
    worst = 0.0
    for c, s in enumerate(seed_ids):
        for f in faces.boundary[c]:
            if on_box(grid, f, box):
                continue
            n += 1
            if not check(loc is not None, "%s: boundary face off the box, no label-0 seed" % name):
                return n
            fa, fc, fn = face_geometry(grid, f)
            h = sum((fc[k] - seeds[s][k]) * fn[k] for k in range(3))
            mirror = [seeds[s][k] + 2 * h * fn[k] for k in range(3)]
            j = loc.FindClosestPoint(mirror)
            worst = max(worst, math.dist(mirror, dropped[j][:3]) / (2 * h))
    check(worst < 1e-9, "%s: a boundary face is not the bisector with a label-0 seed (%.3g)"
          % (name, worst))
    return n


def full_checks(name, seeds, fig, grid, rows, box=None):
    """Cell data, connections, pyramid identity, boundary mirrors. Returns
    (faces, number of cells with only interior faces, boundary faces off
    the box)."""
    check_cell_data(name, grid, seeds)
    faces = Faces(name, grid)
    check_connections(name, seeds, grid, rows, fig, faces)
    inner = check_pyramids(name, seeds, grid, rows, faces)
    mirrors = check_boundary_mirrors(name, seeds, grid, faces, box)
    return faces, inner, mirrors


def grid_content(grid):
    """Everything a reader gets from a .vtu: points, cell types, face
    streams, cell data."""
    ids = vtk.vtkIdList()
    n = grid.GetNumberOfCells()
    return {
        "points": [grid.GetPoint(i) for i in range(grid.GetNumberOfPoints())],
        "types": [grid.GetCellType(c) for c in range(n)],
        "faces": [vtkcheck.cell_faces(grid, c, ids) for c in range(n)],
        "region": vtkcheck.cell_array(grid, "region"),
        "seed": vtkcheck.cell_array(grid, "seed"),
        "volume": vtkcheck.cell_array(grid, "volume"),
    }


def vorocrust_sphere_seeds(n=300, r=0.2, h=0.15):
    """Seeds of the unit sphere built the VoroCrust way: balls of radius r
    centred on n samples of the sphere (Fibonacci spiral); for every three
    balls whose spheres meet, their two intersection points (one inside the
    sphere, label 1, and its mirror image across the plane of the three
    centres, outside, label 0), kept unless strictly inside a fourth ball;
    interior seeds on a lattice of spacing h, outside every ball (label 1).
    Every sample is then equidistant (r) to all the seeds on its sphere, 10
    to 14 of them, and no seed is closer: a degenerate Voronoi vertex.
    Returns (samples, seeds)."""
    golden = math.pi * (3.0 - math.sqrt(5.0))
    q = []
    for i in range(n):
        z = 1.0 - 2.0 * (i + 0.5) / n
        s = math.sqrt(1.0 - z * z)
        q.append((s * math.cos(golden * i), s * math.sin(golden * i), z))

    def sub(a, b):
        return (a[0] - b[0], a[1] - b[1], a[2] - b[2])

    def dot(a, b):
        return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]

    def cross(a, b):
        return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])

    nb = [{j for j in range(n) if j != i and math.dist(q[i], q[j]) < 2 * r} for i in range(n)]
    seeds = []
    seen = set()
    for i in range(n):
        for j in sorted(nb[i]):
            if j <= i:
                continue
            for k in sorted(nb[i] & nb[j]):
                if k <= j:
                    continue
                a = q[i]
                ab, ac = sub(q[j], a), sub(q[k], a)
                nrm = cross(ab, ac)
                nn = dot(nrm, nrm)
                t1, t2 = cross(nrm, ab), cross(ac, nrm)
                cc = tuple(a[m] + (dot(ab, ab) * t2[m] + dot(ac, ac) * t1[m]) / (2 * nn)
                           for m in range(3))  # circumcentre of the three centres
                rho2 = dot(sub(cc, a), sub(cc, a))
                if rho2 >= r * r:
                    continue
                hgt = math.sqrt(r * r - rho2) / math.sqrt(nn)
                for sgn in (1, -1):
                    p = tuple(cc[m] + sgn * hgt * nrm[m] for m in range(3))
                    if any(math.dist(p, q[m]) < r * (1 - 1e-9) for m in nb[i] | nb[j] | nb[k]
                           if m not in (i, j, k)):
                        continue
                    key = tuple(round(x, 7) for x in p)
                    if key not in seen:  # four co-circular centres: one seed
                        seen.add(key)
                        seeds.append((p[0], p[1], p[2], 1 if dot(p, p) < 1 else 0))
    m = int(1 / h) + 1
    for i in range(-m, m + 1):
        for j in range(-m, m + 1):
            for k in range(-m, m + 1):
                p = (i * h + 0.011, j * h + 0.005, k * h + 0.007)
                if math.sqrt(dot(p, p)) < 1 - r - 0.02:
                    seeds.append((p[0], p[1], p[2], 1))
    return q, seeds


if PART == "synthetic":
    # =========================================================================
    # (a) Random seeds in a box, with connections; labels 1..3 (all kept)
    # =========================================================================
    rng = random.Random(7)
    box = (-1.0, 0.0, 0.5, 2.0, 1.5, 2.5)
    vol_box = (box[3] - box[0]) * (box[4] - box[1]) * (box[5] - box[2])
    N_RAND = 3000
    rand = [(rng.uniform(box[0], box[3]), rng.uniform(box[1], box[4]), rng.uniform(box[2], box[5]),
             rng.randint(1, 3)) for _ in range(N_RAND)]
    p_rand = write_seeds("random.csv", rand)
    fig, grid, rows = mesh("random", p_rand, "--box", *map(str, box), cells=N_RAND, volume=vol_box,
                           connections=True)
    if fig:
        faces, inner, mirrors = full_checks("random", rand, fig, grid, rows, box)
        check(inner > 1000, "random: only %d cells away from the walls" % inner)
        check(mirrors == 0, "random: %d boundary faces off the box" % mirrors)
        # Every boundary face is on the box, and they tile its six sides.
        wall_area = math.fsum(face_geometry(grid, f)[0] for b in faces.boundary for f in b)
        sides = 2 * ((box[3] - box[0]) * (box[4] - box[1]) + (box[4] - box[1]) * (box[5] - box[2])
                     + (box[3] - box[0]) * (box[5] - box[2]))
        check(abs(wall_area - sides) <= 1e-9 * sides, "random: boundary area %r, box sides %r"
              % (wall_area, sides))

    # Without --box: the box is the seeds' bounding box grown by its diagonal.
    sub = rand[:200]
    p_sub = write_seeds("random_nobox.csv", sub)
    lo = [min(s[k] for s in sub) for k in range(3)]
    hi = [max(s[k] for s in sub) for k in range(3)]
    diag = math.dist(lo, hi)
    mesh("random_nobox", p_sub, cells=200,
         volume=math.prod(hi[k] - lo[k] + 2 * diag for k in range(3)))

    # =========================================================================
    # (f) The same seeds: raw and zlib encodings, 1 and 2 threads
    # =========================================================================
    for enc in ("raw", "zlib"):
        for t in ("1", "2"):
            out = os.path.join(TMP, "det_%s_%s.vtu" % (enc, t))
            conn = os.path.join(TMP, "det_%s_%s.csv" % (enc, t))
            rc, _, se = run(p_rand, "--box", *map(str, box), "-o", out, "--encoding", enc,
                            "--threads", t, "--connections", conn, "--quiet")
            check(rc == 0 and se == "", "determinism %s %s: exit %d %r" % (enc, t, rc, se))


    def read_bytes(name):
        with open(os.path.join(TMP, name), "rb") as f:
            return f.read()


    for enc in ("raw", "zlib"):
        check(read_bytes("det_%s_1.vtu" % enc) == read_bytes("det_%s_2.vtu" % enc),
              "%s: 1 and 2 threads give different .vtu files" % enc)
        check(read_bytes("det_%s_1.csv" % enc) == read_bytes("det_%s_2.csv" % enc),
              "%s: 1 and 2 threads give different connection files" % enc)
    check(read_bytes("det_raw_1.csv") == read_bytes("random_connections.csv"),
          "connections differ between runs")
    check(len(read_bytes("det_zlib_1.vtu")) < len(read_bytes("det_raw_1.vtu")),
          "zlib file is not smaller than raw")
    try:
        vtkcheck.check_vtu(os.path.join(TMP, "det_raw_1.vtu"), expected_cells=N_RAND,
                           expected_volume=vol_box)
        graw = grid_content(vtkcheck.read_vtu(os.path.join(TMP, "det_raw_1.vtu")))
        gz = grid_content(vtkcheck.read_vtu(os.path.join(TMP, "det_zlib_1.vtu")))
        diff = [k for k in graw if graw[k] != gz[k]]
        check(not diff, "raw and zlib read back differently: %s" % diff)
    except vtkcheck.CheckError as e:
        check(False, "encodings: %s" % e)

    # =========================================================================
    # (b) Cubic lattice: cubes with exactly 6 faces and 8 points
    # =========================================================================
    k = 5
    hl = 0.5
    org = (-1.0, 2.0, 3.0)
    lattice = [(org[0] + (i + 0.5) * hl, org[1] + (j + 0.5) * hl, org[2] + (m + 0.5) * hl, 1)
               for m in range(k) for j in range(k) for i in range(k)]
    p_lat = write_seeds("lattice.csv", lattice)
    lbox = (*org, *(o + k * hl for o in org))
    fig, grid, rows = mesh("lattice", p_lat, "--box", *map(str, lbox), cells=k ** 3,
                           volume=(k * hl) ** 3, connections=True)
    if fig:
        full_checks("lattice", lattice, fig, grid, rows, lbox)
        check(fig["n_points"] == (k + 1) ** 3, "lattice: %d points" % fig["n_points"])
        off_grid = max(abs((grid.GetPoint(i)[d] - org[d]) / hl - round((grid.GetPoint(i)[d] - org[d]) / hl))
                       for i in range(grid.GetNumberOfPoints()) for d in range(3))
        check(off_grid < 1e-12, "lattice: a point is %.3g off the lattice" % off_grid)
        for c in range(k ** 3):
            cf = vtkcheck.cell_faces(grid, c)
            pts = {p for f in cf for p in f}
            if not check(len(cf) == 6 and len(pts) == 8 and all(len(f) == 4 for f in cf),
                         "lattice: cell %d has %d faces, %d points" % (c, len(cf), len(pts))):
                break
        check(len(rows) == 3 * k * k * (k - 1), "lattice: %d connections" % len(rows))
        check(all(abs(r[4] - hl * hl) < 1e-12 and abs(r[5] - hl) < 1e-12 for r in rows),
              "lattice: a connection's area is not h^2 or its distance not h")

    # =========================================================================
    # (c) Co-spherical seeds, built the VoroCrust way, and the bundled ball
    # =========================================================================
    samples, crust = vorocrust_sphere_seeds()
    kept = sum(1 for s in crust if s[3])
    p_crust = write_seeds("crust.csv", crust)
    fig, grid, rows = mesh("crust", p_crust, cells=kept, connections=True)
    if fig:
        faces, inner, mirrors = full_checks("crust", crust, fig, grid, rows)
        # Every boundary face separates an inner seed from its outer twin, and
        # there is no box face (the outer seeds enclose the kept cells).
        check(mirrors == fig["n_faces_boundary"] > 0,
              "crust: %d of %d boundary faces are seed bisectors" % (mirrors, fig["n_faces_boundary"]))
        # Each sample is one mesh vertex (the degenerate Voronoi vertex), not
        # several copies within the merge tolerance.
        loc = vtk.vtkPointLocator()
        loc.SetDataSet(grid)
        loc.BuildLocator()
        ids = vtk.vtkIdList()
        worst, copies = 0.0, 0
        for q in samples:
            worst = max(worst, math.dist(grid.GetPoint(loc.FindClosestPoint(q)), q))
            loc.FindPointsWithinRadius(1e-6, q, ids)
            copies = max(copies, ids.GetNumberOfIds())
        check(worst < 1e-9 and copies == 1,
              "crust: samples as mesh vertices: farthest %.3g, up to %d copies" % (worst, copies))
        on_sphere = [sum(1 for s in crust if abs(math.dist(s[:3], q) - 0.2) < 1e-9) for q in samples]
        check(min(on_sphere) >= 4, "crust: a sample has only %d seeds on its sphere" % min(on_sphere))
        # Independent volumes: the boundary surface (VTK's vtkGeometryFilter +
        # vtkMassProperties, and the boundary faces in check_vtu) encloses what
        # the cells sum to; and it approximates the unit ball.
        tv, bv = fig["total_volume"], fig["vtk_boundary_volume"]
        check(abs(tv - bv) <= 1e-9 * tv, "crust: cells %r, vtkMassProperties on the boundary %r"
              % (tv, bv))
        check(abs(tv - 4 * math.pi / 3) < 0.03 * 4 * math.pi / 3, "crust: volume %r, ball %r"
              % (tv, 4 * math.pi / 3))
        print("crust: %d seeds (%d kept), %d samples with %d-%d seeds on their sphere, volume %.15g "
              "(boundary by VTK %.15g), %d cells VTK's size filter gets wrong"
              % (len(crust), kept, len(samples), min(on_sphere), max(on_sphere), tv, bv,
                 fig["vtk_volume_off"]))
    # Every seed kept, in a box: the cells fill the box exactly.
    p_crust1 = write_seeds("crust_all.csv", [(x, y, z, 1) for x, y, z, _ in crust])
    mesh("crust_all", p_crust1, "--box", "-1.5", "-1.5", "-1.5", "1.5", "1.5", "1.5",
         cells=len(crust), volume=27.0)

    p_ball = os.path.join(SOURCE, "models", "ball-seeds.csv")
    ball = read_seeds(p_ball)
    kept = sum(1 for s in ball if s[3] != 0)
    fig, grid, rows = mesh("ball", p_ball, cells=kept, connections=True)
    if fig:
        faces, inner, mirrors = full_checks("ball", ball, fig, grid, rows)
        check(mirrors == fig["n_faces_boundary"] > 0,
              "ball: %d of %d boundary faces are seed bisectors" % (mirrors, fig["n_faces_boundary"]))
        tv = fig["total_volume"]
        check(abs(tv - fig["vtk_boundary_volume"]) <= 1e-9 * tv,
              "ball: cells %r, boundary %r" % (tv, fig["vtk_boundary_volume"]))
        check(abs(tv - 4 * math.pi / 3) < 0.05 * 4 * math.pi / 3,
              "ball: volume %r, unit ball %r" % (tv, 4 * math.pi / 3))

    # =========================================================================
    # (d) Labels: label-0 seeds have no cell; the kept cells are the cells of
    #     a run where every seed is kept
    # =========================================================================
    rng = random.Random(11)
    lab = [(rng.random(), rng.random(), rng.random(), rng.choice((0, 1, 2))) for _ in range(1500)]
    ubox = ("0", "0", "0", "1", "1", "1")
    p_lab = write_seeds("labels.csv", lab)
    p_all = write_seeds("labels_all.csv", [(x, y, z, 1) for x, y, z, _ in lab])
    kept = [i for i, s in enumerate(lab) if s[3]]
    fig, grid, rows = mesh("labels", p_lab, "--box", *ubox, cells=len(kept), connections=True)
    fig_all, grid_all, rows_all = mesh("labels_all", p_all, "--box", *ubox, cells=len(lab), volume=1.0,
                                       connections=True)
    if fig and fig_all:
        faces, inner, mirrors = full_checks("labels", lab, fig, grid, rows, (0, 0, 0, 1, 1, 1))
        check(mirrors > 0, "labels: no boundary face between kept and dropped seeds")
        vol_all = vtkcheck.cell_array(grid_all, "volume")
        vol = vtkcheck.cell_array(grid, "volume")
        worst = max(abs(v - vol_all[s]) / vol_all[s] for v, s in zip(vol, kept))
        check(worst < 1e-12, "labels: kept cells' volumes differ from the all-kept run by %.3g" % worst)
        # Connections: those of the all-kept run whose two seeds are kept.
        by_seeds = {(r[2], r[3]): r[4] for r in rows_all}
        sub_rows = {(r[2], r[3]): r[4] for r in rows}
        want = {key: a for key, a in by_seeds.items() if lab[key[0]][3] and lab[key[1]][3]}
        check(set(sub_rows) == set(want), "labels: connections are not the kept pairs of the all-kept run")
        if set(sub_rows) == set(want):
            worst = max(abs(sub_rows[key] - want[key]) / want[key] for key in want)
            check(worst < 1e-12, "labels: connection areas differ from the all-kept run by %.3g" % worst)

    # =========================================================================
    # (e) A single seed, no label column: one cell filling the box
    # =========================================================================
    p_one = write_seeds("one.csv", [(0.1, 0.2, 0.3)], labels=False)
    fig, grid, rows = mesh("one", p_one, "--box", "0", "0", "0", "1", "2", "3", cells=1, volume=6.0,
                           connections=True)
    if fig:
        check(fig["n_points"] == 8 and fig["n_faces_boundary"] == 6 and rows == [],
              "one: %d points, %d faces, %d connections" % (fig["n_points"], fig["n_faces_boundary"],
                                                              len(rows)))
        check_cell_data("one", grid, [(0.1, 0.2, 0.3, 1)])
    # Without --box a lone seed has no extent: the box is 1 from it on every side.
    mesh("one_nobox", p_one, cells=1, volume=8.0)


if PART != "synthetic":
    # =========================================================================
    # (g) Nearly co-spherical: a model's VoroCrust seeds plus, for each ball,
    #     a seed at (1 + eps) r from its centre along the inward normal, just
    #     outside the sphere on which the ball's seeds lie. Every ball centre is
    #     then a cluster of Voronoi vertices eps * r across, at the scale of the
    #     merge tolerance (the tolerance engine of sessions 1 to 17 needed
    #     repair passes here, and still refused torus seed 1 at 5e-8). Every
    #     set must mesh, validate and read back.
    # =========================================================================
    MODELS = models_dir()
    # (model, random seed of the sampling, eps values): torus seed 1 at 1e-8,
    # 3e-8 and 5e-8, bracket seed 3 at 5e-8 and 1e-7 and sphere seed 2 at 3e-8
    # failed the tolerance engine before it collapsed open cells' clusters.
    NEAR_COSPHERICAL = [("torus.obj", 1, (1e-9, 3e-9, 1e-8, 3e-8, 5e-8, 1e-7)),
                        ("bracket.obj", 3, (5e-8, 1e-7)),
                        ("sphere.obj", 2, (3e-8,))]
    for model, sample_seed, eps_values in NEAR_COSPHERICAL:
        if PART != "near_" + model.split(".")[0]:
            continue
        stem = "%s_%d" % (model.split(".")[0], sample_seed)
        t_seeds = os.path.join(TMP, stem + "_seeds.csv")
        t_balls = os.path.join(TMP, stem + "_balls.csv")
        p = subprocess.run([BIN, "mesh", os.path.join(MODELS, model), "--surface-only",
                            "--surface", os.path.join(TMP, stem + ".obj"), "--seed", str(sample_seed),
                            "--seeds", t_seeds, "--balls", t_balls, "--quiet"],
                           capture_output=True, text=True, timeout=600)
        if not check(p.returncode == 0, "%s seeds: exit %d: %s" % (stem, p.returncode, p.stderr[-500:])):
            continue
        base = read_seeds(t_seeds)
        with open(t_balls) as f:
            balls = [[float(v) for v in r[:4]] + [float(v) for v in r[6:9]] for r in list(csv.reader(f))[1:]]
        for eps in eps_values:
            extra = [tuple(b[d] - (1 + eps) * b[3] * b[4 + d] for d in range(3)) + (1,) for b in balls]
            name = "near_cospherical_%s_%g" % (stem, eps)
            path = write_seeds(name + ".csv", base + extra)
            n_kept = sum(1 for r in base + extra if r[3] != 0)
            out = os.path.join(TMP, name + ".vtu")
            if os.path.exists(out):
                os.remove(out)
            rc, so, se = run(path, "-o", out)
            if check(rc == 0 and "validation passed" in so + se,
                     "%s: exit %d: %s" % (name, rc, se[-800:])):
                grid = vtkcheck.read_vtu(out)
                check(grid.GetNumberOfCells() == n_kept,
                      "%s: %d cells read back, %d kept seeds" % (name, grid.GetNumberOfCells(), n_kept))
                print("%s: %d cells, validation passed, read back by VTK" % (name, grid.GetNumberOfCells()))

if PART == "synthetic":
    # =========================================================================
    # Bad input: non-zero exit, one stderr line "vorocrust: ..." naming the
    # file and the problem, no output file left behind (not even a temporary)
    # =========================================================================
    def expect_error(name, args, needles, names_file):
        out = os.path.join(TMP, "bad_%s.vtu" % name)
        conn = os.path.join(TMP, "bad_%s.csv" % name)
        before = set(os.listdir(TMP))
        args = [{"OUT": out, "CONN": conn}.get(a, a) for a in args]
        rc, so, se = run(*args)
        lines = se.strip("\n").split("\n") if se else []
        check(rc != 0, "%s: exit code 0" % name)
        check(len(lines) == 1 and lines[0].startswith("vorocrust: ")
              and all(n in lines[0] for n in needles)
              and (names_file is None or names_file in lines[0]),
              "%s: stderr %r should be one line 'vorocrust: ' naming %r with %r"
              % (name, se, names_file, needles))
        check(so == "", "%s: stdout %r" % (name, so))
        left = set(os.listdir(TMP)) - before
        check(not left, "%s: left %r behind" % (name, sorted(left)))
        return lines[0] if lines else ""


    def bad_file(name, text):
        path = os.path.join(TMP, name)
        with open(path, "w") as f:
            f.write(text)
        return path


    missing = os.path.join(TMP, "no_such_seeds.csv")
    expect_error("missing", [missing, "-o", "OUT"], ["cannot open"], missing)
    f = bad_file("empty.csv", "")
    expect_error("empty", [f, "-o", "OUT"], ["empty"], f)
    f = bad_file("header_only.csv", "x,y,z\n")
    expect_error("header_only", [f, "-o", "OUT"], ["no seeds"], f)
    f = bad_file("malformed.csv", "x,y,z\n0,0,0\n1,abc,0\n")
    expect_error("malformed", [f, "-o", "OUT"], [":3:", "abc", "not a number"], f)
    f = bad_file("nan.csv", "x,y,z\n0,0,0\n1,nan,0\n")
    expect_error("nan", [f, "-o", "OUT"], [":3:", "nan", "not finite"], f)
    f = bad_file("inf.csv", "x,y,z\n0,0,0\n1,1,1e400\n")
    expect_error("inf", [f, "-o", "OUT"], [":3:", "not finite"], f)
    f = bad_file("two_columns.csv", "x,y\n0,0\n1,1\n")
    expect_error("two_columns", [f, "-o", "OUT"], [":2:", "found 2"], f)
    f = bad_file("bad_label.csv", "x,y,z,label\n0,0,0,1\n1,1,1,1.5\n")
    expect_error("bad_label", [f, "-o", "OUT"], [":3:", "label"], f)
    f = bad_file("all_dropped.csv", "x,y,z,label\n0,0,0,0\n1,1,1,0\n")
    expect_error("all_dropped", [f, "-o", "OUT", "--connections", "CONN"], ["no kept seed"], f)
    f = bad_file("duplicates.csv", "x,y,z\n0,0,0\n0.5,0.5,0.5\n0,0,0\n")
    expect_error("duplicates", [f, "-o", "OUT", "--connections", "CONN"], ["seeds 0 and 2", "coincide"], f)
    f = bad_file("outside.csv", "x,y,z\n0.5,0.5,0.5\n3,0.5,0.5\n")
    expect_error("outside", [f, "--box", "0", "0", "0", "1", "1", "1", "-o", "OUT"],
                 ["seed 1", "outside the box"], f)
    expect_error("seeds_dir", [TMP, "-o", "OUT"], ["is a directory"], TMP)
    expect_error("inverted_box", [p_one, "--box", "1", "0", "0", "0", "1", "1", "-o", "OUT"],
                 ["--box", "axis x"], None)
    expect_error("box_nan", [p_one, "--box", "0", "0", "0", "1", "nan", "1", "-o", "OUT"],
                 ["--box", "nan"], None)
    expect_error("box_short", [p_one, "-o", "OUT", "--box", "0", "0", "0", "1"], ["--box", "6"], None)
    expect_error("threads_0", [p_one, "--threads", "0", "-o", "OUT"], ["--threads", "'0'"], None)
    expect_error("threads_abc", [p_one, "--threads", "abc", "-o", "OUT"], ["--threads", "'abc'"], None)
    expect_error("encoding", [p_one, "--encoding", "gzip", "-o", "OUT"], ["--encoding", "gzip"], None)
    expect_error("no_output", [p_one], ["missing -o"], None)
    expect_error("o_without_value", [p_one, "-o"], ["-o needs a value"], None)
    expect_error("no_seeds_arg", ["-o", "OUT"], ["missing the seeds file"], None)
    expect_error("two_seeds_args", [p_one, p_one, "-o", "OUT"], ["unexpected argument"], p_one)
    expect_error("unknown_option", [p_one, "--frobnicate", "-o", "OUT"], ["unknown option", "--frobnicate"],
                 None)
    expect_error("same_outputs", [p_one, "-o", "OUT", "--connections", "OUT"], ["both"], None)
    os.makedirs(os.path.join(TMP, "a_directory.vtu"), exist_ok=True)
    expect_error("output_is_dir", [p_one, "-o", os.path.join(TMP, "a_directory.vtu")],
                 ["Is a directory"], os.path.join(TMP, "a_directory.vtu"))
    os.rmdir(os.path.join(TMP, "a_directory.vtu"))
    nodir = os.path.join(TMP, "no_such_dir", "x.vtu")
    line = expect_error("output_no_dir", [p_one, "-o", nodir], ["cannot write"], nodir)
    nodir_conn = os.path.join(TMP, "no_such_dir", "c.csv")
    expect_error("connections_no_dir", [p_one, "-o", "OUT", "--connections", nodir_conn],
                 ["cannot write"], nodir_conn)
    check(not glob.glob(os.path.join(TMP, "no_such_dir*")), "missing directory: something was created")

if failures:
    print("e2e_voronoi: %d failure(s)" % len(failures), file=sys.stderr)
    sys.exit(1)
print("e2e_voronoi %s: all passed" % PART)
