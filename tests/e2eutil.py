"""Helpers the end-to-end tests (tests/e2e_*.py) share: recording failed
checks, a clean scratch directory, running a program, reading "key: value"
output, finding the shared reference models (or skipping: exit 77).

Not a test by itself (tests are tests/e2e_*.py); import it from a test:

    sys.path.insert(0, os.path.join(os.environ["VC_SOURCE"], "tests"))
    from e2eutil import check, failures

failures is the one list every check of the test appends to; the test
exits non-zero when it is not empty.
"""

import glob
import os
import re
import shutil
import subprocess
import sys

failures = []

# The exit code ctest reads as "skipped" (SKIP_RETURN_CODE, tests/CMakeLists.txt).
SKIP = 77


def models_dir():
    """The directory of the shared reference models (VC_MODELS). When it is
    not set or missing, prints one line naming it and exits with SKIP: the
    test needs the models and ctest reports it as skipped (the core suite
    runs from the repository alone)."""
    d = os.environ.get("VC_MODELS", "")
    if not d or not os.path.isdir(d):
        print("SKIP: the shared reference models directory %s is missing (set -DVC_MODELS_DIR "
              "or VC_MODELS)" % (repr(d) if d else "(VC_MODELS not set)"), flush=True)
        sys.exit(SKIP)
    return d


def check(cond, what):
    """Records what as a failure (and prints it on stderr) when cond is
    false; returns cond."""
    if not cond:
        failures.append(what)
        print("FAIL:", what, file=sys.stderr)
    return cond


def fresh_tmp(name):
    """The directory VC_TMP/name (VC_TMP: /tmp by default), made if missing,
    with the files an earlier run left in it removed (subdirectories are
    kept)."""
    tmp = os.path.join(os.environ.get("VC_TMP", "/tmp"), name)
    os.makedirs(tmp, exist_ok=True)
    for old in os.listdir(tmp):
        if os.path.isfile(os.path.join(tmp, old)):
            os.remove(os.path.join(tmp, old))
    return tmp


def run(argv, timeout):
    """Runs the command argv; returns (exit code, stdout, stderr), text."""
    p = subprocess.run(argv, capture_output=True, text=True, timeout=timeout)
    return p.returncode, p.stdout, p.stderr


def field(out, name):
    """The value of the line "name: value" of out, or None."""
    m = re.search(r"^%s: (.*)$" % re.escape(name), out, re.M)
    return m.group(1) if m else None


def coarse_torus(path, nu=12, nv=8, big=1.0, small=0.4):
    """Writes an OBJ torus of 2 nu nv triangles: nu steps around the axis,
    nv around the tube (every edge folded by 360 / nu or 360 / nv degrees)."""
    import math
    with open(path, "w") as f:
        for i in range(nu):
            for j in range(nv):
                u, v = 2 * math.pi * i / nu, 2 * math.pi * j / nv
                f.write("v %.17g %.17g %.17g\n" % ((big + small * math.cos(v)) * math.cos(u),
                                                   (big + small * math.cos(v)) * math.sin(u),
                                                   small * math.sin(v)))
        for i in range(nu):
            for j in range(nv):
                a, b = i * nv + j, ((i + 1) % nu) * nv + j
                c, d = ((i + 1) % nu) * nv + (j + 1) % nv, i * nv + (j + 1) % nv
                f.write("f %d %d %d\nf %d %d %d\n" % (a + 1, b + 1, c + 1, a + 1, c + 1, d + 1))


def voxel_surface(path, dims, label, twice=False, flip=False):
    """Writes the OBJ of the faces between differently labelled cells of a
    dims grid; label(i, j, k) gives each cell's label (outside the grid: 0)."""
    nx, ny, nz = dims

    def lab(i, j, k):
        if 0 <= i < nx and 0 <= j < ny and 0 <= k < nz:
            return label(i, j, k)
        return 0

    verts = {}

    def vid(p):
        if p not in verts:
            verts[p] = len(verts) + 1
        return verts[p]

    tris = []

    def quad(corners, towards_plus):
        # corners in counter-clockwise order seen from +axis
        a, b, c, d = (vid(q) for q in corners)
        if towards_plus:
            tris.append((a, b, c))
            tris.append((a, c, d))
        else:
            tris.append((a, c, b))
            tris.append((a, d, c))

    for i in range(-1, nx):
        for j in range(-1, ny):
            for k in range(-1, nz):
                here = lab(i, j, k)
                for axis in range(3):
                    o = [i, j, k]
                    o[axis] += 1
                    there = lab(*o)
                    if here == there:
                        continue
                    # the face between cell (i, j, k) and its +axis
                    # neighbour, corners counter-clockwise seen from +axis
                    u, v = (axis + 1) % 3, (axis + 2) % 3
                    base = [i, j, k]
                    base[axis] += 1
                    corners = []
                    for du, dv in ((0, 0), (1, 0), (1, 1), (0, 1)):
                        q = list(base)
                        q[u] += du
                        q[v] += dv
                        corners.append(tuple(q))
                    if twice:
                        # each labelled side its own copy, facing out of it
                        sides = ([True] if here else []) + ([False] if there else [])
                    else:
                        # towards the lower label (0: empty space)
                        sides = [there < here]
                    for towards_plus in sides:
                        quad(corners, towards_plus != flip)
    with open(path, "w") as f:
        pts = sorted(verts.items(), key=lambda kv: kv[1])
        for p, _ in pts:
            f.write("v %d %d %d\n" % p)
        for t in tris:
            f.write("f %d %d %d\n" % t)


