"""Reading vorocrust .vtu files back with VTK 9.1 and checking them.

Not a test by itself (tests are tests/e2e_*.py); import it from a test:

    sys.path.insert(0, os.path.join(os.environ["VC_SOURCE"], "tests"))
    import vtkcheck
    figures = vtkcheck.check_vtu(path, expected_cells=8, expected_volume=1.0)

check_vtu raises vtkcheck.CheckError (an AssertionError) with a readable
message on the first problem found. Needs only VTK (no numpy).
"""

import math
import os
import random

import vtk

VTK_POLYHEDRON = 42

# Set by tests/CMakeLists.txt for the sanitizer build (see check_vtu).
SANITIZED = os.environ.get("VC_SANITIZED", "0") in ("1", "ON", "TRUE", "true")


class CheckError(AssertionError):
    pass


def _fail(path, msg):
    raise CheckError("%s: %s" % (path, msg))


def read_vtu(path):
    """Reads a .vtu file; returns the vtkUnstructuredGrid. Fails on a missing
    or unreadable file (VTK itself would only print a warning)."""
    if not os.path.isfile(path):
        _fail(path, "file does not exist")
    # VTK 9.1 may crash on a truncated file: check the end first.
    with open(path, "rb") as fh:
        fh.seek(max(0, os.path.getsize(path) - 64))
        if b"</VTKFile>" not in fh.read():
            _fail(path, "truncated file (no </VTKFile> at the end)")
    reader = vtk.vtkXMLUnstructuredGridReader()
    reader.SetFileName(path)
    errors = vtk.vtkStringOutputWindow()
    previous = vtk.vtkOutputWindow.GetInstance()
    vtk.vtkOutputWindow.SetInstance(errors)
    try:
        reader.Update()
    finally:
        vtk.vtkOutputWindow.SetInstance(previous)
    text = errors.GetOutput()
    if "ERROR" in text or "Error" in text:
        _fail(path, "VTK reported errors while reading:\n" + text)
    grid = reader.GetOutput()
    if grid is None:
        _fail(path, "VTK read no grid")
    return grid


def cell_array(grid, name):
    """The values of a cell-data array as a Python list (None if absent)."""
    arr = grid.GetCellData().GetArray(name)
    if arr is None:
        return None
    nc = arr.GetNumberOfComponents()
    if nc == 1:
        return [arr.GetValue(i) for i in range(arr.GetNumberOfTuples())]
    return [arr.GetTuple(i) for i in range(arr.GetNumberOfTuples())]


def cell_faces(grid, cell_id, ids=None):
    """The faces of a polyhedron cell as lists of global point ids, oriented as
    stored in the file."""
    if ids is None:
        ids = vtk.vtkIdList()
    grid.GetFaceStream(cell_id, ids)
    n = ids.GetNumberOfIds()
    out = []
    if n == 0:
        return out
    nfaces = ids.GetId(0)
    k = 1
    for _ in range(nfaces):
        m = ids.GetId(k)
        out.append([ids.GetId(k + 1 + i) for i in range(m)])
        k += 1 + m
    return out


def face_stream(faces):
    """A polyhedron's faces (lists of point ids) as the vtkIdList face stream
    vtkUnstructuredGrid.InsertNextCell(VTK_POLYHEDRON, ...) takes."""
    ids = vtk.vtkIdList()
    ids.InsertNextId(len(faces))
    for f in faces:
        ids.InsertNextId(len(f))
        for i in f:
            ids.InsertNextId(i)
    return ids


def vtk_volumes(grid, cells=None):
    """Per-cell volumes computed by VTK's vtkCellSizeFilter: of every cell,
    or of the given cells (in that order, extracted by vtkExtractCells)."""
    f = vtk.vtkCellSizeFilter()
    if cells is None:
        f.SetInputData(grid)
    else:
        ids = vtk.vtkIdList()
        for c in cells:
            ids.InsertNextId(c)
        e = vtk.vtkExtractCells()
        e.SetInputData(grid)
        e.SetCellList(ids)
        f.SetInputConnection(e.GetOutputPort())
    f.SetComputeVertexCount(False)
    f.SetComputeLength(False)
    f.SetComputeArea(False)
    f.SetComputeVolume(True)
    f.Update()
    arr = f.GetOutput().GetCellData().GetArray("Volume")
    return [arr.GetValue(i) for i in range(arr.GetNumberOfTuples())]


