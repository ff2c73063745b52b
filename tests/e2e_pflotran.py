"""End-to-end test of the PFLOTRAN explicit unstructured grid (issue 21):
`vorocrust mesh IN -o OUT.vtu --uge OUT.uge` on the bundled icosphere and
on two boxes sharing a face (two regions).

The files are read back by a strict reader written from PFLOTRAN's
UNSTRUCTURED_EXPLICIT format: "CELLS n" then n lines "id x y z volume"
(ids 1..n in order), "CONNECTIONS m" then m lines "id_up id_dn x y z
area", nothing else; a boundary file "CONNECTIONS k" then k lines "id x y
z area". Checked against the .vtu and the seeds:
  - every cell's volume is the .vtu's, its point the cell's seed;
  - the connections are the .vtu's shared faces (same cells, same area);
  - one .ex file per boundary patch (regionN_surface with two regions),
    each boundary face once, areas equal to the .vtu's boundary faces;
  - the two-point flux of a linear field balances in every cell: for
    p = x, y or z, sum over a cell's connections of area (p_other -
    p_cell) / distance is zero (the faces close the cell and every
    connection is orthogonal to its face), interior and boundary
    connections alike, to 1e-9 of the cell's total area.
Environment: VC_BIN, VC_TMP, VC_SOURCE."""
import math
import os
import shutil
import sys
from collections import defaultdict

sys.path.insert(0, os.path.join(os.environ["VC_SOURCE"], "tests"))
import vtkcheck  # noqa: E402
import e2eutil  # noqa: E402
from e2eutil import check, failures  # noqa: E402

BIN = os.environ["VC_BIN"]
TMP = os.path.join(os.environ.get("VC_TMP", "/tmp"), "e2e_pflotran")
shutil.rmtree(TMP, ignore_errors=True)
os.makedirs(TMP)


class FormatError(Exception):
    pass


def number(tok, path, ln):
    try:
        x = float(tok)
    except ValueError:
        raise FormatError("%s:%d: '%s' is not a number" % (path, ln, tok))
    if not math.isfinite(x):
        raise FormatError("%s:%d: '%s' is not finite" % (path, ln, tok))
    return x


def integer(tok, path, ln):
    if not tok.isdigit():
        raise FormatError("%s:%d: '%s' is not a positive integer" % (path, ln, tok))
    return int(tok)


def read_block(lines, at, keyword, fields, path):
    """(rows, next line index) of a block "KEYWORD n" and n rows of fields."""
    if at >= len(lines):
        raise FormatError("%s: missing %s" % (path, keyword))
    head = lines[at].split()
    if len(head) != 2 or head[0] != keyword:
        raise FormatError("%s:%d: expected '%s n', got %r" % (path, at + 1, keyword, lines[at]))
    n = integer(head[1], path, at + 1)
    rows = []
    for i in range(at + 1, at + 1 + n):
        if i >= len(lines):
            raise FormatError("%s: %s announces %d rows, the file ends after %d"
                              % (path, keyword, n, i - at - 1))
        tok = lines[i].split()
        if len(tok) != len(fields):
            raise FormatError("%s:%d: %d fields, expected %d (%s)"
                              % (path, i + 1, len(tok), len(fields), " ".join(fields)))
        rows.append([integer(t, path, i + 1) if f == "i" else number(t, path, i + 1)
                     for t, f in zip(tok, fields)])
    return rows, at + 1 + n


def read_uge(path):
    with open(path) as f:
        lines = [ln.rstrip("\n") for ln in f]
    cells, at = read_block(lines, 0, "CELLS", "iffff", path)
    conns, at = read_block(lines, at, "CONNECTIONS", "iiffff", path)
    if at != len(lines):
        raise FormatError("%s:%d: text after the connections" % (path, at + 1))
    for k, row in enumerate(cells):
        if row[0] != k + 1:
            raise FormatError("%s: cell %d has id %d" % (path, k + 1, row[0]))
        if not row[4] > 0:
            raise FormatError("%s: cell %d has volume %g" % (path, k + 1, row[4]))
    n = len(cells)
    for row in conns:
        if not (1 <= row[0] <= n and 1 <= row[1] <= n and row[0] != row[1] and row[5] > 0):
            raise FormatError("%s: bad connection %r" % (path, row))
    return cells, conns


def read_ex(path, n_cells):
    with open(path) as f:
        lines = [ln.rstrip("\n") for ln in f]
    rows, at = read_block(lines, 0, "CONNECTIONS", "iffff", path)
    if at != len(lines):
        raise FormatError("%s:%d: text after the connections" % (path, at + 1))
    for row in rows:
        if not (1 <= row[0] <= n_cells and row[4] > 0):
            raise FormatError("%s: bad boundary connection %r" % (path, row))
    return rows






