"""End-to-end test of `vorocrust mesh --surface-only` (VoroCrust surface
sampling) on the shared models, checked independently of the C code:

 - the reconstructed surface (OBJ) is a closed 2-manifold, consistently
   oriented, with the input's Euler characteristic (edges counted here);
 - every ball centre (balls CSV) is a vertex of it, and so is every sharp
   corner (the corner balls sit on input vertices; their number is the one
   `vorocrust info --features` prints);
 - the summary reports no half-covered seed pair;
 - the two-sided Hausdorff distance to the input, measured with VTK's
   vtkImplicitPolyDataDistance on dense samples of both surfaces, is at most
   0.5% of the input's bounding-box diagonal;
 - triangle quality Q = 6S/(sqrt(3) h P) (P the half-perimeter; polygons
   fanned from their centroid) and the angle percentages, against recorded
   expectations with a margin;
 - the seeds CSV: inside seeds (label 1) inside the input surface, outside
   seeds outside, by VTK's signed distance;
 - 1 and 2 threads give byte-identical outputs; same --seed, same output;
 - the volume mesh (`mesh -o`, the default octree interior): every cell a valid convex
   polyhedron read back by VTK (tests/vtkcheck.py), cell volumes summing to
   the volume the reconstructed surface encloses within 1e-9 and to the
   input's within 1%, the same .vtu with 1 and 2 threads, the summary's
   counts of cells, faces and vertices equal to the file's;
 - `--foam` writes the same mesh as an OpenFOAM case;
 - touching: parts of one surface that touch along an edge (two boxes) or
   at a vertex (a box and a tetrahedron) mesh, the reconstruction touching
   where the input does (session 30; before, the non-manifold edges the
   reconstruction kept made it an error), the volume exact; two spheres
   sharing a pole (tangent there: it diverged) mesh with the pole opened
   (two components, the volume within 0.5%); VTK reads all three;
 - bad input: open surface (the error names the boundary edge count),
   missing file, bad options, unwritable output; nothing written then.
Usage: e2e_mesh.py PART (one ctest test per part, tests/CMakeLists.txt):
surface (the five models' surfaces), volume (sphere, cube, onebox volume
meshes), icosphere (models/icosphere.obj's volume mesh and --foam),
fandisk_a, fandisk_b, fandisk_c (the seeds 2 to 8; fandisk_c, seeds 5 to 8, in the extended suite), determinism (and smoothing),
bad_input (on models/icosphere.obj), touching. icosphere, bad_input and
touching need only the repository; the others skip (exit 77) when the shared models are missing.
Environment: VC_BIN, VC_MODELS, VC_TMP."""
import math
import os
import re
import subprocess
import sys

import vtk

sys.path.insert(0, os.path.join(os.environ["VC_SOURCE"], "tests"))
import vtkcheck  # noqa: E402
from surfacecheck import (enclosed_volume, fan, max_distance, polydata, quality,  # noqa: E402
                          read_surface, samples)

BIN = os.environ["VC_BIN"]
from e2eutil import models_dir  # noqa: E402

# One part per ctest test (tests/CMakeLists.txt); "icosphere" and
# "bad_input" need only the repository, the others the shared models (they
# skip, exit 77, when the directory is missing).
PARTS = ("surface", "volume", "icosphere", "fandisk_a", "fandisk_b", "fandisk_c", "determinism",
         "bad_input", "touching")
if len(sys.argv) != 2 or sys.argv[1] not in PARTS:
    print("usage: e2e_mesh.py PART, PART one of %s" % ", ".join(PARTS), file=sys.stderr)
    sys.exit(2)
PART = sys.argv[1]
MODELS = models_dir() if PART not in ("icosphere", "bad_input", "touching") else None
TMP = os.environ.get("VC_TMP", "/tmp")
# models/icosphere.obj is the project's own model of the README's first command.
ICOSPHERE = os.path.join(os.environ["VC_SOURCE"], "models", "icosphere.obj")
failures = []

# Recorded surface quality with the default parameters and --seed 1:
# (Q min, % angles < 30, % angles > 90). The test allows a margin.
EXPECTED = {
    "sphere.obj": (0.414, 0.9, 5.4),
    "cube.off": (0.242, 12.8, 8.3),
    "onebox.obj": (0.227, 15.1, 9.1),
    "bracket.obj": (0.112, 6.8, 8.0),  # see e2e_mesh_models.py
    "bumpy-cube.obj": (0.406, 0.6, 5.2),
}


def check(cond, what):
    if not cond:
        failures.append(what)
        print("FAIL:", what, file=sys.stderr)


def run(*args, timeout=600):
    p = subprocess.run([BIN, *args], capture_output=True, text=True, timeout=timeout)
    return p.returncode, p.stdout, p.stderr


