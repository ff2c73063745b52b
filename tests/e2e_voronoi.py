"""End-to-end tests of `vorocrust voronoi`: meshes written by the CLI and
read back with Debian's VTK 9.1, connection files checked against the
seeds, and bad input refused cleanly. Environment: VC_BIN, VC_SOURCE,
VC_TMP."""
import csv
import glob
import math
import os
import random
import subprocess
import sys

sys.path.insert(0, os.path.join(os.environ["VC_SOURCE"], "tests"))
import vtkcheck  # noqa: E402

BIN = os.environ["VC_BIN"]
SOURCE = os.environ["VC_SOURCE"]
TMP = os.path.join(os.environ.get("VC_TMP", "/tmp"), "e2e_voronoi")
os.makedirs(TMP, exist_ok=True)
failures = []


def check(cond, what):
    if not cond:
        failures.append(what)
        print("FAIL:", what, file=sys.stderr)
    return cond


def run(*args):
    p = subprocess.run([BIN, "voronoi", *args], capture_output=True, text=True, timeout=600)
    return p.returncode, p.stdout, p.stderr


def write_seeds(name, rows, labels=True):
    path = os.path.join(TMP, name)
    with open(path, "w") as f:
        f.write("x,y,z,label\n" if labels else "x,y,z\n")
        for r in rows:
            f.write(",".join(repr(float(v)) if i < 3 else str(v) for i, v in enumerate(r)) + "\n")
    return path


def read_seeds(path):
    with open(path) as f:
        rows = list(csv.reader(f))[1:]
    return [(float(r[0]), float(r[1]), float(r[2]), int(r[3]) if len(r) > 3 else 1) for r in rows]


def mesh(name, seeds_path, *opts, cells=None, volume=None, connections=False):
    """Runs the CLI; checks exit code and the .vtu with VTK; returns the
    figures of vtkcheck.check_vtu and the connection rows."""
    out = os.path.join(TMP, name + ".vtu")
    args = [seeds_path, "-o", out, *opts]
    conn = os.path.join(TMP, name + "_connections.csv")
    if connections:
        args += ["--connections", conn]
    rc, so, se = run(*args)
    if not check(rc == 0, "%s: exit %d, stderr %r" % (name, rc, se)):
        return None, None
    check("validation passed" in so + se, "%s: validator did not pass: %r" % (name, se))
    try:
        fig = vtkcheck.check_vtu(out, expected_cells=cells, expected_volume=volume)
    except vtkcheck.CheckError as e:
        check(False, "%s: %s" % (name, e))
        return None, None
    rows = None
    if connections:
        with open(conn) as f:
            r = list(csv.reader(f))
        check(r[0] == ["cell_i", "cell_j", "seed_i", "seed_j", "area", "distance",
                       "cx", "cy", "cz", "nx", "ny", "nz"], "%s: connections header %r" % (name, r[0]))
        rows = [[int(x) for x in row[:4]] + [float(x) for x in row[4:]] for row in r[1:]]
    return fig, rows


def check_connections(name, seeds, rows, fig):
    """Real properties of Voronoi connections: the face is orthogonal to the
    seed pair, the distance is the seed distance, one row per shared face."""
    check(len(rows) == fig["n_faces_shared"],
          "%s: %d connections, VTK sees %d shared faces" % (name, len(rows), fig["n_faces_shared"]))
    worst = [0.0, 0.0, 0.0]  # distance, normal, centroid off the bisector
    for ci, cj, si, sj, area, dist, cx, cy, cz, nx, ny, nz in rows:
        a, b = seeds[si], seeds[sj]
        d = [b[k] - a[k] for k in range(3)]
        dn = math.sqrt(sum(x * x for x in d))
        if not check(ci < cj and area > 0, "%s: row %d %d area %g" % (name, ci, cj, area)):
            break
        worst[0] = max(worst[0], abs(dist - dn) / dn)
        worst[1] = max(worst[1], abs(math.hypot(nx, ny, nz) - 1.0),
                       max(abs(n - x / dn) for n, x in zip((nx, ny, nz), d)))
        # The face centroid lies on the bisector of the two seeds, up to the
        # vertex merge tolerance (1e-8 of the local cell size).
        mid = [(a[k] + b[k]) / 2 for k in range(3)]
        off = sum((c - m) * x / dn for c, m, x in zip((cx, cy, cz), mid, d))
        worst[2] = max(worst[2], abs(off) / dn)
    check(worst[0] < 1e-12 and worst[1] < 1e-9 and worst[2] < 1e-7,
          "%s: connection geometry off: distance %g, normal %g, centroid %g"
          % (name, worst[0], worst[1], worst[2]))


