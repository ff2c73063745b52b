"""End-to-end test of the boundary patches (issue 21): a 4 x 1 x 1 duct whose
input names its inlet (x = 0), outlet (x = 4) and walls, as OBJ groups, as
the solids of an ASCII STL, as a PLY face property, and as two input files
(two regions); a group whose border crosses a flat face (borders are
protected as creases, so its area is exact); groups whose border zigzags
over a sphere's facets (weighed and not made creases: the balls of the
unsplit sphere); and the sharp-feature patches (--patches features).

Checked on every output: the summary's patches and areas (inlet 1, outlet
1, walls 16), OUT_boundary.vtu (read by VTK: patch names, per-patch area),
the connections CSV's boundary rows, the PFLOTRAN .ex files (one per
patch), the OpenFOAM boundary (names, --patch-type walls=wall, checkMesh
"Mesh OK."); and a solver runs on the patches: laplacianFoam (steady) with
T = 1 on the inlet, T = 0 on the outlet and insulated walls gives
T = 1 - x / 4 in every cell. A --patch-type naming no patch is refused.
Environment: VC_BIN, VC_TMP, VC_SOURCE."""
import csv
import os
import re
import shutil
import subprocess
import sys
from collections import defaultdict

sys.path.insert(0, os.path.join(os.environ["VC_SOURCE"], "tests"))
import vtkcheck  # noqa: E402
import e2eutil  # noqa: E402
from e2eutil import check, failures  # noqa: E402

BIN = os.environ["VC_BIN"]
TMP = os.path.join(os.environ.get("VC_TMP", "/tmp"), "e2e_patches")
shutil.rmtree(TMP, ignore_errors=True)
os.makedirs(TMP)
CHECKMESH, FOAM_ENV = e2eutil.find_checkmesh()
FOAM_BIN = os.path.dirname(CHECKMESH)

V = e2eutil.DUCT_V
FACES = e2eutil.DUCT_FACES
AREAS = {"inlet": 1.0, "outlet": 1.0, "walls": 16.0}


duct_obj = e2eutil.duct_obj


def duct_stl(path):
    with open(path, "w") as f:
        for name, tris in FACES.items():
            f.write("solid %s\n" % name)
            for t in tris:
                f.write(" facet normal 0 0 0\n  outer loop\n")
                f.writelines("   vertex %g %g %g\n" % V[i - 1] for i in t)
                f.write("  endloop\n endfacet\n")
            f.write("endsolid %s\n" % name)


def duct_ply(path):
    tris = [(t, k + 1) for k, (name, ts) in enumerate(FACES.items()) for t in ts]
    with open(path, "w") as f:
        f.write("ply\nformat ascii 1.0\nelement vertex 8\nproperty float x\nproperty float y\n"
                "property float z\nelement face %d\nproperty list uchar int vertex_indices\n"
                "property int patch\nend_header\n" % len(tris))
        f.writelines("%g %g %g\n" % v for v in V)
        f.writelines("3 %d %d %d %d\n" % (t[0] - 1, t[1] - 1, t[2] - 1, k) for t, k in tris)


def mesh(name, inputs, *extra):
    out = os.path.join(TMP, name)
    argv = [BIN, "mesh"] + inputs + ["-o", out + ".vtu", "--connections", out + ".csv", "--uge",
                                     out + ".uge", "--foam", out + "_case", "--threads", "2"]
    rc, so, err = e2eutil.run(argv + list(extra), timeout=110)
    check(rc == 0, "%s: exit %d: %s" % (name, rc, err[-800:]))
    return rc, err


def summary_patches(err):
    m = re.search(r"^  boundary patches: \d+: (.*)$", err, re.M)
    if not m:
        return {}
    return {p: float(a) for p, a in re.findall(r"(\w+) \(\d+ faces, area ([-0-9.e+]+)\)", m.group(1))}


def close(got, want, tol=1e-9):
    return sorted(got) == sorted(want) and all(abs(got[k] - want[k]) <= tol * max(1, want[k])
                                               for k in want)