def topology(pts, polys):
    edges = {}
    for f, p in enumerate(polys):
        for j in range(len(p)):
            a, b = p[j], p[(j + 1) % len(p)]
            edges.setdefault((min(a, b), max(a, b)), []).append(1 if a < b else -1)
    bad = sum(1 for e in edges.values() if len(e) != 2)
    misoriented = sum(1 for e in edges.values() if len(e) == 2 and e[0] == e[1])
    # vertex links: the polygons around each vertex form one cycle
    around = {}
    for p in polys:
        for j in range(len(p)):
            around.setdefault(p[j], []).append((p[j - 1], p[(j + 1) % len(p)]))
    pinched = 0
    for v, corners in around.items():
        nxt = {prev: nx for prev, nx in corners}
        start = corners[0][0]
        cur, steps = start, 0
        while steps <= len(corners):
            cur = nxt.get(cur)
            steps += 1
            if cur is None or cur == start:
                break
        if cur != start or steps != len(corners):
            pinched += 1
    return len(pts) - len(edges) + len(polys), bad, misoriented, pinched


def info_features(path):
    rc, out, err = run("info", path, "--features")
    m = re.search(r"^sharp corners: (\d+)$", out, re.M)
    e = re.search(r"^euler characteristic: (-?\d+)$", out, re.M)
    return int(m.group(1)), int(e.group(1))


def read_csv(path):
    with open(path) as f:
        rows = f.read().splitlines()
    return rows[0].split(","), [r.split(",") for r in rows[1:]]


def mesh(model, tag, *extra):
    surf = os.path.join(TMP, "mesh_%s.obj" % tag)
    balls = os.path.join(TMP, "mesh_%s_balls.csv" % tag)
    seeds = os.path.join(TMP, "mesh_%s_seeds.csv" % tag)
    rc, out, err = run("mesh", os.path.join(MODELS, model), "--surface-only", "--surface", surf,
                       "--balls", balls, "--seeds", seeds, *extra)
    return rc, err, surf, balls, seeds


if PART == "surface":
    for model, (q_rec, lo_rec, hi_rec) in EXPECTED.items():
        path = os.path.join(MODELS, model)
        rc, err, surf, balls_csv, seeds_csv = mesh(model, model.replace(".", "_"))
        check(rc == 0, "%s: exit %d: %s" % (model, rc, err))
        if rc != 0:
            continue
        print(err.strip().splitlines()[-6:] if err else "", flush=True)
        m = re.search(r"half-covered seed pairs (\d+)", err)
        check(m is not None and int(m.group(1)) == 0, "%s: half-covered pairs left: %r" % (model, m and m.group(1)))
        n_corners, euler_in = info_features(path)
        pts, polys = read_surface(surf)
        euler, bad, misoriented, pinched = topology(pts, polys)
        check(bad == 0 and misoriented == 0 and pinched == 0,
              "%s: not a closed consistently oriented 2-manifold: %d bad edges, %d misoriented, %d "
              "non-manifold vertices" % (model, bad, misoriented, pinched))
        check(euler == euler_in, "%s: euler %d, input %d" % (model, euler, euler_in))
        # ball centres and sharp corners are vertices
        _, rows = read_csv(balls_csv)
        vset = {}
        for i, p in enumerate(pts):
            vset[tuple(round(x, 9) for x in p)] = i
        ipts, ipolys = read_surface(path)
        missing = 0
        corners = 0
        for r in rows:
            c = tuple(float(x) for x in r[:3])
            found = any(math.dist(c, pts[vset[k]]) <= 1e-9 * (1 + max(map(abs, c)))
                        for k in [tuple(round(x, 9) for x in c)] if k in vset)
            if not found:
                found = min(math.dist(c, p) for p in pts) <= 1e-9 * (1 + max(map(abs, c)))
            missing += not found
            if r[4] == "corner":
                corners += 1
                check(math.dist(c, ipts[int(r[5])]) == 0, "%s: corner ball off its vertex" % model)
        check(missing == 0, "%s: %d ball centres are not surface vertices" % (model, missing))
        check(corners == n_corners, "%s: %d corner balls, %d sharp corners" % (model, corners, n_corners))
        # Hausdorff distance
        inp = polydata(ipts, ipolys)
        rec = polydata(pts, polys)
        lo = [min(p[k] for p in ipts) for k in range(3)]
        hi = [max(p[k] for p in ipts) for k in range(3)]
        diag = math.dist(lo, hi)
        h = max(max_distance(samples(pts, polys), inp), max_distance(samples(ipts, ipolys), rec))
        print("%s: Hausdorff %.4f%% of the diagonal" % (model, 100 * h / diag))
        check(h <= 0.005 * diag, "%s: Hausdorff distance %.3g%% of the diagonal > 0.5%%" % (model, 100 * h / diag))
        # quality against the recorded figures
        qmin, p_lo, p_hi = quality(fan(pts, polys))
        print("%s: Q min %.3f, angles < 30: %.1f%%, > 90: %.1f%%" % (model, qmin, p_lo, p_hi))
        check(qmin >= 0.85 * q_rec, "%s: Q min %.3f below the recorded %.3f" % (model, qmin, q_rec))
        check(p_lo <= lo_rec + 3 and p_hi <= hi_rec + 3,
              "%s: angle percentages %.1f / %.1f above the recorded %.1f / %.1f" % (model, p_lo, p_hi, lo_rec, hi_rec))
        # seeds on the right side of the input
        _, srows = read_csv(seeds_csv)
        sd = vtk.vtkImplicitPolyDataDistance()
        sd.SetInput(inp)
        wrong = 0
        flip = 1.0
        # vtkImplicitPolyDataDistance is negative inside for outward normals;
        # inward-oriented inputs (onebox, torus) flip the sign.
        vol = vtk.vtkMassProperties()
        vol.SetInputData(inp)
        vol.Update()
        # the signed volume decides the orientation
        sv = 0.0
        for a, b, c in fan(ipts, ipolys):
            sv += (a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0])
                   + a[2] * (b[0] * c[1] - b[1] * c[0])) / 6
        flip = 1.0 if sv > 0 else -1.0
        for r in srows:
            v = flip * sd.EvaluateFunction(float(r[0]), float(r[1]), float(r[2]))
            wrong += (r[3] == "1") != (v < 0)
        check(wrong == 0, "%s: %d of %d seeds on the wrong side of the input" % (model, wrong, len(srows)))

