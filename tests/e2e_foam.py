"""End-to-end tests of the OpenFOAM output, `vorocrust voronoi --foam CASE_DIR`.

Every case is judged by OpenFOAM's own checkMesh (Debian package openfoam:
exit 0 and "Mesh OK.") and read back here: the FoamFile headers (class,
object, the owner/neighbour note), the counts against the .vtu of the same
run (read with VTK 9.1), every point equal to the .vtu's (17 digits read
back exactly), every cell's faces equal to the .vtu cell's faces with the
same orientation, owner < neighbour in upper-triangular order, every face
pointing from its owner's centre towards its neighbour's (or out of the
domain), boundary patches contiguous after the interior faces and summing to
the boundary face count, wall patches on their wall.

Meshes: (a) random seeds in a box (with a minimum spacing, and
uniform ones, whose Voronoi cells may fail checkMesh's skewness limit: the
only failure allowed there), (b) a cubic lattice (hexahedra),
(c) models/ball-seeds.csv (co-spherical VoroCrust seeds, patch "surface"),
(d) labelled seeds with label 0 (patch "surface" and wall patches),
(e) writing into an existing case (polyMesh replaced, the user's system/
files and 0/ kept), (f) `vorocrust mesh` of torus.obj, bracket.obj,
fandisk.off and fertility.off: "Mesh OK." for the default case (skew faces
collapsed), and the exact case (--foam-max-skew 0) read back face by face. Bad cases: CASE_DIR's parent missing, CASE_DIR a file,
constant/polyMesh a file in an existing case (fails after the .vtu is
written: no output is left).

checkMesh: $VC_CHECKMESH if set; otherwise the OpenFOAM environment script
(etc/bashrc of /usr/share/openfoam on Debian 12, or /usr/lib/openfoam/
openfoam*/, /opt/openfoam*/, ...) is sourced once and checkMesh found on
its PATH. Debian 12 installs /usr/bin/checkMesh, which needs WM_PROJECT_DIR
(set by the script) to find its etc/controlDict.

Usage: e2e_foam.py PART: "synthetic" ((a) to (e) and the bad cases, from the
repository alone) or one model of (f) (fertility.off: the extended suite):
MODEL the default case, MODEL+exact the exact case (--foam-max-skew 0,
--connections), torus.obj+threads the default case with 1 and 2 threads;
one ctest test per part (tests/CMakeLists.txt). A model part skips (exit 77)
when the shared models directory is missing.

Environment: VC_BIN, VC_SOURCE, VC_TMP, VC_MODELS.
"""
import math
import os
import random
import re
import shutil
import subprocess
import sys

sys.path.insert(0, os.path.join(os.environ["VC_SOURCE"], "tests"))
import vtk  # noqa: E402
import vtkcheck  # noqa: E402

BIN = os.environ["VC_BIN"]
SOURCE = os.environ["VC_SOURCE"]
import e2eutil  # noqa: E402
from e2eutil import models_dir  # noqa: E402

# One part per ctest test (tests/CMakeLists.txt): "synthetic" (a) to (e) and
# the bad cases, from the repository alone; or one model of (f).
PARTS = ("synthetic", "torus.obj", "bracket.obj", "fandisk.off", "fertility.off", "bunny.off",
         "torus.obj+exact",
         "bracket.obj+exact", "fandisk.off+exact", "torus.obj+threads")
if len(sys.argv) != 2 or sys.argv[1] not in PARTS:
    print("usage: e2e_foam.py PART, PART one of %s" % ", ".join(PARTS), file=sys.stderr)
    sys.exit(2)
PART = sys.argv[1]
TMP = os.path.join(os.environ.get("VC_TMP", "/tmp"), "e2e_foam",
                   PART.replace(".", "_").replace("+", "_"))
shutil.rmtree(TMP, ignore_errors=True)
os.makedirs(TMP)
if PART != "synthetic":
    MODELS = models_dir()  # exits 77 (skipped) when the shared models are missing
failures = []
summary = []


def check(cond, what):
    if not cond:
        failures.append(what)
        print("FAIL:", what, file=sys.stderr)
    return cond


# ---- checkMesh -----------------------------------------------------------

CHECKMESH, FOAM_ENV = e2eutil.find_checkmesh()
print("checkMesh: %s (WM_PROJECT_DIR=%s)" % (CHECKMESH, FOAM_ENV.get("WM_PROJECT_DIR")))