def find_checkmesh():
    """(path of checkMesh, environment to run it in), or exits with a clear
    message."""
    env = dict(os.environ)
    scripts = []
    for pattern in ("/usr/lib/openfoam/openfoam*/etc/bashrc", "/usr/share/openfoam/etc/bashrc",
                    "/usr/lib/openfoam*/etc/bashrc", "/opt/openfoam*/etc/bashrc",
                    "/opt/OpenFOAM/OpenFOAM-*/etc/bashrc", "/usr/local/OpenFOAM/*/etc/bashrc"):
        scripts += sorted(glob.glob(pattern), reverse=True)  # newest version first
    tried = []
    for script in scripts:
        p = subprocess.run(["bash", "-c", 'source "$0" >/dev/null 2>&1; env -0', script],
                           capture_output=True, timeout=60)
        tried.append(script)
        if p.returncode != 0:
            continue
        senv = dict(kv.split("=", 1) for kv in p.stdout.decode().split("\0") if "=" in kv)
        if "WM_PROJECT_DIR" in senv:
            env = senv
            break
    exe = os.environ.get("VC_CHECKMESH") or shutil.which("checkMesh", path=env.get("PATH"))
    if not exe or not os.access(exe, os.X_OK):
        print("FAIL: OpenFOAM's checkMesh not found (set VC_CHECKMESH, or install the Debian "
              "package openfoam: bash .ci/install-deps); environment scripts tried: %s"
              % (", ".join(tried) or "none found"), file=sys.stderr)
        sys.exit(1)
    if "WM_PROJECT_DIR" not in env:
        print("FAIL: %s: no OpenFOAM environment script (etc/bashrc) found, checkMesh cannot "
              "find its etc/ files" % exe, file=sys.stderr)
        sys.exit(1)
    # The sanitizer settings of the ASan build are not meant for OpenFOAM.
    for k in ("ASAN_OPTIONS", "UBSAN_OPTIONS", "LD_PRELOAD"):
        env.pop(k, None)
    return exe, env


# A 4 x 1 x 1 duct whose inlet (x = 0), outlet (x = 4) and walls are named:
# its corners (1-based in DUCT_FACES) and each patch's triangles.
DUCT_V = [(0, 0, 0), (4, 0, 0), (4, 1, 0), (0, 1, 0), (0, 0, 1), (4, 0, 1), (4, 1, 1), (0, 1, 1)]
DUCT_FACES = {"inlet": [(1, 5, 8), (1, 8, 4)], "outlet": [(2, 3, 7), (2, 7, 6)],
              "walls": [(1, 3, 2), (1, 4, 3), (5, 6, 7), (5, 7, 8), (1, 2, 6), (1, 6, 5), (3, 4, 8),
                        (3, 8, 7)]}


def duct_obj(path):
    """The duct as an OBJ file, one group per patch."""
    with open(path, "w") as f:
        f.writelines("v %g %g %g\n" % v for v in DUCT_V)
        for name, tris in DUCT_FACES.items():
            f.write("g %s\n" % name)
            f.writelines("f %d %d %d\n" % t for t in tris)


# The header of an OpenFOAM dictionary file: FOAM_HEADER % (class, object).
FOAM_HEADER = "FoamFile\n{\n    version 2.0;\n    format ascii;\n    class %s;\n    object %s;\n}\n"


def write_foam_files(case, files):
    """Writes {relative path: text} under the OpenFOAM case directory."""
    for rel, text in files.items():
        os.makedirs(os.path.dirname(os.path.join(case, rel)), exist_ok=True)
        with open(os.path.join(case, rel), "w") as f:
            f.write(text)