# The volume mesh: surface seeds and octree interior seeds (the default; the
# larger models' volume meshes are checked in e2e_mesh_models).
# models/icosphere.obj is the project's own model of the README's first command.
if PART in ("volume", "icosphere"):
    for model in (ICOSPHERE,) if PART == "icosphere" else ("sphere.obj", "cube.off", "onebox.obj"):
        vols = []
        for t in ("1", "2"):
            tag = os.path.basename(model).replace(".", "_")
            vtu = os.path.join(TMP, "mesh_vol_%s_%s.vtu" % (tag, t))
            surf = os.path.join(TMP, "mesh_vol_%s_%s.obj" % (tag, t))
            rc, out, err = run("mesh", os.path.join(MODELS or "", model), "-o", vtu, "--surface", surf,
                               "--threads", t)
            check(rc == 0 and "warning" not in err, "%s volume mesh: exit %d: %s" % (model, rc, err))
            if rc != 0:
                break
            vols.append(open(vtu, "rb").read())
            m = re.search(r"fatness max ([0-9.]+) mean ([0-9.]+) \(interior cells: max ([0-9.]+)", err)
            check(m is not None, "%s: no fatness in the summary" % model)
            if m:
                # thesis bound: 14.1 for interior cells, 13.65 at the boundary
                check(float(m.group(1)) <= 14 and float(m.group(3)) <= 14,
                      "%s: fatness max %s (interior %s) above 14" % (model, m.group(1), m.group(3)))
        if len(vols) != 2:
            continue
        check(vols[0] == vols[1], "%s: the volume mesh differs between 1 and 2 threads" % model)
        pts, polys = read_surface(surf)
        sv = enclosed_volume(pts, polys)
        ipts, ipolys = read_surface(os.path.join(MODELS or "", model))
        iv = abs(enclosed_volume(ipts, ipolys))
        try:
            fig = vtkcheck.check_vtu(vtu, expected_volume=sv)
            fat = vtkcheck.cell_array(vtkcheck.read_vtu(vtu), "fatness")
            check(len(fat) == fig["n_cells"] and all(1 <= x <= 14 for x in fat),
                  "%s: .vtu fatness array: %d values, range %r..%r" % (model, len(fat), min(fat), max(fat)))
            print("%s volume mesh: %d cells, volume %.12g (surface %.12g, input %.12g)"
                  % (model, fig["n_cells"], fig["total_volume"], sv, iv))
            # the summary's counts are the file's
            c = re.search(r"volume mesh: (\d+) cells .*; (\d+) faces \((\d+) interior, (\d+) "
                          r"boundary\), (\d+) vertices", err)
            got = tuple(int(x) for x in c.groups()) if c else None
            want = (fig["n_cells"], fig["n_faces_shared"] + fig["n_faces_boundary"],
                    fig["n_faces_shared"], fig["n_faces_boundary"], fig["n_points"])
            check(got == want, "%s: summary counts (cells, faces, interior, boundary, vertices) %r, "
                  "the .vtu has %r" % (model, got, want))
            check(abs(fig["total_volume"] - iv) <= 0.01 * iv,
                  "%s: mesh volume %.9g vs input %.9g" % (model, fig["total_volume"], iv))
        except vtkcheck.CheckError as e:
            check(False, "%s volume mesh: %s" % (model, e))

