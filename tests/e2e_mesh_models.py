"""End-to-end test: `vorocrust mesh` with default parameters on the larger
reference models, surface and volume (tests/e2e_mesh.py covers the small
ones, determinism, options and bad input).

For each model:
 - exit 0, no warning;
 - no half-covered seed pair; every ball centre a vertex of the
   reconstructed surface, one corner ball per sharp corner of the input
   (at the sharp angle the sampling used: 60, 20 for fandisk, 120 for
   fertility, whose 64 "corners" at 60 degrees are tessellation artefacts
   smoothed away);
 - the reconstructed surface: a closed, consistently oriented 2-manifold
   with the input's Euler characteristic (as the mesh command reports it;
   tests/e2e_mesh.py checks that report independently), its quality (Q min, angle percentages,
   computed here) at least the recorded figure with a margin, and its
   two-sided Hausdorff distance to the input (VTK) at most 0.5% of the
   input's bounding-box diagonal;
 - the volume mesh read back by VTK 9.1 (tests/vtkcheck.py): every cell a
   closed convex polyhedron VTK's validator accepts, the "volume" array
   exact, faces shared by at most two cells in opposite orientations, total
   volume = the reconstructed surface's (1e-9) and the input's (1%);
 - the fatness array in [1, 14] for interior cells (cells without a
   boundary face), and below a recorded bound for the others;
 - the same .vtu, byte for byte, with 1 and 2 threads (Release only);
 - fandisk.off and fertility.off: meshed at the default theta_sharp 60
   with no second sampling (since session 14; before, sliver elimination
   diverged at their folds and they were sampled again at 20 degrees);
   fertility.off is in the extended suite (ctest -L extended,
   docs/testing.md); tests/e2e_mesh.py checks fandisk.off's seeds 2 to 8.
 - bumpy-cube-10: bumpy-cube.obj with --sharp-angle 10: one sampling at
   10 degrees on the input, with the note of the vertices made corners
   because two of their triangles agree neither in their normals nor in
   their normals smoothed at the error bound (session 47; before, sliver
   elimination diverged there and a smoothed copy was sampled);
 - coarse-torus (generated here, no shared model needed): a 10 x 6 torus
   of 120 triangles (every edge folded by 36 or 60 degrees) meshed with
   --max-error 0.05, at theta_sharp 60 with no second sampling (before
   session 14 it diverged and was sampled at 20 degrees). Checked: no
   resampling, a closed oriented 2-manifold with the input's Euler
   characteristic (0), no half-covered pair, every ball centre a surface
   vertex, the Hausdorff distance within the error bound given, the volume
   mesh read back by VTK (tests/vtkcheck.py) with the reconstructed
   surface's volume (1e-9), the fatness array, the same .vtu with 1 and 2
   threads, the quality against its recorded figures. test_mesh_pipeline
   checks the resampling ladder on it (forced by a one-pass budget).
 - coarse-torus-folds: the same torus at the default error bound, which
   sees its folds (features.h, VC_VISIBLE_FOLD): they are creases from the
   first sampling, and the surface is the input's within the bound.

Usage: e2e_mesh_models.py MODEL (one of EXPECTED's keys or coarse-torus; one
ctest test per model, see tests/CMakeLists.txt). The shared models come from
VC_MODELS; when that directory is missing the test skips (exit 77).
"""

import math
import os
import re
import subprocess
import sys

sys.path.insert(0, os.path.join(os.environ["VC_SOURCE"], "tests"))
import vtkcheck  # noqa: E402
from e2eutil import coarse_torus, models_dir  # noqa: E402
from surfacecheck import (enclosed_volume, fan, max_distance, polydata, quality,  # noqa: E402
                          read_surface, samples)

BIN = os.environ["VC_BIN"]
TMP = os.environ.get("VC_TMP", "/tmp")
failures = []