def check_outputs(name, err, want):
    out = os.path.join(TMP, name)
    got = summary_patches(err)
    check(close(got, want), "%s: summary patches %r, expected %r" % (name, got, want))
    # the boundary .vtu
    grid = vtkcheck.read_vtu(out + "_boundary.vtu")
    names = grid.GetFieldData().GetAbstractArray("patch_names")
    names = [names.GetValue(i) for i in range(names.GetNumberOfValues())] if names else []
    patch = vtkcheck.cell_array(grid, "patch")
    area = defaultdict(float)
    for c in range(grid.GetNumberOfCells()):
        pts = vtk_points(grid, c)
        area[names[patch[c]]] += e2eutil.polygon_area(pts)
    check(close(dict(area), want, 1e-7), "%s: boundary .vtu areas %r" % (name, dict(area)))
    # the connections' boundary rows
    area = defaultdict(float)
    with open(out + ".csv") as f:
        for row in csv.DictReader(f):
            if row["cell_j"] == "-1":
                area[row["patch"]] += float(row["area"])
    check(close(dict(area), want), "%s: connections boundary areas %r" % (name, dict(area)))
    # PFLOTRAN: one .ex per patch
    ex = sorted(f[len(name) + 1:-3] for f in os.listdir(TMP) if f.startswith(name + "_") and f.endswith(".ex"))
    check(ex == sorted(want), "%s: .ex files for %r, expected %r" % (name, ex, sorted(want)))
    for p in ex:
        with open(os.path.join(TMP, "%s_%s.ex" % (name, p))) as f:
            rows = f.read().split("\n")[1:]
        a = sum(float(r.split()[4]) for r in rows if r.strip())
        check(abs(a - want[p]) <= 1e-9 * max(1, want[p]), "%s: %s.ex area %g" % (name, p, a))


def vtk_points(grid, c):
    cell = grid.GetCell(c)
    ids = cell.GetPointIds()
    return [grid.GetPoint(ids.GetId(i)) for i in range(ids.GetNumberOfIds())]




def foam_boundary(case):
    with open(os.path.join(case, "constant", "polyMesh", "boundary")) as f:
        text = f.read()
    return {n: dict(re.findall(r"(\w+)\s+([^;]+);", body))
            for n, body in re.findall(r"^\s{4}(\w+)\s*\{([^}]*)\}", text, re.M)}


def foam(argv, case, log):
    p = subprocess.run(argv + ["-case", case], capture_output=True, text=True, env=FOAM_ENV,
                       timeout=300)
    with open(os.path.join(TMP, log), "w") as f:
        f.write(p.stdout + p.stderr)
    return p.returncode, p.stdout + p.stderr


HEADER = e2eutil.FOAM_HEADER


def laplacian_case(case, patches):
    """Steady conduction: T = 1 on the inlet, 0 on the outlet, walls insulated."""
    files = {
        "0/T": HEADER % ("volScalarField", "T") + "dimensions [0 0 0 1 0 0 0];\n"
        "internalField uniform 0;\nboundaryField\n{\n" + "".join(
            "    %s { type %s; }\n" % (p, "fixedValue; value uniform 1" if p.endswith("inlet")
                                       else "fixedValue; value uniform 0" if p.endswith("outlet")
                                       else "zeroGradient") for p in patches) + "}\n",
        "constant/transportProperties": HEADER % ("dictionary", "transportProperties")
        + "DT DT [0 2 -1 0 0 0 0] 1;\n",
        "system/controlDict": HEADER % ("dictionary", "controlDict")
        + "application laplacianFoam;\nstartFrom startTime;\nstartTime 0;\nstopAt endTime;\n"
        "endTime 1;\ndeltaT 1;\nwriteControl timeStep;\nwriteInterval 1;\nwriteFormat ascii;\n"
        "writePrecision 12;\ntimeFormat general;\n",
        "system/fvSchemes": HEADER % ("dictionary", "fvSchemes")
        + "ddtSchemes { default steadyState; }\ngradSchemes { default Gauss linear; }\n"
        "divSchemes { default none; }\nlaplacianSchemes { default Gauss linear corrected; }\n"
        "interpolationSchemes { default linear; }\nsnGradSchemes { default corrected; }\n",
        "system/fvSolution": HEADER % ("dictionary", "fvSolution")
        + "solvers\n{\n    T { solver PCG; preconditioner DIC; tolerance 1e-12; relTol 0; }\n}\n"
        "SIMPLE { nNonOrthogonalCorrectors 4; }\n",
    }
    e2eutil.write_foam_files(case, files)


internal_field = e2eutil.foam_internal_field


# ---- OBJ groups --------------------------------------------------------------
obj = os.path.join(TMP, "duct.obj")
duct_obj(obj)
rc, out, err = e2eutil.run([BIN, "info", obj], timeout=60)
check(re.search(r"^groups: 3$", out, re.M) and "group 1: inlet, 2 triangles" in out,
      "info: the groups are not listed: %s" % out[-400:])