if PART == "icosphere":
    # The centre lift removes the chords' volume bias: the reconstructed
    # surface encloses the input's volume (without it, about 0.9% less on
    # this sphere), and it is still a closed sphere through the ball centres.
    ipts, ipolys = read_surface(ICOSPHERE)
    iv = abs(enclosed_volume(ipts, ipolys))
    errs = {}
    for flag in ("", "--no-lift"):
        surf = os.path.join(TMP, "mesh_lift%s.obj" % flag)
        rc, out, err = run("mesh", ICOSPHERE, "--surface-only", "--surface", surf,
                           *([flag] if flag else []))
        check(rc == 0, "icosphere %s: exit %d: %s" % (flag, rc, err))
        if rc != 0:
            continue
        line = re.search(r"^  centre lift: (.*)$", err, re.M)
        check(line is not None and (("off (--no-lift)" in line.group(1)) == (flag != "")),
              "icosphere %s: summary line %r" % (flag, line and line.group(0)))
        pts, polys = read_surface(surf)
        euler, bad, misoriented, pinched = topology(pts, polys)
        check(euler == 2 and bad == 0 and misoriented == 0 and pinched == 0,
              "icosphere %s: surface euler %d, %d bad edges" % (flag, euler, bad))
        errs[flag] = enclosed_volume(pts, polys) / iv - 1
    if len(errs) == 2:
        print("icosphere: volume error %+.4f%% lifted, %+.4f%% with --no-lift"
              % (100 * errs[""], 100 * errs["--no-lift"]))
        check(abs(errs[""]) < 0.002 and abs(errs[""]) < abs(errs["--no-lift"]) / 4,
              "icosphere: volume error %+.4f%% lifted, %+.4f%% without"
              % (100 * errs[""], 100 * errs["--no-lift"]))

    # The volume mesh as an OpenFOAM case too (checkMesh itself runs in e2e_foam).
    foam = os.path.join(TMP, "mesh_foam_case")
    vtu = os.path.join(TMP, "mesh_foam.vtu")
    full_surf = os.path.join(TMP, "mesh_foam_surface.obj")
    rc, out, err = run("mesh", ICOSPHERE, "-o", vtu, "--foam", foam, "--surface", full_surf, "--quiet")
    check(rc == 0 and err == "", "mesh --foam: exit %d %r" % (rc, err))
    # --surface-only builds the inside surface seeds' cells alone, bounded
    # by the interior seeds: its surface is the volume mesh's boundary,
    # polygon for polygon (as sets of points; the numbering may differ)
    if rc == 0 and os.path.exists(os.path.join(TMP, "mesh_lift.obj")):
        def polygon_sets(path):
            # a ball centre is one vertex of many co-spherical seeds (the
            # pole seed among them in the volume mesh, where it may have
            # moved on its sphere): the same point to rounding, not to the
            # bit. A polygon: its vertices to 1e-9 (the surface is of size 1)
            pts, polys = read_surface(path)
            return set(frozenset(tuple(round(x, 9) + 0.0 for x in pts[i]) for i in p)
                       for p in polys), len(polys)
        a, na = polygon_sets(os.path.join(TMP, "mesh_lift.obj"))
        b, nb = polygon_sets(full_surf)
        print("icosphere: %d polygons --surface-only, %d in the volume mesh, %d common"
              % (na, nb, len(a & b)))
        check(na == nb and a == b, "icosphere: the --surface-only surface (%d polygons) is not the "
              "volume mesh's boundary (%d, %d in common)" % (na, nb, len(a & b)))
    if rc == 0:
        with open(os.path.join(foam, "constant", "polyMesh", "owner")) as f:
            note = re.search(r"nCells:\s*(\d+)", f.read())
        grid = vtkcheck.read_vtu(vtu)
        check(note is not None and int(note.group(1)) == grid.GetNumberOfCells(),
              "mesh --foam: owner note %r, .vtu cells %d" % (note and note.group(0), grid.GetNumberOfCells()))