def checkmesh(name, case, cells, allow_skew=False):
    p = subprocess.run([CHECKMESH, "-case", case], capture_output=True, text=True,
                       env=FOAM_ENV, cwd=TMP, timeout=600)
    out = p.stdout + p.stderr
    with open(os.path.join(TMP, name + ".checkMesh.log"), "w") as f:
        f.write(out)
    failed = [ln.strip() for ln in out.split("\n") if ln.strip().startswith("***")]
    if allow_skew and p.returncode == 0 and "\nFailed 1 mesh checks." in out and \
            len(failed) == 1 and "highly skew faces" in failed[0]:
        summary.append("%s: checkMesh fails only the skewness check: %s" % (name, failed[0]))
        ok = True
    else:
        ok = check(p.returncode == 0 and "\nMesh OK." in out and "Failed" not in out
                   and not failed, "%s: checkMesh exit %d, no 'Mesh OK.':\n%s"
                   % (name, p.returncode, out[-3000:]))
    m = re.search(r"^\s*cells:\s+(\d+)", out, re.M)
    check(m and int(m.group(1)) == cells, "%s: checkMesh counts %s cells, expected %d"
          % (name, m.group(1) if m else "no", cells))

    def grab(pattern):
        mm = re.search(pattern, out, re.M)
        return mm.group(1) if mm else "?"
    summary.append("%s: checkMesh %s; cells %s, faces %s (internal %s), points %s; "
                   "non-orthogonality max %s, skewness max %s, aspect ratio max %s"
                   % (name, "Mesh OK." if "\nMesh OK." in out else
                      "allowed failure (skewness)" if ok else "FAILED", grab(r"^\s*cells:\s+(\d+)"),
                      grab(r"^\s*faces:\s+(\d+)"), grab(r"^\s*internal faces:\s+(\d+)"),
                      grab(r"^\s*points:\s+(\d+)"), grab(r"non-orthogonality Max: ([\d.e+-]+)"),
                      grab(r"Max skewness = ([\d.e+-]+)"), grab(r"Max aspect ratio = ([\d.e+-]+)")))
    return out


# ---- the files ------------------------------------------------------------

def read_foam(path):
    """(header dict, body text) of an ASCII OpenFOAM file, comments removed."""
    with open(path) as f:
        text = f.read()
    text = re.sub(r"/\*.*?\*/", " ", text, flags=re.S)
    text = re.sub(r"//[^\n]*", " ", text)
    m = re.match(r"\s*FoamFile\s*\{(.*?)\}", text, re.S)
    if not m:
        raise ValueError("%s: no FoamFile header" % path)
    header = {}
    for entry in m.group(1).split(";"):
        entry = entry.strip()
        if entry:
            k, v = entry.split(None, 1)
            header[k] = v.strip().strip('"')
    return header, text[m.end():]


def list_body(path, body):
    """The entries of 'N ( ... )': the text between the outer parentheses
    and N."""
    m = re.match(r"\s*(\d+)\s*\((.*)\)\s*$", body, re.S)
    if not m:
        raise ValueError("%s: not a list 'N ( ... )'" % path)
    return int(m.group(1)), m.group(2)


def read_case(name, case):
    """Reads constant/polyMesh; returns a dict or None (failures recorded)."""
    pm = os.path.join(case, "constant", "polyMesh")
    want = {"points": "vectorField", "faces": "faceList", "owner": "labelList",
            "neighbour": "labelList", "boundary": "polyBoundaryMesh"}
    mesh = {}
    try:
        for obj, cls in want.items():
            h, body = read_foam(os.path.join(pm, obj))
            check(h.get("class") == cls and h.get("object") == obj and h.get("format") == "ascii"
                  and h.get("version") == "2.0" and h.get("location") == "constant/polyMesh",
                  "%s: %s header %r" % (name, obj, h))
            mesh[obj + "_header"] = h
            if obj == "boundary":
                n, inner = list_body(obj, body)
                patches = re.findall(r"(\w+)\s*\{([^}]*)\}", inner)
                check(len(patches) == n, "%s: boundary announces %d patches, has %d"
                      % (name, n, len(patches)))
                mesh["patches"] = []
                for pname, d in patches:
                    kv = dict(re.findall(r"(\w+)\s+([^;]+);", d))
                    mesh["patches"].append((pname, kv.get("type"), int(kv["nFaces"]),
                                            int(kv["startFace"])))
                continue
            n, inner = list_body(obj, body)
            if obj == "points":
                vals = re.findall(r"\(([^()]*)\)", inner)
                pts = [tuple(float(x) for x in v.split()) for v in vals]
                check(all(len(p) == 3 for p in pts), "%s: a point has not 3 coordinates" % name)
                mesh["points"] = pts
            elif obj == "faces":
                vals = re.findall(r"(\d+)\s*\(([^()]*)\)", inner)
                faces = [[int(x) for x in v.split()] for _, v in vals]
                check(all(int(k) == len(f) for (k, _), f in zip(vals, faces)),
                      "%s: a face's size prefix is wrong" % name)
                mesh["faces"] = faces
            else:
                mesh[obj] = [int(x) for x in inner.split()]
            check(len(mesh[obj]) == n, "%s: %s announces %d entries, has %d"
                  % (name, obj, n, len(mesh[obj])))
    except (OSError, ValueError, KeyError) as e:
        check(False, "%s: cannot read the case: %s" % (name, e))
        return None
    for obj in ("owner", "neighbour"):
        note = mesh[obj + "_header"].get("note", "")
        m = re.match(r"nPoints:\s*(\d+)\s+nCells:\s*(\d+)\s+nFaces:\s*(\d+)\s+"
                     r"nInternalFaces:\s*(\d+)$", note)
        if check(m, "%s: %s note %r" % (name, obj, note)):
            mesh["note"] = tuple(int(x) for x in m.groups())
    return mesh