# Recorded surface quality with the default parameters and --seed 1:
# (Q min, % angles < 30, % angles > 90); Q min may drop 15%, the
# percentages rise by 1 point.
# The last figure: the largest fatness allowed for a boundary cell (thesis:
# 13.65 next to smooth surfaces; sharp features make thinner cells).
EXPECTED = {
    # 0.166 before session 19: the union coverage test draws another sample
    # (over seeds 1 to 14 the mean is the same: 0.160, before 0.164)
    "bracket.obj": (0.112, 6.8, 8.0, 14),
    "bumpy-cube.obj": (0.406, 0.6, 5.2, 14),
    "torus.obj": (0.418, 0.9, 5.9, 14),
    # at 60 degrees since session 14 (before: resampled at 20, 0.143); 0.171
    # before session 19's batched darts drew another seed-1 sample (README:
    # 0.07 to 0.20 by --seed); 0.140 before session 49's narrower slab at
    # knife edges drew another (seeds 1 to 14: mean 0.131 -> 0.124, least
    # 0.076 -> 0.077; seed 1's worst triangle at the same corner, whose
    # ball and creases the rule leaves as they were)
    "fandisk.off": (0.100, 7.5, 8.4, 20),
    # at 60 degrees since session 14 (before: at 20 degrees, Q min 0.000)
    "fertility.off": (0.120, 2.1, 6.2, 36),
}
# generated here (see coarse_torus): fertility.off's path in a few seconds
# (its folds as creases: the facets meet at the creases at the angles the
# torus' 36- and 60-degree folds leave)
GENERATED = {"coarse-torus": (0.266, 13.5, 10.1, 14),
             # the same torus at the default error bound: its 36-degree folds
             # are creases from the start (the bound sees them: features.h,
             # VC_VISIBLE_FOLD), the surface is the input's (Hausdorff and
             # volume checked). Until session 33 sliver elimination diverged
             # at them first and --fold-creases made them creases in a second
             # sampling (Q min 0.170, fatness max 12.6, Hausdorff 0.30 to 0.80%
             # over seeds); now 60 corners where those creases meet, Q min
             # 0.121, fatness max 14.9 (a cell at a corner), Hausdorff 0.000%.
             "coarse-torus-folds": (0.121, 13.9, 10.9, 16)}
# shared models with options: (the model, its options, the recorded figures)
VARIANTS = {
    # bumpy-cube.obj at 10 degrees: its bumps' folds are noise at the error
    # bound, but 24 vertices keep two triangles that agree within 10 degrees
    # neither in their normals nor in their smoothed ones; corners since
    # session 47 (the sizing would vanish there: until then sliver
    # elimination diverged after 59 s, and a copy was sampled instead)
    "bumpy-cube-10": ("bumpy-cube.obj", ["--sharp-angle", "10"], (0.306, 0.9, 6.3, 14)),
}
SANITIZED = os.environ.get("VC_SANITIZED", "0") == "1"


def check(cond, what):
    if not cond:
        failures.append(what)
        print("FAIL:", what, file=sys.stderr)


NAMES = list(EXPECTED) + list(GENERATED) + list(VARIANTS)
if len(sys.argv) != 2 or sys.argv[1] not in NAMES:
    print("usage: e2e_mesh_models.py MODEL, MODEL one of %s" % ", ".join(NAMES), file=sys.stderr)
    sys.exit(2)