if PART in ("fandisk_a", "fandisk_b", "fandisk_c"):
    # A reconstructed surface that is not a closed oriented 2-manifold of the
    # input's Euler characteristic is an error (exit 1, no output): fandisk.off
    # at 45 degrees with --seed 4 gave one (3 boundary edges, Euler
    # characteristic 1) when this test was written. Exit 0 must come with a
    # surface that is right (checked here), so the test stays right once the
    # sampling is fixed.
    stale = os.path.join(TMP, "mesh_broken45.obj")
    if PART == "fandisk_a" and os.path.exists(stale):
        # of an earlier run in the same directory; only the part that writes
        # it (fandisk_b runs at the same time in the same directory)
        os.remove(stale)
    rc, err, surf, _, _ = mesh("fandisk.off", "broken45", "--seed", "4", "--sharp-angle", "45",
                               "--max-error", "0.0035") if PART == "fandisk_a" else (None,) * 5
    if rc is None:
        pass
    elif rc == 0:
        pts, polys = read_surface(surf)
        euler, bad, misoriented, pinched = topology(pts, polys)
        broken = euler != 2 or bad or misoriented or pinched
        check(not broken, "fandisk --seed 4 at 45 degrees: exit 0 with a broken surface: euler %d, "
              "%d bad edges, %d misoriented, %d pinched" % (euler, bad, misoriented, pinched))
        print("fandisk --seed 4 at 45 degrees: exit 0, surface right")
    else:
        check(re.search(r"^vorocrust: .*fandisk\.off: (the reconstructed surface is not a closed "
                        r"consistently oriented 2-manifold|sliver elimination does not converge)",
                        err, re.M) is not None and not os.path.exists(surf),
              "fandisk --seed 4 at 45 degrees: exit %d (output left: %s): %s"
              % (rc, os.path.exists(surf), err[-1500:]))
        print("fandisk --seed 4 at 45 degrees: exit %d, %s" % (rc, err.strip().splitlines()[-1][:160]))

    # fandisk.off with the default parameters and seeds 2 to 8 (seed 1 is in
    # e2e_mesh_models): until session 14 the sampling at 60 degrees diverged
    # at the folds of 20 to 57 degrees inside its patches and a second
    # sampling at 20 degrees made them creases; now it must succeed at 60
    # degrees for every seed, with no second sampling: no warning, no
    # half-covered pair, a closed oriented 2-manifold with Euler
    # characteristic 2, the Hausdorff distance within 0.5%, and Q min at
    # least 0.07 (measured 0.073 to 0.199 over seeds 1 to 8; the worst are
    # needles between a large corner ball and two small balls, the thesis
    # reports 0.09 for sharp models: an open defect). The sanitized build
    # (several times slower) checks two seeds.
    # Three parts: fandisk_a the warning above and seed 2, fandisk_b seeds 3
    # and 4, fandisk_c (the extended suite) seeds 5 to 8.
    SANITIZED = os.environ.get("VC_SANITIZED", "0") == "1"
    fd_path = os.path.join(MODELS, "fandisk.off")
    fd_pts, fd_polys = read_surface(fd_path)
    fd_diag = math.dist([min(p[k] for p in fd_pts) for k in range(3)],
                        [max(p[k] for p in fd_pts) for k in range(3)])
    fd_inp = polydata(fd_pts, fd_polys)
    fd_samples = samples(fd_pts, fd_polys)
    seeds = {"fandisk_a": (2,), "fandisk_b": (3, 4), "fandisk_c": (5, 6, 7, 8)}[PART]
    for seed in seeds[:1] if SANITIZED else seeds:
        rc, err, surf, _, _ = mesh("fandisk.off", "fandisk_seed%d" % seed, "--seed", str(seed))
        what = "fandisk --seed %d" % seed
        check(rc == 0 and "warning" not in err, "%s: exit %d: %s" % (what, rc, err[-1500:]))
        if rc != 0:
            continue
        check("sampling again" not in err and "after 0 smoothing rounds; sharp angle 60)" in err,
              "%s: sampled again, or not at 60 degrees" % what)
        m = re.search(r"half-covered seed pairs (\d+)", err)
        check(m is not None and m.group(1) == "0", "%s: half-covered pairs left" % what)
        pts, polys = read_surface(surf)
        euler, bad, misoriented, pinched = topology(pts, polys)
        check(euler == 2 and not bad and not misoriented and not pinched,
              "%s: euler %d, %d bad edges, %d misoriented, %d pinched" % (what, euler, bad, misoriented,
                                                                           pinched))
        qmin, _, _ = quality(fan(pts, polys))
        h = max(max_distance(samples(pts, polys), fd_inp), max_distance(fd_samples, polydata(pts, polys)))
        print("%s: %d vertices, Q min %.3f, Hausdorff %.3f%% of the diagonal"
              % (what, len(pts), qmin, 100 * h / fd_diag))
        check(qmin >= 0.07, "%s: Q min %.3f below 0.07" % (what, qmin))
        check(h <= 0.005 * fd_diag, "%s: Hausdorff %.3f%% > 0.5%%" % (what, 100 * h / fd_diag))