def newell(pts):
    n = [0.0, 0.0, 0.0]
    for a, b in zip(pts, pts[1:] + pts[:1]):
        n[0] += (a[1] - b[1]) * (a[2] + b[2])
        n[1] += (a[2] - b[2]) * (a[0] + b[0])
        n[2] += (a[0] - b[0]) * (a[1] + b[1])
    return n


def mean(pts):
    return [sum(p[k] for p in pts) / len(pts) for k in range(3)]


def same_cycle(a, b):
    if len(a) != len(b) or a[0] not in b:
        return False
    i = b.index(a[0])
    return a == b[i:] + b[:i]


WALLS = {"xmin": (0, 0), "xmax": (0, 1), "ymin": (1, 0), "ymax": (1, 1), "zmin": (2, 0),
         "zmax": (2, 1)}


def check_case(name, case, vtu, box=None, expect_patches=None):
    """Every check of the module docstring against the .vtu of the run."""
    mesh = read_case(name, case)
    if mesh is None:
        return None
    grid = vtkcheck.read_vtu(vtu)
    pts, faces, own, nei = mesh["points"], mesh["faces"], mesh["owner"], mesh["neighbour"]
    nc = grid.GetNumberOfCells()
    nf, ni = len(faces), len(nei)
    check(mesh.get("note") == (len(pts), nc, nf, ni),
          "%s: note %r, expected %r" % (name, mesh.get("note"), (len(pts), nc, nf, ni)))
    check(len(own) == nf, "%s: %d owners for %d faces" % (name, len(own), nf))
    # Points: the .vtu's, exactly.
    check(len(pts) == grid.GetNumberOfPoints(), "%s: %d points, .vtu has %d"
          % (name, len(pts), grid.GetNumberOfPoints()))
    if len(pts) == grid.GetNumberOfPoints():
        off = sum(1 for i, p in enumerate(pts) if p != grid.GetPoint(i))
        check(off == 0, "%s: %d points differ from the .vtu's" % (name, off))
    check(all(len(f) >= 3 and all(0 <= v < len(pts) for v in f) for f in faces),
          "%s: a face has < 3 vertices or a vertex out of range" % name)
    check(all(0 <= c < nc for c in own) and all(0 <= c < nc for c in nei),
          "%s: a cell index is out of range" % name)
    # Upper-triangular order, owner < neighbour.
    check(all(own[f] < nei[f] for f in range(ni)), "%s: an interior face has owner >= neighbour"
          % name)
    pairs = list(zip(own[:ni], nei))
    check(all(a < b for a, b in zip(pairs, pairs[1:])),
          "%s: interior faces are not in upper-triangular order" % name)
    # Every cell's faces are the .vtu cell's faces, same orientation
    # (the .vtu writes each face outward for its cell).
    per_cell = [[] for _ in range(nc)]
    for f in range(nf):
        per_cell[own[f]].append(faces[f])
        if f < ni:
            per_cell[nei[f]].append(list(reversed(faces[f])))
    ids = vtk.vtkIdList()
    bad = 0
    for c in range(nc):
        vf = vtkcheck.cell_faces(grid, c, ids)
        by_key = {tuple(sorted(f)): f for f in vf}
        if len(vf) != len(per_cell[c]):
            bad += 1
            continue
        for f in per_cell[c]:
            g = by_key.get(tuple(sorted(f)))
            if g is None or not same_cycle(f, g):
                bad += 1
                break
    check(bad == 0, "%s: %d cells whose faces differ from the .vtu's (set or orientation)"
          % (name, bad))
    # Orientation, geometrically: from the owner's centre towards the
    # neighbour's, out of the domain on the boundary (the vertex mean of a
    # convex cell is inside it).
    centre = []
    for c in range(nc):
        vs = sorted(set(v for f in per_cell[c] for v in f))
        centre.append(mean([pts[v] for v in vs]))
    wrong = 0
    for f in range(nf):
        fp = [pts[v] for v in faces[f]]
        n = newell(fp)
        fc = mean(fp)
        a = centre[own[f]]
        b = centre[nei[f]] if f < ni else fc
        d = [b[k] - a[k] for k in range(3)]
        if sum(n[k] * d[k] for k in range(3)) <= 0:
            wrong += 1
    check(wrong == 0, "%s: %d faces do not point from owner to neighbour (or outward)"
          % (name, wrong))
    # Patches: contiguous after the interior faces, covering the boundary.
    patches = mesh["patches"]
    start = ni
    for pname, ptype, n, s in patches:
        # the surface of an input without groups is a wall, the box's walls patches
        want_type = "wall" if pname.endswith("surface") else "patch"
        check(s == start and n > 0 and ptype == want_type,
              "%s: patch %s (type %s) starts at %d with %d faces, expected start %d"
              % (name, pname, ptype, s, n, start))
        start = s + n
    check(start == nf, "%s: the patches end at face %d of %d" % (name, start, nf))
    check(sum(p[2] for p in patches) == nf - ni, "%s: patch sizes sum to %d, boundary has %d"
          % (name, sum(p[2] for p in patches), nf - ni))
    names = [p[0] for p in patches]
    if expect_patches is not None:
        check(names == expect_patches, "%s: patches %r, expected %r"
              % (name, names, expect_patches))
    for pname, ptype, n, s in patches:
        if pname in WALLS and box:
            axis, side = WALLS[pname]
            w = box[axis + 3 * side]
            off = [f for f in range(s, s + n) if any(pts[v][axis] != w for v in faces[f])]
            check(not off, "%s: %d faces of patch %s are not on the wall %s = %r"
                  % (name, len(off), pname, "xyz"[axis], w))
        elif pname == "surface" and box:
            on = [f for f in range(s, s + n)
                  if any(all(pts[v][a] == box[a + 3 * sd] for v in faces[f])
                         for a in range(3) for sd in range(2))]
            check(not on, "%s: %d faces of patch surface lie on the box" % (name, len(on)))
    return mesh


