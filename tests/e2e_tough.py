"""End-to-end test of the TOUGH2/TOUGH3 MESH file (issue 21): `vorocrust
mesh IN -o OUT.vtu --tough MESH` on the bundled icosphere and on two boxes
sharing a face (two regions).

The file is read back by a strict reader written from the TOUGH2 user's
guide's fixed 80-column records: a line starting "ELEME", element records
(columns 1-5 name, 6-15 NSEQ/NADD blank, 16-20 material, 21-30 VOLX,
31-50 blank, 51-60 X, 61-70 Y, 71-80 Z), a blank line, a line starting
"CONNE", connection records (1-5 and 6-10 names, 11-25 blank, 26-30 ISOT,
31-40 D1, 41-50 D2, 51-60 AREAX, 61-70 BETAX), a blank line; every number
a valid Fortran real in its ten columns. Checked:
  - element names unique, a letter, two base-36 characters, two digits;
  - one element per cell (volume and seed as in the .vtu, material
    R0001 / R0002 by region), then one boundary element per boundary face
    (volume 1e50, the cell's material);
  - one connection per interior face (D1 = D2 = half the seed distance,
    area the face's) and per boundary face (D2 = 0); ISOT the dominant
    axis, BETAX the cosine of the angle between -z and the connection;
  - the two-point flux of a linear field balances in every cell, from
    the file's own areas (ten columns: five to eight digits), to 5e-4 of
    the cell's area.
Environment: VC_BIN, VC_TMP, VC_SOURCE."""
import math
import os
import re
import shutil
import sys
from collections import defaultdict

sys.path.insert(0, os.path.join(os.environ["VC_SOURCE"], "tests"))
import vtkcheck  # noqa: E402
import e2eutil  # noqa: E402
from e2eutil import check, failures  # noqa: E402

BIN = os.environ["VC_BIN"]
TMP = os.path.join(os.environ.get("VC_TMP", "/tmp"), "e2e_tough")
shutil.rmtree(TMP, ignore_errors=True)
os.makedirs(TMP)

NAME = re.compile(r"^[A-Z][0-9A-Z]{2}[0-9]{2}$")
# a Fortran real in a ten-column field: optional sign, digits with an
# optional point, optional exponent
REAL = re.compile(r"^ *[-+]?(\d+\.?\d*|\.\d+)([eEdD][-+]?\d+)?$")


class FormatError(Exception):
    pass


def real(line, a, b, where):
    field = line[a:b]
    if not REAL.match(field):
        raise FormatError("%s: columns %d-%d %r are not a real number" % (where, a + 1, b, field))
    return float(field.replace("d", "e").replace("D", "e"))


def blank(line, a, b, where):
    if line[a:b].strip():
        raise FormatError("%s: columns %d-%d must be blank: %r" % (where, a + 1, b, line[a:b]))


def read_mesh(path):
    with open(path) as f:
        lines = f.read().split("\n")
    if not lines[0].startswith("ELEME"):
        raise FormatError("%s:1: no ELEME" % path)
    elements, i = [], 1
    while lines[i].strip():
        ln, where = lines[i], "%s:%d" % (path, i + 1)
        if len(ln) > 80:
            raise FormatError("%s: longer than 80 columns" % where)
        ln = ln.ljust(80)
        name = ln[0:5]
        if not NAME.match(name):
            raise FormatError("%s: element name %r" % (where, name))
        blank(ln, 5, 15, where)
        elements.append((name, ln[15:20], real(ln, 20, 30, where), real(ln, 50, 60, where),
                         real(ln, 60, 70, where), real(ln, 70, 80, where)))
        blank(ln, 30, 50, where)
        i += 1
    i += 1
    if not lines[i].startswith("CONNE"):
        raise FormatError("%s:%d: no CONNE after the blank line" % (path, i + 1))
    conns = []
    i += 1
    while lines[i].strip():
        ln, where = lines[i], "%s:%d" % (path, i + 1)
        if len(ln) > 80:
            raise FormatError("%s: longer than 80 columns" % where)
        ln = ln.ljust(80)
        blank(ln, 10, 25, where)
        isot = ln[25:30]
        if isot.strip() not in ("1", "2", "3") or not isot.startswith("    "):
            raise FormatError("%s: ISOT %r" % (where, isot))
        conns.append((ln[0:5], ln[5:10], int(isot), real(ln, 30, 40, where), real(ln, 40, 50, where),
                      real(ln, 50, 60, where), real(ln, 60, 70, where)))
        blank(ln, 70, 80, where)
        i += 1
    if any(x.strip() for x in lines[i:]):
        raise FormatError("%s:%d: text after the connections" % (path, i + 1))
    return elements, conns




def rel(a, b):
    return abs(a - b) / max(abs(b), 1e-300)