if PART == "determinism":
    # Patch smoothing before sampling: sphere.obj, 6 rounds of adaptive Loop.
    rc, err, surf, balls_csv, seeds_csv = mesh("sphere.obj", "smooth6", "--smooth-iterations", "6")
    check(rc == 0 and "13520 after 6 smoothing rounds" in err, "smoothing run: exit %d: %s" % (rc, err))
    if rc == 0:
        pts, polys = read_surface(surf)
        euler, bad, misoriented, pinched = topology(pts, polys)
        check(euler == 2 and bad == 0 and misoriented == 0 and pinched == 0,
              "smoothed sphere: euler %d, %d bad edges, %d misoriented, %d pinched" % (euler, bad, misoriented, pinched))
        qmin, _, _ = quality(fan(pts, polys))
        # The flat-facet pass lifts facets (triangles of ball triplets) to
        # Q 0.40; this measure fans each polygon from its centroid, which
        # can sit just below (0.399 with session 22's darts, no facet below
        # 0.40): the bound allows that much.
        check(qmin >= 0.39, "smoothed sphere: Q min %.3f" % qmin)

    # Determinism: 1 and 2 threads, same seed twice, and the default (every
    # core: --threads unset is 0 for the library, which some phases once
    # read as one thread); another seed differs.
    outs = []
    for t in ("1", "2", "2", None):
        args = ("--threads", t, "--quiet") if t else ("--quiet",)
        rc, err, surf, balls_csv, seeds_csv = mesh("bracket.obj", "det%s_%d" % (t, len(outs)), *args)
        check(rc == 0 and err == "", "determinism run: exit %d %r" % (rc, err))
        outs.append(b"".join(open(p, "rb").read() for p in (surf, balls_csv, seeds_csv)))
    det_surf, det_seeds, det_balls = open(surf, "rb").read(), open(seeds_csv, "rb").read(), balls_csv
    check(outs[0] == outs[1] == outs[2] == outs[3], "bracket: outputs differ between runs or thread counts")
    # The same solid numbered another way, as another exporter writes it
    # (OFF, vertices renumbered, triangles shuffled and each started at
    # another corner): the same outputs (the mesher samples the surface in
    # the order of its geometry).
    verts, tris = [], []
    for line in open(os.path.join(MODELS, "bracket.obj")):
        w = line.split()
        if w and w[0] == "v":
            verts.append(w[1:4])
        elif w and w[0] == "f":
            tris.append([int(x.split("/")[0]) - 1 for x in w[1:]])
    nv = len(verts)
    new_of = [(7 * v + 3) % nv for v in range(nv)]
    check(len(set(new_of)) == nv, "bracket: the renumbering is no permutation")
    placed = [None] * nv
    for v in range(nv):
        placed[new_of[v]] = verts[v]
    renumbered = os.path.join(TMP, "mesh_bracket_renumbered.off")
    with open(renumbered, "w") as f:
        f.write("OFF\n%d %d 0\n" % (nv, len(tris)))
        f.writelines(" ".join(p) + "\n" for p in placed)
        for t, tri in enumerate(reversed(tris)):
            r = t % len(tri)
            tri = tri[r:] + tri[:r]
            f.write("%d %s\n" % (len(tri), " ".join(str(new_of[v]) for v in tri)))
    surf, balls_csv, seeds_csv = (os.path.join(TMP, "mesh_det_renumbered%s" % x)
                                  for x in (".obj", "_balls.csv", "_seeds.csv"))
    rc, _, err = run("mesh", renumbered, "--surface-only", "--surface", surf, "--balls", balls_csv,
                     "--seeds", seeds_csv, "--quiet")
    check(rc == 0 and err == "", "renumbered bracket: exit %d %r" % (rc, err))
    # the balls name their corner vertex and triangle in each file's own
    # numbering: that column aside, the same bytes
    def without_elements(path):
        return [",".join(w[:5] + w[6:]) for w in (line.split(",") for line in open(path))]
    check(rc == 0 and open(surf, "rb").read() == det_surf and open(seeds_csv, "rb").read() == det_seeds
          and without_elements(balls_csv) == without_elements(det_balls),
          "bracket renumbered as OFF: outputs differ from the OBJ's")
    rc, err, surf, balls_csv, seeds_csv = mesh("bracket.obj", "det_seed2", "--seed", "2", "--quiet")
    check(rc == 0 and open(balls_csv, "rb").read() not in outs[0], "--seed 2 gives the same balls")