rc, err = mesh("obj", [obj], "--patch-type", "walls=wall")
if rc == 0:
    check_outputs("obj", err, AREAS)
    case = os.path.join(TMP, "obj_case")
    b = foam_boundary(case)
    check({n: d.get("type") for n, d in b.items()} == {"inlet": "patch", "outlet": "patch", "walls": "wall"},
          "obj: OpenFOAM patches %r" % b)
    rc, text = foam([CHECKMESH], case, "obj.checkMesh.log")
    check(rc == 0 and "\nMesh OK." in text, "obj: checkMesh: %s" % text[-1500:])
    laplacian_case(case, list(b))
    rc, text = foam([os.path.join(FOAM_BIN, "laplacianFoam")], case, "obj.laplacianFoam.log")
    check(rc == 0 and "\nEnd" in text, "obj: laplacianFoam exit %d: %s" % (rc, text[-1500:]))
    rc, text = foam([os.path.join(FOAM_BIN, "postProcess"), "-func", "writeCellCentres", "-time", "1"],
                    case, "obj.postProcess.log")
    T = internal_field(os.path.join(case, "1", "T"))
    C = internal_field(os.path.join(case, "1", "C"))
    if check(T is not None and C is not None and len(T) == len(C), "obj: no T or C field after the run"):
        worst = max(abs(t - (1 - c[0] / 4)) for t, c in zip(T, C))
        check(worst <= 0.01, "obj: laplacianFoam's T is off 1 - x/4 by %g" % worst)
        print("obj: patches inlet/outlet/walls on every output; checkMesh OK; laplacianFoam T = 1 - x/4 "
              "within %.2g over %d cells" % (worst, len(T)), flush=True)

# ---- STL solids --------------------------------------------------------------
stl = os.path.join(TMP, "duct.stl")
duct_stl(stl)
rc, err = mesh("stl", [stl])
if rc == 0:
    check_outputs("stl", err, AREAS)
    b = foam_boundary(os.path.join(TMP, "stl_case"))
    check({n: d.get("type") for n, d in b.items()} == {"inlet": "patch", "outlet": "patch", "walls": "patch"},
          "stl: OpenFOAM patches %r" % b)
    print("stl: the three solids are the three patches", flush=True)

# ---- a PLY face property -------------------------------------------------------
ply = os.path.join(TMP, "duct.ply")
duct_ply(ply)
rc, err = mesh("ply", [ply])
if rc == 0:
    check_outputs("ply", err, {"patch1": 1.0, "patch2": 1.0, "patch3": 16.0})
    print("ply: the face property patch gives patch1, patch2, patch3", flush=True)

# ---- two files: two regions, a patch per region and file --------------------
left, right = os.path.join(TMP, "left.obj"), os.path.join(TMP, "right.obj")
e2eutil.voxel_surface(left, (4, 1, 1), lambda i, j, k: 1 if i < 2 else 0)
e2eutil.voxel_surface(right, (4, 1, 1), lambda i, j, k: 1 if i >= 2 else 0)
rc, err = mesh("files", [left, right])
if rc == 0:
    want = {"region1_left": 9.0, "region2_right": 9.0}  # 2 x 1 x 1 boxes, one end each
    check_outputs("files", err, want)
    b = foam_boundary(os.path.join(TMP, "files_case"))
    groups = {n: d.get("inGroups") for n, d in b.items()}
    check(groups == {"region1_left": "List<word> 1(left)", "region2_right": "List<word> 1(right)"},
          "files: inGroups %r" % groups)
    print("files: region1_left and region2_right, with their input groups", flush=True)

# ---- a group border on a flat face: protected as a crease, exact areas ---------
split = os.path.join(TMP, "split.obj")
with open(split, "w") as f:
    f.write("v 0 0 0\nv 2 0 0\nv 2 1 0\nv 0 1 0\nv 0 0 1\nv 2 0 1\nv 2 1 1\nv 0 1 1\n"
            "v 0.7 0 1\nv 0.7 1 1\ng walls\nf 1 3 2\nf 1 4 3\nf 1 2 6 9 5\nf 2 3 7\nf 2 7 6\n"
            "f 3 4 8 10 7\nf 4 1 5\nf 4 5 8\nf 6 7 10\nf 6 10 9\ng inlet\nf 5 9 10\nf 5 10 8\n")