# ---- Random seeds in a box, with connections ----
rng = random.Random(7)
box = (-1.0, 0.0, 0.5, 2.0, 1.5, 2.5)
vol_box = (box[3] - box[0]) * (box[4] - box[1]) * (box[5] - box[2])
rand = [(rng.uniform(box[0], box[3]), rng.uniform(box[1], box[4]), rng.uniform(box[2], box[5]), 1)
        for _ in range(3000)]
p_rand = write_seeds("random.csv", rand)
fig, rows = mesh("random", p_rand, "--box", *map(str, box), cells=3000, volume=vol_box,
                 connections=True)
if fig:
    check_connections("random", rand, rows, fig)
    grid = vtkcheck.read_vtu(os.path.join(TMP, "random.vtu"))
    seed_ids = vtkcheck.cell_array(grid, "seed")
    region = vtkcheck.cell_array(grid, "region")
    check(seed_ids == list(range(3000)), "random: seed ids are not 0..2999 in order")
    check(set(region) == {1}, "random: region values %r" % set(region))
    # Pyramid identity for cells away from the walls: volume = sum over the
    # faces of area * (distance / 2) / 3, since the seed is at distance/2
    # from every face.
    vols = vtkcheck.cell_array(grid, "volume")
    pyr = [0.0] * 3000
    for ci, cj, si, sj, area, dist, *_ in rows:
        pyr[ci] += area * dist / 6
        pyr[cj] += area * dist / 6
    n_faces = [0] * 3000
    for ci, cj, *_ in rows:
        n_faces[ci] += 1
        n_faces[cj] += 1
    ids = None
    inner = 0
    for c in range(3000):
        if len(vtkcheck.cell_faces(grid, c)) == n_faces[c]:  # no wall face
            inner += 1
            check(abs(pyr[c] - vols[c]) <= 1e-9 * vols[c],
                  "random: cell %d volume %r, pyramid sum %r" % (c, vols[c], pyr[c]))
    check(inner > 1000, "random: only %d cells away from the walls" % inner)

# ---- Same seeds: raw and zlib encodings, 1 and 2 threads ----
for enc in ("raw", "zlib"):
    for t in ("1", "2"):
        out = os.path.join(TMP, "det_%s_%s.vtu" % (enc, t))
        rc, _, se = run(p_rand, "--box", *map(str, box), "-o", out, "--encoding", enc,
                        "--threads", t, "--quiet")
        check(rc == 0, "determinism %s %s: exit %d %r" % (enc, t, rc, se))
for enc in ("raw", "zlib"):
    a = open(os.path.join(TMP, "det_%s_1.vtu" % enc), "rb").read()
    b = open(os.path.join(TMP, "det_%s_2.vtu" % enc), "rb").read()
    check(a == b, "%s: 1 and 2 threads give different files" % enc)
try:
    fr = vtkcheck.check_vtu(os.path.join(TMP, "det_raw_1.vtu"), expected_cells=3000,
                            expected_volume=vol_box)
    fz = vtkcheck.check_vtu(os.path.join(TMP, "det_zlib_1.vtu"), expected_cells=3000,
                            expected_volume=vol_box)
    check(fr == fz, "raw and zlib read back differently: %r vs %r" % (fr, fz))
except vtkcheck.CheckError as e:
    check(False, "encodings: %s" % e)

# ---- Cubic lattice: cubes with exactly 6 faces and 8 vertices ----
k = 5
lattice = [(i + 0.5, j + 0.5, m + 0.5, 1) for m in range(k) for j in range(k) for i in range(k)]
p_lat = write_seeds("lattice.csv", lattice)
fig, rows = mesh("lattice", p_lat, "--box", "0", "0", "0", str(k), str(k), str(k),
                 cells=k ** 3, volume=float(k ** 3), connections=True)
if fig:
    check(fig["n_points"] == (k + 1) ** 3, "lattice: %d points" % fig["n_points"])
    grid = vtkcheck.read_vtu(os.path.join(TMP, "lattice.vtu"))
    for c in range(k ** 3):
        faces = vtkcheck.cell_faces(grid, c)
        pts = {p for f in faces for p in f}
        if not check(len(faces) == 6 and len(pts) == 8 and all(len(f) == 4 for f in faces),
                     "lattice: cell %d has %d faces, %d points" % (c, len(faces), len(pts))):
            break
    check(len(rows) == 3 * k * k * (k - 1), "lattice: %d connections" % len(rows))
    check(all(abs(r[4] - 1) < 1e-12 and abs(r[5] - 1) < 1e-12 for r in rows),
          "lattice: connection area/distance not 1")