if PART == "bad_input":
    # Bad input: one line naming the file and the problem, exit non-zero, nothing written.
    open_obj = os.path.join(TMP, "mesh_open.obj")
    with open(open_obj, "w") as f:
        f.write("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\n")
    bad_cases = [
        (["mesh", open_obj, "--surface-only", "--surface", os.path.join(TMP, "x.obj")], 1,
         "3 boundary edges"),
        (["mesh", os.path.join(TMP, "nope.obj"), "--surface-only", "--surface", os.path.join(TMP, "x.obj")], 1,
         "nope.obj"),
        (["mesh", ICOSPHERE, "--surface-only", "--surface", os.path.join(TMP, "x.obj"),
          "--lipschitz", "1.5"], 2, "--lipschitz"),
        (["mesh", ICOSPHERE, "--surface-only", "--surface", os.path.join(TMP, "x.obj"),
          "--sharp-angle", "abc"], 2, "--sharp-angle"),
        (["mesh", ICOSPHERE, "--surface-only", "--surface", os.path.join(TMP, "x.obj"),
          "--max-size", "-1"], 2, "--max-size"),
        (["mesh", ICOSPHERE, "--surface-only"], 2, "--surface"),
        (["mesh", ICOSPHERE, "--surface-only", "--surface", os.path.join(TMP, "x.obj"),
          "--smooth-iterations", "13"], 2, "--smooth-iterations"),
        (["mesh", ICOSPHERE, "--surface-only", "--surface", os.path.join(TMP, "x.obj"),
          "--curvature-factor", "0.3"], 2, "needs --smooth-width"),
        (["mesh", ICOSPHERE, "-o", os.path.join(TMP, "x.obj"),
          "--interior", "voxel"], 2, "--interior"),
        (["mesh", ICOSPHERE, "-o", os.path.join(TMP, "x.obj"),
          "--lloyd", "-1"], 2, "--lloyd"),
        (["mesh", ICOSPHERE, "--surface-only", "--surface",
          os.path.join(TMP, "no_such_dir", "x.obj")], 1, "no_such_dir"),
        (["mesh", ICOSPHERE, "--surface-only", "--surface", os.path.join(TMP, "x.obj"),
          "--connections", os.path.join(TMP, "c.csv")], 2, "--connections"),
        (["mesh", ICOSPHERE, "-o", os.path.join(TMP, "x.obj"),
          "--connections", os.path.join(TMP, "x.obj")], 2, "named by two outputs"),
        (["mesh", ICOSPHERE, "-o", os.path.join(TMP, "y.vtu"),
          "--surface", os.path.join(TMP, "y_boundary.vtu")], 2, "_boundary.vtu too"),
        (["mesh", ICOSPHERE, "-o", os.path.join(TMP, "y.vtu"),
          "--patch-type", "inlet"], 2, "NAME=TYPE"),
        (["mesh", ICOSPHERE, "-o", os.path.join(TMP, "y.vtu"),
          "--patches", "faces"], 2, "groups, features or none"),
        (["mesh", ICOSPHERE, "-o", os.path.join(TMP, "x.obj"),
          "--foam-max-skew", "0.5"], 2, "--foam-max-skew"),
        (["mesh", ICOSPHERE, "-o", os.path.join(TMP, "x.obj"),
          "--foam-max-skew", "nan"], 2, "--foam-max-skew"),
    ]
    for args, want_rc, want in bad_cases:
        if os.path.exists(os.path.join(TMP, "x.obj")):
            os.remove(os.path.join(TMP, "x.obj"))
        rc, out, err = run(*args)
        lines = err.strip().splitlines()
        check(rc == want_rc and len(lines) == 1 and want in err and lines[0].startswith("vorocrust: "),
              "bad input %r: exit %d, stderr %r" % (args[1:], rc, err))
        check(not os.path.exists(os.path.join(TMP, "x.obj")), "bad input %r left an output" % (args[1:],))

    # A result the mesher knows to be wrong is an error: a sampling so coarse
    # (the error bound 0.9 of the diagonal, radii growing at 0.99 per unit of
    # distance, no creases) that the reconstructed surface misses 43% of the
    # icosphere's volume. Exit 1, one line, no output.
    wrong = os.path.join(TMP, "wrong.vtu")
    for stale in (wrong, os.path.join(TMP, "wrong_boundary.vtu")):
        if os.path.exists(stale):
            os.remove(stale)
    rc, out, err = run("mesh", ICOSPHERE, "-o", wrong, "--quiet", "--lipschitz", "0.99",
                       "--max-error", "0.9", "--sharp-angle", "179")
    lines = err.strip().splitlines()
    check(rc == 1 and len(lines) == 1 and re.search(r"^vorocrust: .*icosphere\.obj: the reconstructed "
                                                    r"surface encloses .*more than 1% off", lines[0]),
          "a mesh 43%% off the input's volume: exit %d, stderr %r" % (rc, err[-600:]))
    check(not os.path.exists(wrong) and not os.path.exists(os.path.join(TMP, "wrong_boundary.vtu")),
          "a mesh known to be wrong was written")

def write_tangent_spheres(path, nu=32, nv=16):
    """Two UV spheres of radius 1 centred at (0, 0, 0) and (0, 0, 2) sharing
    the vertex (0, 0, 1), tangent there. Returns the enclosed volume."""
    pts, tris = [], []
    shared = None
    volume = 0.0
    for cz in (0.0, 2.0):
        idx = {}

        def vert(j, i):
            key = (j, 0 if j in (0, nv) else i % nu)
            if key not in idx:
                th, ph = math.pi * j / nv, 2 * math.pi * i / nu
                p = (math.sin(th) * math.cos(ph), math.sin(th) * math.sin(ph), cz + math.cos(th))
                if abs(p[2] - 1) < 1e-12 and abs(p[0]) < 1e-12 and abs(p[1]) < 1e-12 and shared is not None:
                    idx[key] = shared
                else:
                    idx[key] = len(pts)
                    pts.append(p)
            return idx[key]
        faces = []
        for j in range(nv):
            for i in range(nu):
                a, b, c, d = vert(j, i), vert(j + 1, i), vert(j + 1, i + 1), vert(j, i + 1)
                faces += [t for t in ((a, b, c), (a, c, d)) if len(set(t)) == 3]
        if shared is None:
            shared = vert(0, 0)  # the first sphere's top pole, (0, 0, 1)
        tris += faces
    for a, b, c in tris:
        p, q, r = pts[a], pts[b], pts[c]
        volume += (p[0] * (q[1] * r[2] - q[2] * r[1]) - p[1] * (q[0] * r[2] - q[2] * r[0]) +
                   p[2] * (q[0] * r[1] - q[1] * r[0])) / 6
    with open(path, "w") as f:
        f.write("".join("v %r %r %r\n" % p for p in pts))
        f.write("".join("f %d %d %d\n" % (a + 1, b + 1, c + 1) for a, b, c in tris))
    return volume