rc, err = mesh("split", [split])
if rc == 0:
    check_outputs("split", err, {"walls": 9.3, "inlet": 0.7})
    print("split: the inlet, 0.7 of a flat face, has exactly its area (its border is a crease)", flush=True)

# ---- groups whose border zigzags over a smooth surface: not creases ----------
# An icosphere's triangles split by the sign of their centroid's x: as
# creases the border turns at every vertex and runs next to itself (a
# 404-triangle STL split so was predicted 5.6e5 balls and ran past 150 s).
# The borders are weighed: the run says so, meshes with the balls of the
# unsplit sphere, and its two patches still cover the boundary.
def icosphere(levels):
    t = (1 + 5 ** 0.5) / 2
    pts = [(-1, t, 0), (1, t, 0), (-1, -t, 0), (1, -t, 0), (0, -1, t), (0, 1, t), (0, -1, -t),
           (0, 1, -t), (t, 0, -1), (t, 0, 1), (-t, 0, -1), (-t, 0, 1)]
    tris = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4),
            (11, 10, 2), (10, 7, 6), (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8),
            (3, 8, 9), (4, 9, 5), (2, 4, 11), (6, 2, 10), (8, 6, 7), (9, 8, 1)]
    pts = [tuple(c / sum(x * x for x in p) ** 0.5 for c in p) for p in pts]
    for _ in range(levels):
        mid, out = {}, []

        def m(a, b):
            k = (min(a, b), max(a, b))
            if k not in mid:
                q = [(pts[a][d] + pts[b][d]) / 2 for d in range(3)]
                n = sum(x * x for x in q) ** 0.5
                pts.append(tuple(x / n for x in q))
                mid[k] = len(pts) - 1
            return mid[k]
        for a, b, c in tris:
            ab, bc, ca = m(a, b), m(b, c), m(c, a)
            out += [(a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca)]
        tris = out
    return pts, tris


zig = os.path.join(TMP, "zigzag.obj")
pts, tris = icosphere(3)
with open(zig, "w") as f:
    f.writelines("v %.17g %.17g %.17g\n" % p for p in pts)
    for g in ("west", "east"):
        f.write("g %s\n" % g)
        f.writelines("f %d %d %d\n" % (a + 1, b + 1, c + 1) for a, b, c in tris
                     if (sum(pts[v][0] for v in (a, b, c)) > 0) == (g == "east"))
rc, err = mesh("zigzag", [zig])
if rc == 0:
    m = re.search(r"mesh: the borders between the input's 2 groups as creases would take about "
                  r"([0-9.e+]+) balls, ([0-9.e+]+) without: not creases", err)
    check(m is not None and float(m.group(1)) > 2 * float(m.group(2)),
          "zigzag: the borders' weighing not said: %r" % err[:600])
    got = summary_patches(err)
    check(set(got) == {"west", "east"} and min(got.values()) > 1.5,
          "zigzag: patches %r" % got)
    b = re.search(r"balls: (\d+) ", err)
    rc1, err1 = mesh("zigzag_none", [zig], "--patches", "none")
    b1 = re.search(r"balls: (\d+) ", err1)
    check(b and b1 and int(b.group(1)) == int(b1.group(1)),
          "zigzag: %s balls, %s with --patches none" % (b and b.group(1), b1 and b1.group(1)))
    print("zigzag: the borders not made creases, the balls of the unsplit sphere, 2 patches %r" % got,
          flush=True)

# ---- sharp-feature patches -----------------------------------------------------
rc, err = mesh("features", [obj], "--patches", "features")
if rc == 0:
    got = summary_patches(err)
    check(sorted(round(a, 9) for a in got.values()) == [1, 1, 4, 4, 4, 4] and
          all(re.match(r"patch\d+$", n) for n in got), "features: patches %r" % got)
    print("features: 6 patches, the duct's faces", flush=True)

# ---- a --patch-type that names no patch -------------------------------------
rc, so, err = e2eutil.run([BIN, "mesh", obj, "-o", os.path.join(TMP, "bad.vtu"), "--patch-type",
                           "inlte=wall"], timeout=60)
check(rc == 2 and len(err.strip().splitlines()) == 1 and "no patch 'inlte'" in err and
      not os.path.exists(os.path.join(TMP, "bad.vtu")), "bad --patch-type: exit %d, %r" % (rc, err))

sys.exit(1 if failures else 0)