def _mass_volume(polydata_port_or_data):
    tri = vtk.vtkTriangleFilter()
    if isinstance(polydata_port_or_data, vtk.vtkPolyData):
        tri.SetInputData(polydata_port_or_data)
    else:
        tri.SetInputConnection(polydata_port_or_data)
    mp = vtk.vtkMassProperties()
    mp.SetInputConnection(tri.GetOutputPort())
    mp.Update()
    return mp.GetVolume()


def cell_mass_volume(grid, c):
    """Volume of cell c by VTK's vtkMassProperties on its faces, each fanned
    from its first vertex (the faces are convex: the plane test checks it).
    vtkTriangleFilter's own triangulation is not used: it drops a triangle
    of a polygon with an edge of 5e-7 of its cell (fandisk.off's lattice
    mesh sampled at 20 degrees: 49 triangles instead of 50, volume 0.069
    instead of 0.0025)."""
    faces = cell_faces(grid, c)
    pts = vtk.vtkPoints()
    pts.SetDataTypeToDouble()  # the default, float, loses 1e-5 of a small cell far from 0
    index = {}
    polys = vtk.vtkCellArray()
    for f in faces:
        for p in f:
            if p not in index:
                index[p] = pts.InsertNextPoint(grid.GetPoint(p))
        for k in range(1, len(f) - 1):
            polys.InsertNextCell(3)
            for p in (f[0], f[k], f[k + 1]):
                polys.InsertCellPoint(index[p])
    pd = vtk.vtkPolyData()
    pd.SetPoints(pts)
    pd.SetPolys(polys)
    return _mass_volume(pd)


def boundary_surface(grid):
    """The mesh's boundary faces (faces of one cell only) as vtkPolyData,
    extracted by VTK's vtkGeometryFilter."""
    g = vtk.vtkGeometryFilter()
    g.SetInputData(grid)
    g.Update()
    return g.GetOutput()


def boundary_volume(grid):
    """Volume enclosed by the mesh's boundary surface, by vtkMassProperties:
    computed by VTK from the boundary alone, independent of the cells'
    "volume" array and of this module's per-cell arithmetic."""
    return _mass_volume(boundary_surface(grid))


def surface_volume(grid, faces):
    """Volume enclosed by a closed set of oriented faces (lists of point
    ids), by the divergence theorem with each face fanned from its first
    point, relative to the points' bounding-box centre, summed with fsum."""
    b = grid.GetBounds()
    o = [(b[0] + b[1]) / 2, (b[2] + b[3]) / 2, (b[4] + b[5]) / 2]
    terms = []
    for f in faces:
        p = [grid.GetPoint(i) for i in f]
        a = [p[0][k] - o[k] for k in range(3)]
        for i in range(1, len(p) - 1):
            u = [p[i][k] - o[k] for k in range(3)]
            d = [p[i + 1][k] - o[k] for k in range(3)]
            terms.append(a[0] * (u[1] * d[2] - u[2] * d[1]) - a[1] * (u[0] * d[2] - u[2] * d[0])
                         + a[2] * (u[0] * d[1] - u[1] * d[0]))
    return math.fsum(terms) / 6.0


def validity_states(grid, tolerance=None, cells=None):
    """Per-cell vtkCellValidator states (0 = valid) of the given cells (all
    by default), with the filter's default tolerance unless given. Uses
    vtkCellValidator.Check cell by cell: the filter form prints a full dump
    of every invalid cell to stdout."""
    if tolerance is None:
        tolerance = vtk.vtkCellValidator().GetTolerance()
    cell = vtk.vtkGenericCell()
    states = []
    for c in (range(grid.GetNumberOfCells()) if cells is None else cells):
        grid.GetCell(c, cell)
        states.append(int(vtk.vtkCellValidator.Check(cell, tolerance)))
    return states