def write_touching(path, second):
    """A box [0, 1] x [0, 1.3] x [0, 0.8] and a second part sharing vertices
    with it: "edge", a box [1, 2.2] x [1.3, 2] x [0, 0.8] (their edge x = 1,
    y = 1.3 in common); "vertex", a tetrahedron on the corner (1, 1.3, 0.8).
    Returns the enclosed volume."""
    box = [(0, 0, 0), (1, 0, 0), (1, 1.3, 0), (0, 1.3, 0), (0, 0, 0.8), (1, 0, 0.8), (1, 1.3, 0.8), (0, 1.3, 0.8)]
    quads = [(0, 3, 2, 1), (4, 5, 6, 7), (0, 1, 5, 4), (2, 3, 7, 6), (0, 4, 7, 3), (1, 2, 6, 5)]
    pts = list(box)
    tris = [t for a, b, c, d in quads for t in ((a, b, c), (a, c, d))]
    if second == "tangent":
        pass
    elif second == "edge":
        other = [(1, 1.3, 0), (2.2, 1.3, 0), (2.2, 2, 0), (1, 2, 0), (1, 1.3, 0.8), (2.2, 1.3, 0.8), (2.2, 2, 0.8),
                 (1, 2, 0.8)]
        volume = 1 * 1.3 * 0.8 + 1.2 * 0.7 * 0.8
        faces = [t for a, b, c, d in quads for t in ((a, b, c), (a, c, d))]
    else:
        other = [(1, 1.3, 0.8), (1.9, 1.3, 0.8), (1, 2.1, 0.8), (1, 1.3, 1.5)]
        volume = 1 * 1.3 * 0.8 + 0.9 * 0.8 * 0.7 / 6
        faces = [(0, 2, 1), (0, 1, 3), (1, 2, 3), (0, 3, 2)]
    if second == "tangent":
        return write_tangent_spheres(path)
    index = {}
    for k, p in enumerate(other):
        if p in pts:
            index[k] = pts.index(p)
        else:
            index[k] = len(pts)
            pts.append(p)
    tris += [tuple(index[v] for v in t) for t in faces]
    with open(path, "w") as f:
        f.write("".join("v %r %r %r\n" % p for p in pts))
        f.write("".join("f %d %d %d\n" % (a + 1, b + 1, c + 1) for a, b, c in tris))
    return volume


if PART == "touching":
    for second in ("edge", "vertex", "tangent"):
        src = os.path.join(TMP, "mesh_touching_%s.obj" % second)
        vtu = os.path.join(TMP, "mesh_touching_%s.vtu" % second)
        volume = write_touching(src, second)
        rc, out, err = run("mesh", src, "-o", vtu, "--threads", "2")
        check(rc == 0 and "warning" not in err, "touching %s: exit %d: %s" % (second, rc, err[-1500:]))
        if rc != 0:
            continue
        # the tangent spheres' shared pole is opened (their sheets part at
        # no angle: two components, Euler 4); the box corners meet at 90
        # degrees and the boxes along an edge: kept, Euler 3
        tangent = second == "tangent"
        euler = "4" if tangent else "3"
        m = re.search(r"euler (-?\d+) \(input (-?\d+)\), closed", err)
        check(m is not None and m.group(1) == m.group(2) == euler,
              "touching %s: the surface's Euler characteristic is not %s" % (second, euler))
        opened = re.search(r"(\d+) pinch vertices \(parts touching at a point at a small angle\) opened", err)
        check((opened is not None and opened.group(1) == "1") == tangent,
              "touching %s: pinch line %r" % (second, opened and opened.group(0)))
        m = re.search(r"volume mesh: \d+ cells \(\d+ interior seeds\), volume ([0-9.eE+-]+)", err)
        mesh_volume = float(m.group(1)) if m else -1.0
        check(abs(mesh_volume / volume - 1) < (0.005 if tangent else 1e-9),
              "touching %s: volume %.12g, input %.12g" % (second, mesh_volume, volume))
        try:
            fig = vtkcheck.check_vtu(vtu, expected_volume=mesh_volume)
            print("touching %s: %d cells, volume %.12g (input %.12g)"
                  % (second, fig["n_cells"], fig["total_volume"], volume))
        except vtkcheck.CheckError as e:
            check(False, "touching %s volume mesh: %s" % (second, e))

if failures:
    print("e2e_mesh: %d failure(s)" % len(failures), file=sys.stderr)
    sys.exit(1)
print("e2e_mesh %s: all checks passed" % PART)