for model in sys.argv[1:]:
    q_rec, lo_rec, hi_rec, fat_bnd = (EXPECTED.get(model) or GENERATED.get(model) or
                                      VARIANTS[model][2])
    generated = model in GENERATED
    tag = model.replace(".", "_").replace("-", "_")
    if generated:
        in_path = os.path.join(TMP, "mesh_models_%s_input.obj" % tag)
        # a 10 x 6 torus (120 triangles) either way
        if model == "coarse-torus-folds":
            # at the default error bound, which sees its folds
            coarse_torus(in_path, nu=10, nv=6)
            extra = []
        else:
            coarse_torus(in_path, nu=10, nv=6)
            extra = ["--max-error", "0.05"]
    elif model in VARIANTS:
        in_path = os.path.join(models_dir(), VARIANTS[model][0])
        extra = list(VARIANTS[model][1])
    else:
        in_path = os.path.join(models_dir(), model)
        extra = []
    vtu = os.path.join(TMP, "mesh_models_%s.vtu" % tag)
    surf = os.path.join(TMP, "mesh_models_%s.obj" % tag)
    balls_csv = os.path.join(TMP, "mesh_models_%s_balls.csv" % tag)
    p = subprocess.run([BIN, "mesh", in_path, "-o", vtu, "--surface", surf,
                        "--balls", balls_csv, "--threads", "2"] + extra, capture_output=True,
                       text=True, timeout=900)
    check(p.returncode == 0 and "warning" not in p.stderr,
          "%s: exit %d: %s" % (model, p.returncode, p.stderr[-2000:]))
    if p.returncode != 0:
        continue
    if not SANITIZED:
        # the same mesh with one thread, byte for byte
        vtu1 = os.path.join(TMP, "mesh_models_%s_t1.vtu" % tag)
        p1 = subprocess.run([BIN, "mesh", in_path, "-o", vtu1, "--threads",
                             "1"] + extra, capture_output=True, text=True, timeout=900)
        with open(vtu, "rb") as a, open(vtu1, "rb") as b:
            same = p1.returncode == 0 and a.read() == b.read()
        check(same, "%s: the .vtu differs between 1 and 2 threads" % model)
        print("%s: the same .vtu with 1 and 2 threads: %s" % (model, same))
    m = re.search(r"euler (-?\d+) \(input (-?\d+)\), closed 2-manifold, consistently oriented",
                  p.stderr)
    check(m is not None and m.group(1) == m.group(2),
          "%s: the surface is not a closed oriented 2-manifold with the input's Euler "
          "characteristic" % model)
    m = re.search(r"half-covered seed pairs (\d+)", p.stderr)
    check(m is not None and m.group(1) == "0", "%s: half-covered seed pairs left" % model)
    pts, polys = read_surface(surf)
    # every ball centre is a surface vertex; the corner balls are the
    # input's sharp corners at the sharp angle the sampling used
    with open(balls_csv) as fb:
        rows = [r.split(",") for r in fb.read().splitlines()[1:]]
    ext = math.dist([min(q[k] for q in pts) for k in range(3)], [max(q[k] for q in pts) for k in range(3)])
    h = 1e-6 * ext
    grid = {}
    for q in pts:
        grid.setdefault(tuple(math.floor(x / h) for x in q), []).append(q)

    def is_vertex(c):
        k = [math.floor(x / h) for x in c]
        return any(math.dist(c, q) <= 1e-8 * ext
                   for a in (-1, 0, 1) for b in (-1, 0, 1) for d in (-1, 0, 1)
                   for q in grid.get((k[0] + a, k[1] + b, k[2] + d), ()))
    missing = sum(not is_vertex([float(x) for x in r[:3]]) for r in rows)
    check(missing == 0, "%s: %d of %d ball centres are not surface vertices" % (model, missing, len(rows)))
    angle = re.search(r"sharp angle ([0-9.]+)", p.stderr)
    check(angle is not None, "%s: no sharp angle in the summary" % model)
    if angle:
        # at the mesh's error bound: the folds it sees are creases too
        bound_args = extra if "--max-error" in extra else []
        info = subprocess.run([BIN, "info", in_path, "--features", "--sharp-angle",
                               angle.group(1)] + bound_args, capture_output=True, text=True, timeout=300)
        nc = re.search(r"^sharp corners: (\d+)$", info.stdout, re.M)
        corner_balls = sum(r[4] == "corner" for r in rows)
        # folds made creases add corners where they end or meet
        folds = model == "coarse-torus-folds"
        check(nc is not None and (int(nc.group(1)) <= corner_balls if folds
                                  else int(nc.group(1)) == corner_balls),
              "%s: %d corner balls, input corners at %s degrees: %s"
              % (model, corner_balls, angle.group(1), nc and nc.group(1)))
    qmin, p_lo, p_hi = quality(fan(pts, polys))
    print("%s: surface Q min %.3f, angles < 30: %.1f%%, > 90: %.1f%%" % (model, qmin, p_lo, p_hi))
    if model == "coarse-torus":
        check("sampling again" not in p.stderr and
              "after 0 smoothing rounds; sharp angle 60)" in p.stderr,
              "coarse-torus: sampled again, or not at 60 degrees")
        check("euler 0 (input 0)" in p.stderr, "coarse-torus: the surface's Euler characteristic is not 0")
    check(qmin >= 0.85 * q_rec, "%s: Q min %.3f below the recorded %.3f" % (model, qmin, q_rec))
    check(p_lo <= lo_rec + 1 and p_hi <= hi_rec + 1,
          "%s: angles < 30 %.1f%%, > 90 %.1f%% above the recorded %.1f%%, %.1f%%"
          % (model, p_lo, p_hi, lo_rec, hi_rec))
    if model in ("fandisk.off", "fertility.off"):
        check("sampling again" not in p.stderr and "after 0 smoothing rounds; sharp angle 60)" in p.stderr,
              "%s: sampled again, or not at 60 degrees" % model)
    if model == "bumpy-cube-10":
        check(re.search(r"mesh: \d+ vertices are corners: two of their triangles agree", p.stderr)
              is not None and "sampling again" not in p.stderr and
              "after 0 smoothing rounds; sharp angle 10)" in p.stderr,
              "bumpy-cube-10: no note of the vertices made corners, or sampled again")
    if model == "fertility.off":
        check("euler -6 (input -6)" in p.stderr, "fertility: the surface's Euler characteristic is not -6")
    if model == "coarse-torus-folds":
        check(re.search(r"mesh: \d+ folds below 60 degrees are creases", p.stderr) is not None and
              "sampling again" not in p.stderr and
              "after 0 smoothing rounds; sharp angle 60)" in p.stderr,
              "coarse-torus-folds: no note of the folds made creases, or sampled again")
        check("euler 0 (input 0)" in p.stderr, "coarse-torus-folds: the Euler characteristic is not 0")
    moved = False  # no resampling moves the surface any more
    ipts, ipolys = read_surface(in_path)
    if not moved:
        diag = math.dist([min(x[k] for x in ipts) for k in range(3)],
                         [max(x[k] for x in ipts) for k in range(3)])
        h = max(max_distance(samples(pts, polys), polydata(ipts, ipolys)),
                max_distance(samples(ipts, ipolys), polydata(pts, polys)))
        print("%s: Hausdorff distance %.3f%% of the diagonal" % (model, 100 * h / diag))
        # the error bound: the default 0.4% (0.5% allowed), or the one given
        # (until session 33 the folded torus, its folds made creases only
        # where sliver elimination was stuck, missed it: 0.30 to 0.80% over
        # seeds 1 to 16, on facets across the folds left smooth)
        bound = 0.05 if model == "coarse-torus" else 0.005
        check(h <= bound * diag, "%s: Hausdorff %.4g > %g%% of the diagonal %.4g"
              % (model, h, 100 * bound, diag))
    sv = enclosed_volume(pts, polys)
    iv = abs(enclosed_volume(ipts, ipolys))
    try:
        fig = vtkcheck.check_vtu(vtu, expected_volume=sv)
        grid = vtkcheck.read_vtu(vtu)
        fat = vtkcheck.cell_array(grid, "fatness")
        on_boundary = fig["boundary_cells"]  # cells with a face no other cell has
        worst_inner = max((x for c, x in enumerate(fat) if c not in on_boundary), default=1)
        check(len(fat) == fig["n_cells"] and min(fat) >= 1 and worst_inner <= 14
              and max(fat) <= fat_bnd,
              "%s: fatness array: %d values, range %r..%r, interior cells up to %r"
              % (model, len(fat), min(fat), max(fat), worst_inner))
        print("%s: %d cells, volume %.12g (surface %.12g, input %.12g); VTK flagged %d of %d cells judged "
              "(%d with tiny edges after rotation), fatness max %.2f"
              % (model, fig["n_cells"], fig["total_volume"], sv, iv, fig["vtk_flagged"], fig["vtk_judged"],
                 fig["vtk_rejected_tiny"], max(fat)))
        check(moved or abs(fig["total_volume"] - iv) <= 0.01 * iv,
              "%s: mesh volume %.9g vs input %.9g" % (model, fig["total_volume"], iv))
    except vtkcheck.CheckError as e:
        check(False, "%s: %s" % (model, e))
    m = re.search(r"fatness max ([0-9.]+)", p.stderr)
    check(m is not None, "%s: no fatness in the summary" % model)

if failures:
    print("%d failure(s)" % len(failures), file=sys.stderr)
    sys.exit(1)
print("e2e_mesh_models %s: all checks passed" % " ".join(sys.argv[1:]))