def run(*args):
    p = subprocess.run([BIN, "voronoi", *args], capture_output=True, text=True, timeout=600)
    return p.returncode, p.stdout, p.stderr


def write_seeds(name, rows):
    path = os.path.join(TMP, name)
    with open(path, "w") as f:
        f.write("x,y,z,label\n")
        for r in rows:
            f.write(",".join(repr(float(v)) for v in r[:3]) + "," + str(r[3]) + "\n")
    return path


def mesh_case(name, seeds_path, cells, box=None, expect_patches=None, case=None,
              allow_skew=False):
    vtu = os.path.join(TMP, name + ".vtu")
    case = case or os.path.join(TMP, name)
    args = [seeds_path, "-o", vtu, "--foam", case, "--quiet"]
    if box:
        args += ["--box"] + [repr(float(v)) for v in box]
    rc, so, se = run(*args)
    if not check(rc == 0 and se == "", "%s: exit %d, stderr %r" % (name, rc, se)):
        return None
    out = checkmesh(name, case, cells, allow_skew)
    mesh = check_case(name, case, vtu, box, expect_patches)
    left = [e for e in os.listdir(TMP) if ".tmp." in e or ".old." in e]
    check(not left, "%s: temporaries left behind: %r" % (name, left))
    return mesh, out