def foam_internal_field(path):
    """The values of an OpenFOAM field file's nonuniform internalField: a list
    of floats (scalar) or of tuples (vector), or None."""
    with open(path) as f:
        text = f.read()
    m = re.search(r"internalField\s+nonuniform\s+List<(\w+)>\s*(\d+)\s*\((.*?)\)\s*;", text, re.S)
    if not m:
        return None
    body = m.group(3)
    if m.group(1) == "scalar":
        return [float(x) for x in body.split()]
    return [tuple(float(x) for x in v.split()) for v in re.findall(r"\(([^()]*)\)", body)]


def foam_patch_sum(path, patch):
    """The sum of a surface scalar field's values on one patch (e.g. phi: the
    flux through it), from its boundaryField entry, or None."""
    with open(path) as f:
        text = f.read()
    m = re.search(r"\n\s*%s\s*\{(.*?)\n\s*\}" % re.escape(patch), text, re.S)
    if not m:
        return None
    body = m.group(1)
    mm = re.search(r"value\s+nonuniform\s+List<scalar>\s*\d+\s*\((.*?)\)\s*;", body, re.S)
    if mm:
        return sum(float(x) for x in mm.group(1).split())
    mm = re.search(r"value\s+uniform\s+([-0-9.eE+]+)\s*;", body)
    return None if not mm else (0.0 if float(mm.group(1)) == 0 else None)


def obj_volume(path):
    """Volume enclosed by an OBJ polygon surface (surfacecheck's reading and volume)."""
    import surfacecheck
    return surfacecheck.enclosed_volume(*surfacecheck.read_surface(path))


def polygon_area(pts):
    """Area of a planar polygon: half the length of its Newell normal."""
    n = [0.0, 0.0, 0.0]
    for i in range(len(pts)):
        a, b = pts[i], pts[(i + 1) % len(pts)]
        n[0] += (a[1] - b[1]) * (a[2] + b[2])
        n[1] += (a[2] - b[2]) * (a[0] + b[0])
        n[2] += (a[0] - b[0]) * (a[1] + b[1])
    return 0.5 * sum(x * x for x in n) ** 0.5


def seeds_csv(path):
    """The x, y, z of a seeds CSV (header line, rows x,y,z[,label])."""
    with open(path) as f:
        next(f)
        return [tuple(float(x) for x in line.split(",")[:3]) for line in f if line.strip()]


def locator(points):
    """A VTK k-d tree locator over the points (x, y, z tuples)."""
    import vtk
    P = vtk.vtkPoints()
    for x in points:
        P.InsertNextPoint(*x)
    pd = vtk.vtkPolyData()
    pd.SetPoints(P)
    loc = vtk.vtkKdTreePointLocator()
    loc.SetDataSet(pd)
    loc.BuildLocator()
    return loc


def seeds_outside_balls_and_inside(tag, seeds, n_surface, balls, clearance=0.0):
    """Checks that every interior seed (seeds: ((x, y, z), label), the first
    n_surface the surface seeds) lies outside every ball (balls: ((x, y, z),
    radius)) grown by the clearance (1 + clearance times its radius: the
    interior seeds' VC_INTERIOR_CLEARANCE), except the ball on whose sphere
    it lies, if any (a pole or cap seed, a tie at the ball centre), and that
    its nearest surface seed is an inside seed of its own label."""
    import math
    import vtk
    rmax = max(r for _, r in balls) * (1 + clearance)
    ball_loc = locator([c for c, _ in balls])
    surf_loc = locator([s[0] for s in seeds[:n_surface]])
    near = vtk.vtkIdList()
    in_ball = outside = 0
    for x, lab in seeds[n_surface:]:
        ball_loc.FindPointsWithinRadius(rmax, x, near)
        for k in range(near.GetNumberOfIds()):
            c, r = balls[near.GetId(k)]
            d = math.dist(c, x)
            if abs(d - r) <= 1e-9 * r:
                continue  # on this ball's sphere
            in_ball += d < r * (1 + clearance) * (1 - 1e-9)
        q = surf_loc.FindClosestPoint(x)
        outside += seeds[q][1] != lab or lab == 0
    check(in_ball == 0, "%s: %d interior seeds inside a surface ball grown by %g of its radius"
          % (tag, in_ball, clearance))
    check(outside == 0, "%s: %d interior seeds whose nearest surface seed is outside or of "
          "another region" % (tag, outside))