def run_case(name, inputs, expect_patches):
    vtu = os.path.join(TMP, name + ".vtu")
    uge = os.path.join(TMP, name + ".uge")
    seeds = os.path.join(TMP, name + "_seeds.csv")
    rc, out, err = e2eutil.run([BIN, "mesh"] + inputs + ["-o", vtu, "--uge", uge, "--seeds", seeds,
                                                         "--threads", "2"], timeout=110)
    if not check(rc == 0, "%s: exit %d: %s" % (name, rc, err[-800:])):
        return
    ex = sorted(f for f in os.listdir(TMP) if f.startswith(name + "_") and f.endswith(".ex"))
    check(ex == ["%s_%s.ex" % (name, p) for p in sorted(expect_patches)],
          "%s: boundary files %r, expected one per patch %r" % (name, ex, expect_patches))
    try:
        cells, conns = read_uge(uge)
        bnd = [row for f in ex for row in read_ex(os.path.join(TMP, f), len(cells))]
    except FormatError as e:
        check(False, str(e))
        return
    grid = vtkcheck.read_vtu(vtu)
    volume = vtkcheck.cell_array(grid, "volume")
    seed_of = vtkcheck.cell_array(grid, "seed")
    xyz = e2eutil.seeds_csv(seeds)
    check(len(cells) == grid.GetNumberOfCells(), "%s: %d cells, the .vtu %d"
          % (name, len(cells), grid.GetNumberOfCells()))
    worst_v = worst_p = 0.0
    for k, (_, x, y, z, v) in enumerate(cells):
        worst_v = max(worst_v, abs(v - volume[k]) / volume[k])
        s = xyz[seed_of[k]]
        worst_p = max(worst_p, math.dist((x, y, z), s))
    check(worst_v <= 1e-15 and worst_p == 0.0, "%s: cell volumes off the .vtu's by %g, points off "
          "the seeds by %g" % (name, worst_v, worst_p))
    # the .vtu's faces: shared ones by cell pair, boundary ones by cell
    faces = defaultdict(list)
    for c in range(grid.GetNumberOfCells()):
        for f in vtkcheck.cell_faces(grid, c):
            faces[tuple(sorted(f))].append((c, f))
    shared, boundary = {}, defaultdict(float)
    for key, owners in faces.items():
        pts = [grid.GetPoint(p) for p in owners[0][1]]
        a = e2eutil.polygon_area(pts)
        if len(owners) == 2:
            shared[tuple(sorted((owners[0][0], owners[1][0])))] = a
        else:
            boundary[owners[0][0]] += a
    got = {}
    for i, j, _, _, _, a in conns:
        got[tuple(sorted((i - 1, j - 1)))] = a
    check(len(got) == len(conns) == len(shared) and set(got) == set(shared),
          "%s: %d connections (%d distinct), the .vtu has %d shared faces"
          % (name, len(conns), len(got), len(shared)))
    worst_a = max((abs(got[k] - shared[k]) / shared[k] for k in shared if k in got), default=0)
    check(worst_a <= 1e-9, "%s: connection areas off the .vtu's faces by %g" % (name, worst_a))
    bsum = defaultdict(float)
    for i, _, _, _, a in bnd:
        bsum[i - 1] += a
    worst_b = max((abs(bsum[c] - boundary[c]) / boundary[c] for c in boundary), default=0)
    check(set(bsum) == set(boundary) and worst_b <= 1e-9,
          "%s: boundary areas by cell off the .vtu's by %g (%d cells, the .vtu %d)"
          % (name, worst_b, len(bsum), len(boundary)))
    # two-point flux of p = x, y, z: balanced in every cell
    res = [[0.0, 0.0, 0.0] for _ in cells]
    tot = [0.0 for _ in cells]
    pos = [(r[1], r[2], r[3]) for r in cells]
    for i, j, _, _, _, a in conns:
        i, j = i - 1, j - 1
        d = math.dist(pos[i], pos[j])
        for k in range(3):
            q = a * (pos[j][k] - pos[i][k]) / d
            res[i][k] += q
            res[j][k] -= q
        tot[i] += a
        tot[j] += a
    for i, x, y, z, a in bnd:
        i -= 1
        d = math.dist(pos[i], (x, y, z))
        for k, b in enumerate((x, y, z)):
            res[i][k] += a * (b - pos[i][k]) / d
        tot[i] += a
    worst = max(max(abs(r) for r in res[c]) / tot[c] for c in range(len(cells)))
    check(worst <= 1e-9, "%s: the two-point flux of a linear field leaves %g of a cell's area"
          % (name, worst))
    print("%s: %d cells, %d connections, %d boundary connections in %d files; linear-field "
          "flux balance %.2g, volumes %.2g, areas %.2g" % (name, len(cells), len(conns), len(bnd),
                                                           len(ex), worst, worst_v, worst_a),
          flush=True)


run_case("icosphere", [os.path.join(os.environ["VC_SOURCE"], "models", "icosphere.obj")],
         ["surface"])
boxes = os.path.join(TMP, "boxes.obj")
e2eutil.voxel_surface(boxes, (4, 2, 2), lambda i, j, k: 1 if i < 2 else 2)
run_case("boxes", [boxes], ["region1_surface", "region2_surface"])

# a write that cannot happen leaves no file behind
rc, out, err = e2eutil.run([BIN, "mesh", boxes, "-o", os.path.join(TMP, "x.vtu"), "--uge",
                            os.path.join(TMP, "no_such_dir", "x.uge")], timeout=60)
check(rc != 0 and "no_such_dir" in err and not os.path.exists(os.path.join(TMP, "x.vtu")),
      "unwritable --uge: exit %d, %r, x.vtu left: %s" % (rc, err[-300:],
                                                       os.path.exists(os.path.join(TMP, "x.vtu"))))

sys.exit(1 if failures else 0)