# vtkCellValidator costs about 0.8 ms per polyhedron (VTK's own time, the
# same through the filter): a mesh of 24,000 cells took 19 s, the largest
# part of most end-to-end tests. Above this many cells it judges an evenly
# spaced sample of this many (every cell is still checked by the plane
# test, the volumes and the face pairing below).
VALIDATOR_SAMPLE = 4000


def validator_sample(n_cells, sample=VALIDATOR_SAMPLE):
    """The cells vtkCellValidator judges: all, or sample of them evenly spaced."""
    if n_cells <= sample:
        return list(range(n_cells))
    return sorted({(i * n_cells) // sample for i in range(sample)})


def state_text(state):
    """The reasons behind a vtkCellValidator state, as text."""
    names = [(0x01, "wrong number of points"), (0x02, "intersecting edges"),
             (0x04, "intersecting faces"), (0x08, "noncontiguous edges"),
             (0x10, "nonconvex"), (0x20, "faces oriented incorrectly")]
    parts = [n for bit, n in names if state & bit]
    return ", ".join(parts) if parts else ("valid" if state == 0 else "0x%x" % state)


# VTK 9.1's convexity test (vtkPolyhedron::IsConvex, the seam method of
# Devillers et al.) uses exact comparisons on projected x-y silhouettes, so its
# verdict on a convex cell depends on the cell's orientation in space: on 3000
# random Voronoi cells it flags 74 as "nonconvex" (or "faces oriented
# incorrectly"), 15 after rotating the mesh by (10, 20, 30) degrees, 26 after
# (45, 0, 0), and never the same cells. A rigid rotation cannot make a
# non-convex cell convex, so a cell counts as invalid only if the validator
# rejects it in the original orientation and in every rotated copy tried; in
# addition every cell is checked by an exact-arithmetic-free plane test.
# Four fixed rotations, then 12 drawn from a seeded generator: on
# fandisk.off's volume mesh, two cells sharing a triangle with edges of
# 2e-3 of their extent are rejected in the original orientation and the
# first five rotations, and accepted in the sixth (924 cells rejected in the
# original orientation, 32 after the fixed rotations, 19 after the drawn
# ones, all with an edge under 1e-3 of their extent).
_ROTATION_RNG = random.Random(1)
ROTATIONS = ((10.0, 20.0, 30.0), (45.0, 0.0, 0.0), (0.0, 35.0, 0.0), (23.0, 47.0, 61.0)) + tuple(
    tuple(_ROTATION_RNG.uniform(0.0, 360.0) for _ in range(3)) for _ in range(12))


def divergence_volume(grid, c, ids=None):
    """Volume of polyhedron c by the divergence theorem over its faces (each
    face fanned from its first point), computed here from the file's face
    stream: independent of both vorocrust and VTK's volume filter."""
    faces = cell_faces(grid, c, ids)
    pts = {p: grid.GetPoint(p) for f in faces for p in f}
    m = len(pts)
    ox = sum(x[0] for x in pts.values()) / m
    oy = sum(x[1] for x in pts.values()) / m
    oz = sum(x[2] for x in pts.values()) / m
    rel = {p: (x[0] - ox, x[1] - oy, x[2] - oz) for p, x in pts.items()}
    vol = 0.0
    for f in faces:
        ax, ay, az = rel[f[0]]
        bx, by, bz = rel[f[1]]
        for q in f[2:]:
            dx, dy, dz = rel[q]
            vol += ax * (by * dz - bz * dy) - ay * (bx * dz - bz * dx) + az * (bx * dy - by * dx)
            bx, by, bz = dx, dy, dz
    return vol / 6.0


def validator_verdict(grid, cells=None):
    """Returns (invalid, flagged): of the given cells (all by default), those
    vtkCellValidator rejects in every orientation tried as (cell, state)
    pairs, and how many it rejected in the original orientation."""
    if cells is None:
        cells = range(grid.GetNumberOfCells())
    states = validity_states(grid, cells=cells)
    suspects = {c: s for c, s in zip(cells, states) if s != 0}
    flagged = len(suspects)
    # the copies are also moved to the box's centre: VTK's tolerances are
    # absolute, a mesh far from the origin (UTM coordinates) loses to them
    b = grid.GetBounds()
    centre = [0.5 * (b[0] + b[1]), 0.5 * (b[2] + b[3]), 0.5 * (b[4] + b[5])]
    for ang in ((0.0, 0.0, 0.0),) + ROTATIONS:
        if not suspects:
            break
        t = vtk.vtkTransform()
        t.RotateX(ang[0])
        t.RotateY(ang[1])
        t.RotateZ(ang[2])
        t.Translate(-centre[0], -centre[1], -centre[2])  # applied first
        f = vtk.vtkTransformFilter()
        f.SetInputData(grid)
        f.SetTransform(t)
        f.Update()
        rotated = f.GetOutput()
        cell = vtk.vtkGenericCell()
        tol = vtk.vtkCellValidator().GetTolerance()
        for c in list(suspects):
            rotated.GetCell(c, cell)
            if int(vtk.vtkCellValidator.Check(cell, tol)) == 0:
                del suspects[c]
    return sorted(suspects.items()), flagged


# vtkCellValidator's orientation test (FacesAreOrientedCorrectly) takes the
# centre of the cell's axis-aligned bounding box for its centroid and asks
# every face to point away from it. A thin convex cell lying across the box
# diagonal can have that box centre outside itself, beyond one of its face
# planes; the test then rejects it whatever the faces do (bracket.obj's
# volume mesh has such cells). Such a verdict says nothing about the cell:
# it is accepted when the orientation test is VTK's only complaint, the box
# centre is outside the cell, and the exact plane test below passes.
FACES_ORIENTED_INCORRECTLY = 32


def newell_normal(pts, f):
    """Newell's area vector of face f (point ids into pts)."""
    n = [0.0, 0.0, 0.0]
    for a, b in zip(f, f[1:] + f[:1]):
        pa, pb = pts[a], pts[b]
        n[0] += (pa[1] - pb[1]) * (pa[2] + pb[2])
        n[1] += (pa[2] - pb[2]) * (pa[0] + pb[0])
        n[2] += (pa[0] - pb[0]) * (pa[1] + pb[1])
    return n


def bbox_centre_outside(grid, c):
    """Is the centre of cell c's bounding box beyond one of its face planes
    (Newell normals, outward)?"""
    faces = cell_faces(grid, c)
    pts = {p: grid.GetPoint(p) for f in faces for p in f}
    xs = list(pts.values())
    mid = [(max(x[k] for x in xs) + min(x[k] for x in xs)) / 2 for k in range(3)]
    for f in faces:
        n = newell_normal(pts, f)
        p0 = pts[f[0]]
        if sum((mid[k] - p0[k]) * n[k] for k in range(3)) > 0:
            return True
    return False


def _shortest_edge_ratio(grid, c):
    """Shortest edge of cell c over the cell's largest coordinate extent."""
    faces = cell_faces(grid, c)
    pts = {p: grid.GetPoint(p) for f in faces for p in f}
    xs = list(pts.values())
    ext = max(max(x[k] for x in xs) - min(x[k] for x in xs) for k in range(3))
    shortest = min(math.dist(pts[a], pts[b]) for f in faces for a, b in zip(f, f[1:] + f[:1]))
    return shortest / ext


def convexity_problems(grid, rel_tol=1e-8):
    """Cells whose points are not all on the inner side of every face plane
    (Newell normal through the face centroid), within rel_tol times the
    cell's extent; and faces whose normal points inward. Returns a list of
    (cell, text). The default tolerance is the engine's: copies of a vertex
    computed in different cells are merged within 1e-8 of the cell size, so
    a face is planar to that (fertility.off's volume mesh has a quad 1.2e-9
    of its cell's extent off its plane). The arithmetic is written out per
    coordinate: generator sums made this test most of the suite's time."""
    out = []
    ids = vtk.vtkIdList()
    get_point = grid.GetPoint
    sqrt = math.sqrt
    for c in range(grid.GetNumberOfCells()):
        faces = cell_faces(grid, c, ids)
        pts = {p: get_point(p) for f in faces for p in f}
        xs = list(pts.values())
        X = [x[0] for x in xs]
        Y = [x[1] for x in xs]
        Z = [x[2] for x in xs]
        ext = max(max(X) - min(X), max(Y) - min(Y), max(Z) - min(Z))
        m = len(xs)
        mx, my, mz = sum(X) / m, sum(Y) / m, sum(Z) / m
        # relative to the cell's centre: the plane test keeps its digits far
        # from the origin
        pts = {p: (x[0] - mx, x[1] - my, x[2] - mz) for p, x in pts.items()}
        xs = list(pts.values())
        for f in faces:
            nx = ny = nz = 0.0
            cx = cy = cz = 0.0
            pb = pts[f[-1]]
            for q in f:
                pa = pb
                pb = pts[q]
                nx += (pa[1] - pb[1]) * (pa[2] + pb[2])
                ny += (pa[2] - pb[2]) * (pa[0] + pb[0])
                nz += (pa[0] - pb[0]) * (pa[1] + pb[1])
                cx += pb[0]
                cy += pb[1]
                cz += pb[2]
            ln = sqrt(nx * nx + ny * ny + nz * nz)
            if ln == 0.0:
                out.append((c, "face %s has no area" % f))
                break
            nx, ny, nz = nx / ln, ny / ln, nz / ln
            k = len(f)
            cx, cy, cz = cx / k, cy / k, cz / k
            d = nx * cx + ny * cy + nz * cz
            above = max(nx * x + ny * y + nz * z for x, y, z in xs) - d
            if above > rel_tol * ext:
                out.append((c, "a point is %.3g above face %s" % (above, f)))
                break
            if cx * nx + cy * ny + cz * nz <= 0.0:
                out.append((c, "face %s points inward" % f))
                break
    return out


def check_vtu(path, expected_cells=None, expected_volume=None, rel_tol=1e-9, plane_tol=1e-8):
    """Reads path with VTK 9.1 and checks it is a sound polyhedral mesh:

    - expected_cells cells if given, every cell a VTK_POLYHEDRON;
    - every cell valid per vtkCellValidator (closed, convex, outward faces;
      an evenly spaced sample of VALIDATOR_SAMPLE cells in a larger mesh; none
      under the sanitizers, see SANITIZED),
      in the original orientation or a rotated copy (see validator_verdict),
      except an orientation verdict taken from a box centre outside the cell
      (see FACES_ORIENTED_INCORRECTLY),
      and convex with outward faces by an exact plane test (points within
      plane_tol of the cell's extent above a face plane: 1e-8, the engine's
      merge tolerance; a mesh far from the origin needs more, its file
      coordinates keeping fewer digits at the cells' scale);
    - the cell array "volume" equals the volume its faces enclose (computed
      here) within rel_tol (at least 1e-8, the engine's planarity of faces);
      VTK's vtkCellSizeFilter agrees (1e-6) or, where
      it loses volume on co-spherical points, vtkMassProperties on the
      cell's faces agrees (rel_tol);
    - the boundary faces (faces of one cell) enclose the total volume within
      rel_tol, and within 1e-6 by VTK (vtkGeometryFilter + vtkMassProperties);
    - total volume within rel_tol of expected_volume if given;
    - every face (as its set of point ids) belongs to at most 2 cells, and a
      face shared by 2 cells is seen in opposite orientations.

    Returns a dict: n_cells, n_points, total_volume, n_faces_shared,
    n_faces_boundary, boundary_volume, vtk_boundary_volume, boundary_cells (the
    set of cells with a face no other cell has), vtk_judged (cells vtkCellValidator judged), vtk_flagged (of them, cells
    vtkCellValidator rejects in the original orientation), vtk_rejected_tiny, vtk_volume_off (judged cells where
    vtkCellSizeFilter loses volume). Raises CheckError on failure."""
    grid = read_vtu(path)
    n_cells = grid.GetNumberOfCells()
    n_points = grid.GetNumberOfPoints()
    if expected_cells is not None and n_cells != expected_cells:
        _fail(path, "%d cells, expected %d" % (n_cells, expected_cells))

    for c in range(n_cells):
        t = grid.GetCellType(c)
        if t != VTK_POLYHEDRON:
            _fail(path, "cell %d has type %d, expected VTK_POLYHEDRON (42)" % (c, t))

    # Under the sanitizers VTK's own validator and cell-size filter are left
    # out: they judge the file's bytes, which the Release run of the same test
    # writes identically, and took a third of a sanitized test's time
    # (e2e_materials basin: 28 of 75 s). Every check computed here still runs.
    vtk_judges = not SANITIZED
    judged = validator_sample(n_cells) if vtk_judges else []
    bad, flagged = validator_verdict(grid, judged)
    # What VTK still rejects must be a cell with a tiny feature (an edge
    # shorter than 2e-3 of the cell's extent: VTK's convexity test on
    # projected silhouettes and its FLT_EPSILON thresholds cannot resolve it;
    # fandisk.off's volume mesh has such cells with edges of 1.4e-4 and
    # 4e-4 of their extent, and since its sampling at 20 degrees one with
    # "intersecting edges" at 1.03e-3 that the plane test finds convex),
    # few of them, and convex by the plane test below; anything else fails.
    tiny = []
    for c, st in bad:
        if st == FACES_ORIENTED_INCORRECTLY and bbox_centre_outside(grid, c):
            continue
        rel = _shortest_edge_ratio(grid, c)
        if rel >= 2e-3:
            _fail(path, "cell %d invalid per vtkCellValidator (%s) in every orientation tried, "
                  "shortest edge %.3g of its extent" % (c, state_text(st), rel))
        tiny.append(c)
    if len(tiny) > max(1, len(judged) // 200):
        _fail(path, "%d of %d cells judged have tiny features and are rejected by "
              "vtkCellValidator (more than 0.5%%)" % (len(tiny), len(judged)))
    bad = convexity_problems(grid, plane_tol)
    if bad:
        _fail(path, "%d cell(s) not convex or not outward by the exact plane test, first: %s"
              % (len(bad), ", ".join("cell %d: %s" % cb for cb in bad[:5])))

    # Volumes: the file's "volume" array must match the divergence-theorem
    # volume computed here from the face stream. VTK's own vtkCellSizeFilter
    # is a looser cross-check: it tetrahedralizes the cell's points with an
    # ordered Delaunay triangulator, which loses volume on co-spherical
    # point sets (VoroCrust's normal case: up to 7% on single cells of the
    # bundled ball model while the cells are exact to 1e-11), so it must
    # agree to 1e-6 on at least 99% of the cells.
    ids = vtk.vtkIdList()
    vols = [divergence_volume(grid, c, ids) for c in range(n_cells)]
    total = math.fsum(vols)
    for c, v in enumerate(vols):
        if not (v > 0.0):
            _fail(path, "cell %d has volume %r" % (c, v))
    written = cell_array(grid, "volume")
    if written is None:
        _fail(path, "no cell array \"volume\"")
    if len(written) != n_cells:
        _fail(path, "\"volume\" has %d values for %d cells" % (len(written), n_cells))
    for c in range(n_cells):
        # per cell, the engine's planarity (see convexity_problems): a face
        # 1e-9 off its plane changes the two formulas' volumes by as much
        if abs(written[c] - vols[c]) > max(rel_tol, 1e-8) * abs(vols[c]):
            _fail(path, "cell %d: \"volume\" %.17g but its faces enclose %.17g"
                  % (c, written[c], vols[c]))
    if expected_volume is not None:
        if abs(total - expected_volume) > rel_tol * abs(expected_volume):
            _fail(path, "total volume %.17g, expected %.17g" % (total, expected_volume))
    # VTK's own volumes. vtkCellSizeFilter tetrahedralizes each cell's points
    # with an ordered Delaunay triangulator and loses volume on co-spherical
    # point sets (VoroCrust's normal case: about 4% of the cells of a
    # VoroCrust-style sphere, by up to 1%); a lost tetrahedron can only lower
    # the volume of a convex cell. So a cell it disagrees with (1e-6) must be
    # one where it reports less, and VTK's vtkMassProperties on that cell's
    # own triangulated faces must then agree. vtkMassProperties computes
    # triangle areas by Heron's formula, which loses about 1e-7 on needle
    # triangles (next to the short edges of co-spherical cells): hence 1e-6.
    # (On the validator's sample: the filter costs 0.35 ms per polyhedron.)
    vtk_off = 0
    for c, a in zip(judged, vtk_volumes(grid, judged) if judged else []):
        b = vols[c]
        if abs(a - b) <= 1e-6 * b:
            continue
        vtk_off += 1
        if a > b:
            _fail(path, "cell %d: vtkCellSizeFilter volume %.17g exceeds the face volume %.17g"
                  % (c, a, b))
        mp = cell_mass_volume(grid, c)
        if abs(mp - written[c]) > 1e-6 * abs(written[c]):
            _fail(path, "cell %d: vtkMassProperties volume %.17g, \"volume\" %.17g"
                  % (c, mp, written[c]))

    # Faces: key = sorted point ids; value = [count, first orientation]
    faces = {}
    ids = vtk.vtkIdList()
    for c in range(n_cells):
        for face in cell_faces(grid, c, ids):
            key = tuple(sorted(face))
            entry = faces.get(key)
            if entry is None:
                faces[key] = [1, face, c]
                continue
            entry[0] += 1
            if entry[0] > 2:
                _fail(path, "face %s belongs to more than 2 cells (cells %d, %d, ...)"
                      % (list(key), entry[2], c))
            if _same_orientation(entry[1], face):
                _fail(path, "face %s has the same orientation in cells %d and %d "
                      "(a shared face must be seen reversed)" % (face, entry[2], c))
    shared = sum(1 for e in faces.values() if e[0] == 2)
    boundary = sum(1 for e in faces.values() if e[0] == 1)

    # The whole mesh from its boundary alone: the faces of one cell only
    # enclose the sum of the cell volumes (divergence theorem over the
    # boundary, fsum; interior faces cancel only if they are shared exactly).
    # VTK cross-check: vtkGeometryFilter extracts the boundary and
    # vtkMassProperties measures it (Heron areas: 1e-6, see above).
    surf_vol = surface_volume(grid, [e[1] for e in faces.values() if e[0] == 1])
    if abs(surf_vol - total) > rel_tol * abs(total):
        _fail(path, "the boundary faces enclose %.17g, the cells sum to %.17g"
              % (surf_vol, total))
    vtk_surf_vol = boundary_volume(grid)
    if abs(vtk_surf_vol - total) > 1e-6 * abs(total):
        _fail(path, "the boundary surface encloses %.17g by vtkMassProperties, the cells "
              "sum to %.17g" % (vtk_surf_vol, total))
    return {
        "n_cells": n_cells,
        "n_points": n_points,
        "total_volume": total,
        "n_faces_shared": shared,
        "n_faces_boundary": boundary,
        "vtk_judged": len(judged),
        "vtk_flagged": flagged,
        "vtk_rejected_tiny": len(tiny),
        "vtk_volume_off": vtk_off,
        "boundary_volume": surf_vol,
        "vtk_boundary_volume": vtk_surf_vol,
        "boundary_cells": {e[2] for e in faces.values() if e[0] == 1},
    }


def _same_orientation(a, b):
    """True if vertex cycles a and b (same vertex set) run the same way."""
    if len(a) != len(b) or len(a) < 3:
        return False
    try:
        k = b.index(a[0])
    except ValueError:
        return False
    n = len(a)
    return b[(k + 1) % n] == a[1]