if PART == "synthetic":
    # =========================================================================
    # (a) Random seeds in a box, no two closer than 0.6 times the mean spacing
    #     (dart throwing; VoroCrust's seeds have such a spacing too)
    # =========================================================================
    rng = random.Random(4)
    box = (0.0, 0.0, 0.0, 1.0, 1.0, 1.0)
    rand = []
    while len(rand) < 400:
        p = (rng.random(), rng.random(), rng.random())
        if all(sum((p[i] - q[i]) ** 2 for i in range(3)) > (0.6 * 400 ** (-1 / 3)) ** 2 for q in rand):
            rand.append(p + (1,))
    p_rand = write_seeds("random.csv", rand)
    mesh_case("random", p_rand, 400, box, ["xmin", "xmax", "ymin", "ymax", "zmin", "zmax"])
    # Uniform (Poisson) seeds: the writer's output is as valid, but such a
    # Voronoi mesh may hold a face skewer than checkMesh's limit (4): that is
    # the only check allowed to fail.
    rng = random.Random(4)
    poisson = [(rng.random(), rng.random(), rng.random(), 1) for _ in range(400)]
    p_poisson = write_seeds("poisson.csv", poisson)
    mesh_case("poisson", p_poisson, 400, box, ["xmin", "xmax", "ymin", "ymax", "zmin", "zmax"],
              allow_skew=True)

    # =========================================================================
    # (b) A cubic lattice: hexahedra
    # =========================================================================
    k = 6
    h = 1.0 / k
    lat = [((i + 0.5) * h, (j + 0.5) * h, (m + 0.5) * h, 1)
           for i in range(k) for j in range(k) for m in range(k)]
    p_lat = write_seeds("lattice.csv", lat)
    r = mesh_case("lattice", p_lat, k ** 3, box, ["xmin", "xmax", "ymin", "ymax", "zmin", "zmax"])
    if r:
        mesh, out = r
        check(re.search(r"hexahedra:\s+%d\b" % k ** 3, out), "lattice: checkMesh sees no %d hexahedra"
              % k ** 3)
        check(len(mesh["faces"]) == 3 * k * k * (k + 1) and len(mesh["neighbour"]) == 3 * k * k * (k - 1),
              "lattice: %d faces, %d interior" % (len(mesh["faces"]), len(mesh["neighbour"])))
        check(all(p[2] == k * k for p in mesh["patches"]), "lattice: patch sizes %r" % mesh["patches"])

    # =========================================================================
    # (c) The bundled VoroCrust-style ball: one closed patch "surface"
    # =========================================================================
    p_ball = os.path.join(SOURCE, "models", "ball-seeds.csv")
    with open(p_ball) as f:
        n_ball = sum(1 for row in list(f)[1:] if row.strip() and row.strip().split(",")[3] != "0")
    r = mesh_case("ball", p_ball, n_ball, None, ["surface"])
    if r:
        check("ok (closed singly connected)" in r[1], "ball: the surface patch is not closed")

    # =========================================================================
    # (d) Labelled seeds: label 0 for x > 0.6, labels 1 and 2 elsewhere: per
    #     region, a "surface" patch against the dropped seeds and walls
    #     (e2e_materials checks the cell and face zones)
    # =========================================================================
    rng = random.Random(5)
    lab = []
    for _ in range(600):
        x, y, z = rng.random(), rng.random(), rng.random()
        lab.append((x, y, z, 0 if x > 0.6 else rng.choice((1, 2))))
    p_lab = write_seeds("labels.csv", lab)
    kept = sum(1 for s in lab if s[3])
    r = mesh_case("labels", p_lab, kept, box, ["region%d_%s" % (k, p) for k in (1, 2) for p in
                                               ("surface", "xmin", "ymin", "ymax", "zmin", "zmax")])

    # =========================================================================
    # (e) Into an existing case: polyMesh replaced as a whole, the user's
    #     system/ files and other directories kept; a trailing slash is fine
    # =========================================================================
    case = os.path.join(TMP, "existing")
    os.makedirs(os.path.join(case, "0"))
    os.makedirs(os.path.join(case, "system"))
    os.makedirs(os.path.join(case, "constant", "polyMesh", "sets"))
    with open(os.path.join(case, "0", "p"), "w") as f:
        f.write("user field\n")
    with open(os.path.join(case, "constant", "polyMesh", "cellZones"), "w") as f:
        f.write("stale\n")
    with open(os.path.join(case, "constant", "polyMesh", "sets", "old"), "w") as f:
        f.write("stale\n")
    shutil.copy(os.path.join(TMP, "random", "system", "controlDict"), os.path.join(case, "system"))
    with open(os.path.join(case, "system", "controlDict"), "a") as f:
        f.write("// user edit\n")
    r = mesh_case("existing", p_lat, k ** 3, box, ["xmin", "xmax", "ymin", "ymax", "zmin", "zmax"],
                  case=case + "/")
    if r:
        with open(os.path.join(case, "system", "controlDict")) as f:
            check("// user edit" in f.read(), "existing: the user's controlDict was overwritten")
        check(os.path.isfile(os.path.join(case, "system", "fvSchemes")),
              "existing: the missing fvSchemes was not added")
        check(os.path.isfile(os.path.join(case, "0", "p")), "existing: 0/p is gone")
        check(sorted(os.listdir(os.path.join(case, "constant", "polyMesh"))) ==
              ["boundary", "faces", "neighbour", "owner", "points"],
              "existing: polyMesh holds %r" % os.listdir(os.path.join(case, "constant", "polyMesh")))
        check(sorted(os.listdir(os.path.join(case, "constant"))) == ["polyMesh"],
              "existing: constant/ holds %r" % os.listdir(os.path.join(case, "constant")))
    # And again over itself with another mesh; a new case named with a slash.
    mesh_case("existing_again", p_rand, 400, box, case=case)
    mesh_case("slash", p_lat, k ** 3, box, case=os.path.join(TMP, "slash") + "/")


    # =========================================================================
    # Bad cases: one stderr line "vorocrust: ..." naming the case, non-zero
    # exit, nothing written (no .vtu, no case, no temporary)
    # =========================================================================
    def expect_error(name, case, needles, extra=()):
        vtu = os.path.join(TMP, "bad_%s.vtu" % name)
        before = sorted(os.listdir(TMP))
        rc, so, se = run(p_rand, "-o", vtu, "--box", "0", "0", "0", "1", "1", "1", "--foam", case,
                         "--quiet", *extra)
        lines = se.strip("\n").split("\n") if se else []
        check(rc != 0, "%s: exit code 0" % name)
        check(len(lines) == 1 and lines[0].startswith("vorocrust: ") and case in lines[0]
              and all(n in lines[0] for n in needles),
              "%s: stderr %r should be one line 'vorocrust: ' naming %r with %r"
              % (name, se, case, needles))
        after = sorted(os.listdir(TMP))
        check(after == before, "%s: left %r behind" % (name, sorted(set(after) - set(before))))


    expect_error("missing_parent", os.path.join(TMP, "no_such_dir", "case"),
                 ["directory missing or not writable"])
    as_file = os.path.join(TMP, "a_file")
    with open(as_file, "w") as f:
        f.write("not a case\n")
    expect_error("case_is_file", as_file, ["Not a directory"])
    with open(as_file) as f:
        check(f.read() == "not a case\n", "case_is_file: the file was changed")
    expect_error("parent_is_file", os.path.join(as_file, "case"), ["cannot write"])
    if os.geteuid() != 0:  # root writes anywhere
        ro = os.path.join(TMP, "read_only")
        os.makedirs(ro)
        os.chmod(ro, 0o555)
        expect_error("read_only_parent", os.path.join(ro, "case"), ["cannot write"])
        os.chmod(ro, 0o755)
    # A failure after the .vtu is written: the .vtu and connections go too, the
    # case is left as it was.
    broken = os.path.join(TMP, "broken")
    os.makedirs(os.path.join(broken, "constant"))
    with open(os.path.join(broken, "constant", "polyMesh"), "w") as f:
        f.write("a file\n")
    expect_error("polymesh_is_file", broken, ["polyMesh", "Not a directory"],
                 ["--connections", os.path.join(TMP, "bad_conn.csv")])
    check(sorted(os.listdir(broken)) == ["constant"] and
          sorted(os.listdir(os.path.join(broken, "constant"))) == ["polyMesh"],
          "polymesh_is_file: the case was changed: %r" % os.listdir(broken))