# ---- Co-spherical seed pairs (the bundled VoroCrust-like ball) ----
p_ball = os.path.join(SOURCE, "models", "ball-seeds.csv")
ball = read_seeds(p_ball)
kept = sum(1 for s in ball if s[3] != 0)
fig, rows = mesh("ball", p_ball, cells=kept, connections=True)
if fig:
    check_connections("ball", ball, rows, fig)
    # The kept region approximates the unit ball (pairs at 1 -/+ 0.06).
    check(abs(fig["total_volume"] - 4 * math.pi / 3) < 0.05 * 4 * math.pi / 3,
          "ball: volume %r, unit ball %r" % (fig["total_volume"], 4 * math.pi / 3))
    grid = vtkcheck.read_vtu(os.path.join(TMP, "ball.vtu"))
    seed_ids = vtkcheck.cell_array(grid, "seed")
    check(all(ball[s][3] != 0 for s in seed_ids), "ball: a label-0 seed has a cell")
# All labels 1 inside a box: the volumes must fill the box exactly.
p_ball1 = write_seeds("ball_all.csv", [(x, y, z, 1) for x, y, z, _ in ball])
mesh("ball_all", p_ball1, "--box", "-1.5", "-1.5", "-1.5", "1.5", "1.5", "1.5",
     cells=len(ball), volume=27.0)

# ---- A single seed, no label column ----
p_one = write_seeds("one.csv", [(0.1, 0.2, 0.3)], labels=False)
fig, _ = mesh("one", p_one, "--box", "0", "0", "0", "1", "2", "3", cells=1, volume=6.0)
if fig:
    check(fig["n_points"] == 8, "one: %d points" % fig["n_points"])


# ---- Bad input: one line naming the file, non-zero exit, no output ----
def expect_error(name, args, needle, names_file):
    out = os.path.join(TMP, "bad_%s.vtu" % name)
    if os.path.exists(out):
        os.remove(out)
    before = set(os.listdir(TMP))
    rc, so, se = run(*[a if a != "OUT" else out for a in args])
    lines = se.strip().splitlines()
    check(rc != 0, "%s: exit code 0" % name)
    check(len(lines) == 1 and lines[0].startswith("vorocrust") and needle in lines[0]
          and (names_file is None or names_file in lines[0]),
          "%s: stderr %r should be one line naming %r with %r" % (name, se, names_file, needle))
    check(not os.path.exists(out), "%s: output file left behind" % name)
    left = set(os.listdir(TMP)) - before
    check(not left, "%s: left %r behind" % (name, sorted(left)))


def bad_file(name, text):
    path = os.path.join(TMP, name)
    with open(path, "w") as f:
        f.write(text)
    return path


missing = os.path.join(TMP, "no_such_seeds.csv")
expect_error("missing", [missing, "-o", "OUT"], "cannot open", missing)
f = bad_file("empty.csv", "")
expect_error("empty", [f, "-o", "OUT"], "empty", f)
f = bad_file("header_only.csv", "x,y,z\n")
expect_error("header_only", [f, "-o", "OUT"], "no seeds", f)
f = bad_file("malformed.csv", "x,y,z\n0,0,0\n1,abc,0\n")
expect_error("malformed", [f, "-o", "OUT"], ":3:", f)
f = bad_file("nan.csv", "x,y,z\n0,0,0\n1,nan,0\n")
expect_error("nan", [f, "-o", "OUT"], ":3:", f)
f = bad_file("two_columns.csv", "x,y\n0,0\n1,1\n")
expect_error("two_columns", [f, "-o", "OUT"], ":2:", f)
f = bad_file("duplicates.csv", "x,y,z\n0,0,0\n0.5,0.5,0.5\n0,0,0\n")
expect_error("duplicates", [f, "-o", "OUT"], "coincide", f)
f = bad_file("outside.csv", "x,y,z\n0.5,0.5,0.5\n3,0.5,0.5\n")
expect_error("outside", [f, "--box", "0", "0", "0", "1", "1", "1", "-o", "OUT"], "outside the box", f)
expect_error("inverted_box", [p_one, "--box", "1", "0", "0", "0", "1", "1", "-o", "OUT"], "box", None)
expect_error("threads_0", [p_one, "--threads", "0", "-o", "OUT"], "--threads", None)
expect_error("threads_abc", [p_one, "--threads", "abc", "-o", "OUT"], "--threads", None)
expect_error("no_output", [p_one], "missing -o", None)
expect_error("unknown_option", [p_one, "--frobnicate", "-o", "OUT"], "--frobnicate", None)
nodir = os.path.join(TMP, "no_such_dir", "x.vtu")
rc, so, se = run(p_one, "-o", nodir)
check("cells built" not in se, "missing directory: refused only after the work")
check(rc != 0 and len(se.strip().splitlines()) == 1 and nodir in se,
      "output in a missing directory: exit %d, stderr %r" % (rc, se))
check(not glob.glob(os.path.join(TMP, "no_such_dir*")), "missing directory: something was created")

if failures:
    print("e2e_voronoi: %d failure(s)" % len(failures), file=sys.stderr)
    sys.exit(1)
print("e2e_voronoi: all passed")