def run_case(name, inputs, n_regions):
    vtu = os.path.join(TMP, name + ".vtu")
    mesh = os.path.join(TMP, name + ".MESH")
    seeds = os.path.join(TMP, name + "_seeds.csv")
    rc, out, err = e2eutil.run([BIN, "mesh"] + inputs + ["-o", vtu, "--tough", mesh, "--seeds",
                                                         seeds, "--threads", "2"], timeout=110)
    if not check(rc == 0, "%s: exit %d: %s" % (name, rc, err[-800:])):
        return
    try:
        elements, conns = read_mesh(mesh)
    except FormatError as e:
        check(False, str(e))
        return
    grid = vtkcheck.read_vtu(vtu)
    nc = grid.GetNumberOfCells()
    volume = vtkcheck.cell_array(grid, "volume")
    region = vtkcheck.cell_array(grid, "region")
    seed_of = vtkcheck.cell_array(grid, "seed")
    xyz = e2eutil.seeds_csv(seeds)
    names = [e[0] for e in elements]
    check(len(set(names)) == len(names), "%s: element names repeat" % name)
    index = {n: k for k, n in enumerate(names)}
    worst_v = worst_x = 0.0
    for k in range(nc):
        _, mat, v, x, y, z = elements[k]
        worst_v = max(worst_v, rel(v, volume[k]))
        s = xyz[seed_of[k]]
        worst_x = max(worst_x, math.dist((x, y, z), s) / max(1.0, math.dist(s, (0, 0, 0))))
        if mat != "R%04d" % region[k]:
            check(False, "%s: element %d has material %r, region %d" % (name, k, mat, region[k]))
            return
    # ten columns keep at least five significant digits
    check(worst_v <= 1e-4 and worst_x <= 1e-7, "%s: volumes off by %g, centres off the seeds by "
          "%g" % (name, worst_v, worst_x))
    bnd = elements[nc:]
    check(all(e[2] == 1e50 for e in bnd), "%s: a boundary element's volume is not 1e50" % name)
    # the .vtu's faces
    faces = defaultdict(list)
    for c in range(nc):
        for f in vtkcheck.cell_faces(grid, c):
            faces[tuple(sorted(f))].append(c)
    n_shared = sum(1 for v in faces.values() if len(v) == 2)
    n_bface = sum(1 for v in faces.values() if len(v) == 1)
    check(len(bnd) == n_bface, "%s: %d boundary elements, %d boundary faces" % (name, len(bnd), n_bface))
    inner = [c for c in conns if index[c[0]] < nc and index[c[1]] < nc]
    outer = [c for c in conns if index[c[1]] >= nc]
    check(len(inner) == n_shared and len(outer) == n_bface and len(conns) == n_shared + n_bface,
          "%s: %d + %d connections, the .vtu %d shared and %d boundary faces"
          % (name, len(inner), len(outer), n_shared, n_bface))
    # the cells' exact centres (the seeds), the boundary elements' as written
    pos = [xyz[seed_of[k]] for k in range(nc)] + [(e[3], e[4], e[5]) for e in bnd]
    res = [[0.0] * 3 for _ in range(nc)]
    tot = [0.0] * nc
    worst_d = worst_b = 0.0
    axes_ok = True
    for n1, n2, isot, d1, d2, a, beta in conns:
        i, j = index[n1], index[n2]
        d = [pos[j][k] - pos[i][k] for k in range(3)]
        dist = math.sqrt(sum(x * x for x in d))
        if j < nc:
            worst_d = max(worst_d, rel(d1, dist / 2), rel(d2, dist / 2))
            worst_b = max(worst_b, abs(beta - (-d[2] / dist)))
        else:
            # the boundary element's centre carries the file's rounding
            worst_d = max(worst_d, abs(d1 - dist) / (dist + 1e-6), abs(d2))
        axes_ok &= isot == 1 + max(range(3), key=lambda k: abs(d[k])) or \
            sorted(abs(x) for x in d)[-1] - sorted(abs(x) for x in d)[-2] < 1e-6 * dist
        for k in range(3):
            q = a * d[k] / dist
            res[i][k] += q
            if j < nc:
                res[j][k] -= q
        tot[i] += a
        if j < nc:
            tot[j] += a
    # five significant digits at least: 5e-5 relative
    check(worst_d <= 1e-4 and worst_b <= 1e-4 and axes_ok,
          "%s: D1/D2 off by %g, BETAX off by %g, ISOT %s" % (name, worst_d, worst_b,
                                                             "ok" if axes_ok else "wrong"))
    worst = max(max(abs(r) for r in res[c]) / tot[c] for c in range(nc))
    # the file's areas and the boundary centres carry five to eight digits
    check(worst <= 5e-4, "%s: the two-point flux of a linear field leaves %g of a cell's area"
          % (name, worst))
    mats = sorted({e[1] for e in elements})
    check(mats == ["R%04d" % (k + 1) for k in range(n_regions)], "%s: materials %r" % (name, mats))
    print("%s: %d elements (%d boundary), %d connections; flux balance %.2g, volumes %.2g, "
          "materials %s" % (name, len(elements), len(bnd), len(conns), worst, worst_v,
                            " ".join(mats)), flush=True)


run_case("icosphere", [os.path.join(os.environ["VC_SOURCE"], "models", "icosphere.obj")], 1)
boxes = os.path.join(TMP, "boxes.obj")
e2eutil.voxel_surface(boxes, (4, 2, 2), lambda i, j, k: 1 if i < 2 else 2)
run_case("boxes", [boxes], 2)
sys.exit(1 if failures else 0)