# =========================================================================
# (f) `vorocrust mesh` on the reference models of issue #4 (torus.obj,
#     bracket.obj, fandisk.off, bunny.off (Release only); fertility.off in the extended suite, ctest
#     -L extended: about a minute in Release, several in the sanitized
#     build). checkMesh must print "Mesh OK." for the default case, whose faces above skewness 3.5 are collapsed
#     (--foam-max-skew). The default case is read back: the cell count, the
#     boundary (the reconstructed surface: the same faces on the same
#     points, exactly) and the total volume are the .vtu's; at most 2% of the
#     points moved and 5% of the faces changed. With --foam-max-skew 0 the
#     case is the exact Voronoi mesh, checked face by face against the .vtu,
#     and --connections lists its interior faces;
#     checkMesh then fails only its skewness check (needle faces between
#     neighbouring surface cells; the printed maximum may not grow).
# =========================================================================
# model -> checkMesh's max skewness of the exact Voronoi case (recorded;
# fandisk.off's 11.1 became 15.5 when its second sampling went from 45 to
# 20 degrees: more creases, more needle faces between surface cells). The
# maximum is one face's: over --seed 1 to 3 it spans 4.79 to 5.52 on torus
# and 10.6 to 14.9 on bracket, with the centre lift or without; the lift
# (session 14) gave seed 1 5.28 and 13.36, with as many highly skew faces
# (bracket 411 against 413, torus 20 against 18). fandisk.off 17.17 since
# it is sampled at 60 degrees (session 14), with half the balls. Session 15
# samples again only where shrunk balls left ground uncovered (other darts):
# bracket 17.18 with 405 highly skew faces (was 411), one face's figure.
# Session 34: interior seeds keep a clearance of 0.1 radius from every ball
# (VC_INTERIOR_CLEARANCE): torus 4.31 (1 face above 4), bracket 7.65 (105),
# fandisk 6.78 (32). bunny.off, whose OpenFOAM case was refused (after the
# collapse one face kept 6.13), passes checkMesh: exact 13.7 (223 faces).
# Then seeds spread over the spheres of corner and edge balls (caps,
# vc_interior_sphere_seeds): bracket 4.15 (1 face), fandisk 3.93 (the exact
# case passes checkMesh), bunny.off 4.97 (5 faces; 42 collapsed).
# Session 39 samples a solid in an order of its geometry (the darts fall
# elsewhere): fandisk 4.23 (4 faces). Its 3.93 was one draw's: --seed 2 to
# 4 gave 4.53, 4.54 and 4.32 then, 4.40, 4.48 and 4.83 now.
SKEW_EXACT = {"torus.obj": 4.4, "bracket.obj": 4.2, "fandisk.off": 4.3,
              "fertility.off": 5.2, "bunny.off": 5.0}
FULL_READBACK = ("torus.obj", "bracket.obj", "fandisk.off")  # fertility: too slow in Python
# Exact cases run through `checkMesh -allGeometry -allTopology` (issue
# 20's acceptance): every check but the skewness (above) must pass.
EXACT_ALL_CHECKS = ("fandisk.off",)


def checkmesh_all(name, case):
    """checkMesh -allGeometry -allTopology: no failed check but the skewness."""
    p = subprocess.run([CHECKMESH, "-allGeometry", "-allTopology", "-case", case],
                       capture_output=True, text=True, env=FOAM_ENV, cwd=TMP, timeout=600)
    out = p.stdout + p.stderr
    with open(os.path.join(TMP, name + ".checkMesh-all.log"), "w") as f:
        f.write(out)
    failed = [ln.strip() for ln in out.split("\n") if ln.strip().startswith("***")]
    other = [ln for ln in failed if "skewness" not in ln]
    if check(p.returncode == 0 and not other and ("\nMesh OK." in out or failed),
             "%s: checkMesh -allGeometry -allTopology exit %d, failed: %r"
             % (name, p.returncode, other)):
        summary.append("%s: checkMesh -allGeometry -allTopology: %s" % (name, failed or "Mesh OK."))


def vtu_total_volume(grid):
    vols = grid.GetCellData().GetArray("volume")
    return math.fsum(vols.GetValue(i) for i in range(grid.GetNumberOfCells()))


