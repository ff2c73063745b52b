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

import vtk

VTK_POLYHEDRON = 42


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


def vtk_volumes(grid):
    """Per-cell volumes computed by VTK's vtkCellSizeFilter."""
    f = vtk.vtkCellSizeFilter()
    f.SetInputData(grid)
    f.SetComputeVertexCount(False)
    f.SetComputeLength(False)
    f.SetComputeArea(False)
    f.SetComputeVolume(True)
    f.Update()
    arr = f.GetOutput().GetCellData().GetArray("Volume")
    return [arr.GetValue(i) for i in range(arr.GetNumberOfTuples())]


def validity_states(grid, tolerance=None):
    """Per-cell vtkCellValidator states (0 = valid), with the filter's default
    tolerance unless given. Uses vtkCellValidator.Check cell by cell: the
    filter form prints a full dump of every invalid cell to stdout."""
    if tolerance is None:
        tolerance = vtk.vtkCellValidator().GetTolerance()
    cell = vtk.vtkGenericCell()
    states = []
    for c in range(grid.GetNumberOfCells()):
        grid.GetCell(c, cell)
        states.append(int(vtk.vtkCellValidator.Check(cell, tolerance)))
    return states


def state_text(state):
    """The reasons behind a vtkCellValidator state, as text."""
    names = [(0x01, "wrong number of points"), (0x02, "intersecting edges"),
             (0x04, "intersecting faces"), (0x08, "noncontiguous edges"),
             (0x10, "nonconvex"), (0x20, "faces oriented incorrectly")]
    parts = [n for bit, n in names if state & bit]
    return ", ".join(parts) if parts else ("valid" if state == 0 else "0x%x" % state)


def check_vtu(path, expected_cells=None, expected_volume=None, rel_tol=1e-9):
    """Reads path with VTK 9.1 and checks it is a sound polyhedral mesh:

    - expected_cells cells if given, every cell a VTK_POLYHEDRON;
    - every cell valid per vtkCellValidator (closed, convex, outward faces);
    - the cell array "volume" equals VTK's volume (vtkCellSizeFilter) of
      every cell within rel_tol (relative to the cell's volume);
    - total volume within rel_tol of expected_volume if given;
    - every face (as its set of point ids) belongs to at most 2 cells, and a
      face shared by 2 cells is seen in opposite orientations.

    Returns a dict: n_cells, n_points, total_volume, n_faces_shared,
    n_faces_boundary. Raises CheckError on failure."""
    grid = read_vtu(path)
    n_cells = grid.GetNumberOfCells()
    n_points = grid.GetNumberOfPoints()
    if expected_cells is not None and n_cells != expected_cells:
        _fail(path, "%d cells, expected %d" % (n_cells, expected_cells))

    for c in range(n_cells):
        t = grid.GetCellType(c)
        if t != VTK_POLYHEDRON:
            _fail(path, "cell %d has type %d, expected VTK_POLYHEDRON (42)" % (c, t))

    states = validity_states(grid)
    bad = [(c, s) for c, s in enumerate(states) if s != 0]
    if bad:
        _fail(path, "%d invalid cell(s) per vtkCellValidator, first: %s"
              % (len(bad), ", ".join("cell %d (%s)" % (c, state_text(st)) for c, st in bad[:5])))

    vols = vtk_volumes(grid)
    total = math.fsum(vols)
    for c, v in enumerate(vols):
        if not (v > 0.0):
            _fail(path, "cell %d has VTK volume %r" % (c, v))
    written = cell_array(grid, "volume")
    if written is None:
        _fail(path, "no cell array \"volume\"")
    if len(written) != n_cells:
        _fail(path, "\"volume\" has %d values for %d cells" % (len(written), n_cells))
    for c in range(n_cells):
        if abs(written[c] - vols[c]) > rel_tol * abs(vols[c]):
            _fail(path, "cell %d: \"volume\" %.17g but VTK computes %.17g"
                  % (c, written[c], vols[c]))
    if expected_volume is not None:
        if abs(total - expected_volume) > rel_tol * abs(expected_volume):
            _fail(path, "total volume %.17g, expected %.17g" % (total, expected_volume))

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
    return {
        "n_cells": n_cells,
        "n_points": n_points,
        "total_volume": total,
        "n_faces_shared": shared,
        "n_faces_boundary": boundary,
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