def check_collapsed_case(name, case, vtu):
    """The collapsed case against the exact .vtu: same cells, same boundary
    faces on the same points, and the changed faces all touch moved points."""
    mesh = read_case(name, case)
    if mesh is None:
        return
    grid = vtkcheck.read_vtu(vtu)
    pts, faces, own, nei = mesh["points"], mesh["faces"], mesh["owner"], mesh["neighbour"]
    ni = len(nei)
    nc = grid.GetNumberOfCells()
    check(max(own + nei) == nc - 1 and min(own) == 0, "%s: cells 0..%d expected" % (name, nc - 1))
    check(all(own[f] < nei[f] for f in range(ni)), "%s: an interior face has owner >= neighbour"
          % name)
    pairs = list(zip(own[:ni], nei))
    check(all(x < y for x, y in zip(pairs, pairs[1:])),
          "%s: interior faces are not in upper-triangular order" % name)
    vpts = [grid.GetPoint(i) for i in range(grid.GetNumberOfPoints())]
    vindex = {p: i for i, p in enumerate(vpts)}
    # every .vtu face by its point coordinates, per cell
    ids = vtk.vtkIdList()
    vtu_faces = set()
    vtu_boundary = []
    seen = {}
    for c in range(nc):
        for f in vtkcheck.cell_faces(grid, c, ids):
            key = tuple(sorted(f))
            vtu_faces.add(key)
            seen[key] = seen.get(key, 0) + 1
    for c in range(nc):
        for f in vtkcheck.cell_faces(grid, c, ids):
            if seen[tuple(sorted(f))] == 1:
                vtu_boundary.append(tuple(sorted(f)))
    case_key = []
    moved = set()
    for i, p in enumerate(pts):
        if tuple(p) not in vindex:
            moved.add(i)
    for f in faces:
        case_key.append(tuple(sorted(vindex.get(tuple(pts[v]), -1 - v) for v in f)))
    boundary = sorted(case_key[ni:])
    check(boundary == sorted(vtu_boundary), "%s: the boundary differs from the .vtu's "
          "(%d faces, .vtu %d)" % (name, len(boundary), len(vtu_boundary)))
    changed = [f for f in range(len(faces)) if case_key[f] not in vtu_faces]
    check(len(changed) <= 0.05 * len(faces), "%s: %d of %d faces changed"
          % (name, len(changed), len(faces)))
    check(len(moved) <= 0.02 * len(pts), "%s: %d of %d points moved" % (name, len(moved), len(pts)))
    summary.append("%s: collapsed case: %d points moved (of %d), %d faces changed, %d interior "
                   "faces (.vtu %d)" % (name, len(moved), len(pts), len(changed), ni,
                                        (len(vtu_faces) - len(vtu_boundary))))


model_part, _, mode = PART.partition("+")
for model, skew_rec in SKEW_EXACT.items():
    if model != model_part:
        continue
    path = os.path.join(MODELS, model)
    if not os.path.exists(path):
        check(False, "%s: model not found (VC_MODELS=%r)" % (model, MODELS))
        continue
    name = "model_" + model.replace(".", "_")
    vtu = os.path.join(TMP, name + ".vtu")
    case, exact = os.path.join(TMP, name), os.path.join(TMP, name + "_exact")
    if mode in ("", "threads"):
        p = subprocess.run([BIN, "mesh", path, "-o", vtu, "--foam", case], capture_output=True,
                           text=True, timeout=1800)
        if not check(p.returncode == 0, "%s: mesh exit %d: %s" % (model, p.returncode, p.stderr[-2000:])):
            continue
        line = [ln.strip() for ln in p.stderr.split("\n") if "OpenFOAM case:" in ln]
        check(line, "%s: no 'OpenFOAM case:' line in the summary" % model)
        summary.append("%s: %s" % (model, line[0] if line else "?"))
        if not mode:
            grid = vtkcheck.read_vtu(vtu)
            cells = grid.GetNumberOfCells()
            # the steps after the cells take seconds on large meshes: each
            # says so (issue 16's progress lines, from 50,000 cells: bunny)
            for line in ("mesh: ordering and checking %d cells" % cells,
                         "mesh: %d cells valid; measuring them" % cells,
                         "mesh: writing %s, %s" % (vtu, case)):
                check((line in p.stderr) == (cells >= 50000), "%s: %d cells, progress line %r %s"
                      % (model, cells, line, "missing" if cells >= 50000 else "printed"))
            out = checkmesh(name, case, cells)
            m = re.search(r"Total volume = ([\d.e+-]+?)\.?\s", out)
            total = vtu_total_volume(grid)
            check(m and abs(float(m.group(1)) - total) <= 1e-9 * abs(total),
                  "%s: checkMesh total volume %s, .vtu %.17g" % (model, m.group(1) if m else "?", total))
        if mode == "threads":
            # the collapse is serial: the same case with one thread
            case1 = case + "_1thread"
            p = subprocess.run([BIN, "mesh", path, "-o", vtu + ".1.vtu", "--foam", case1, "--threads",
                                "1", "--quiet"], capture_output=True, text=True, timeout=1800)
            if check(p.returncode == 0, "%s: 1-thread mesh exit %d" % (model, p.returncode)):
                for obj in ("points", "faces", "owner", "neighbour", "boundary"):
                    a, b = (os.path.join(x, "constant", "polyMesh", obj) for x in (case, case1))
                    with open(a, "rb") as fa, open(b, "rb") as fb:
                        check(fa.read() == fb.read(), "%s: %s differs with 1 thread" % (model, obj))
    if not mode and model in FULL_READBACK:
        check_collapsed_case(name, case, vtu)
    if mode == "exact":
        # the exact Voronoi case, face by face against the same .vtu
        conn = os.path.join(TMP, name + "_connections.csv")
        p = subprocess.run([BIN, "mesh", path, "-o", vtu, "--foam", exact, "--foam-max-skew", "0",
                            "--connections", conn],
                           capture_output=True, text=True, timeout=1800)
        if check(p.returncode == 0, "%s: exact mesh exit %d: %s"
                 % (model, p.returncode, p.stderr[-2000:])):
            cells = vtkcheck.read_vtu(vtu).GetNumberOfCells()
            out = checkmesh(name + "_exact", exact, cells, allow_skew=True)
            if model in EXACT_ALL_CHECKS:
                checkmesh_all(name + "_exact", exact)
            m = re.search(r"Max skewness = ([\d.e+-]+)", out)
            skew = float(m.group(1)) if m else float("inf")
            check(skew <= 1.05 * skew_rec, "%s: exact case: checkMesh skewness max %g above the "
                  "recorded %g" % (model, skew, skew_rec))
            # the summary's solver measures are checkMesh's own (issue 20)
            ms = re.search(r"non-orthogonality max ([\d.]+) average ([\d.]+) degrees; skewness max "
                           r"([\d.]+) \((\d+) faces above 4\)", p.stderr)
            mo = re.search(r"Mesh non-orthogonality Max: ([\d.e+-]+) average: ([\d.e+-]+)", out)
            mh = re.search(r"(\d+) highly skew faces", out)
            if check(ms and mo, "%s: no solver measures in the summary, or no non-orthogonality "
                     "from checkMesh" % model):
                check(abs(float(ms.group(1)) - float(mo.group(1))) <= 0.06 and
                      abs(float(ms.group(2)) - float(mo.group(2))) <= 0.06,
                      "%s: non-orthogonality max/average %s/%s in the summary, checkMesh %s/%s"
                      % (model, ms.group(1), ms.group(2), mo.group(1), mo.group(2)))
                check(abs(float(ms.group(3)) - skew) <= 0.006 + 1e-3 * skew,
                      "%s: skewness max %s in the summary, checkMesh %g" % (model, ms.group(3), skew))
                # and the cells' figures are those `vorocrust quality` reads back from the .vtu
                q = subprocess.run([BIN, "quality", vtu], capture_output=True, text=True, timeout=600)
                mq = re.search(r"below 1e-2: ([\d.]+)%", q.stdout)
                mf = re.search(r"smallest face / enclosing radius\^2: min (\S+),", q.stdout)
                mm = re.search(r"([\d.]+)% of the cells below 1e-2; smallest face / radius\^2 min (\S+) ",
                               p.stderr)
                if check(mq and mf and mm, "%s: short-edge share or smallest face missing from the "
                         "summary or from vorocrust quality" % model):
                    check(abs(float(mq.group(1)) - float(mm.group(1))) <= 0.051,
                          "%s: short-edge share %s%% in the summary, %s%% from the .vtu"
                          % (model, mm.group(1), mq.group(1)))
                    check(abs(float(mf.group(1)) - float(mm.group(2))) <= 6e-3 * float(mf.group(1)),  # %.3g
                          "%s: smallest face / r^2 %s in the summary, %s from the .vtu"
                          % (model, mm.group(2), mf.group(1)))
                check(mh is None or int(mh.group(1)) == int(ms.group(4)),
                      "%s: %s faces above 4 in the summary, checkMesh %s" % (model, ms.group(4),
                                                                             mh.group(1) if mh else "?"))
            exact_mesh = check_case(name + "_exact", exact, vtu, None, ["surface"])
            # --connections: one row per interior face of the exact mesh
            with open(conn) as f:
                rows = f.read().split("\n")[1:]
            pairs = sorted(tuple(sorted(int(x) for x in r.split(",")[:2])) for r in rows
                           if r and r.split(",")[1] != "-1")
            if exact_mesh is not None:
                ni = len(exact_mesh["neighbour"])
                want = sorted(tuple(sorted(fc)) for fc in zip(exact_mesh["owner"][:ni],
                                                                exact_mesh["neighbour"]))
                check(pairs == want, "%s: --connections has %d rows, the exact case %d interior "
                      "faces (or other cell pairs)" % (model, len(pairs), ni))

for line in summary:
    print(line)
if failures:
    print("%d failures" % len(failures), file=sys.stderr)
    sys.exit(1)
print("e2e_foam %s: all checks passed" % PART)
