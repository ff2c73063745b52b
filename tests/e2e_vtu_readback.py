"""Reads the .vtu files written by test_io (into $VC_TMP) back with VTK 9.1
and checks them: cell types, validity, cell data, volumes.

Runs after test_io (DEPENDS in tests/CMakeLists.txt). A missing file is a
failure, not a skip: it means test_io did not run or did not write it.
"""

import math
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(os.environ.get("VC_SOURCE", os.path.dirname(HERE)), "tests"))
sys.path.insert(0, HERE)

import vtk  # noqa: E402
import vtkcheck  # noqa: E402

failures = []


def check(cond, msg):
    if not cond:
        failures.append(msg)
        print("FAIL: " + msg)


def run(name, fn):
    try:
        fn()
    except AssertionError as e:  # vtkcheck.CheckError included
        check(False, "%s: %s" % (name, e))


def two_cubes(path):
    fig = vtkcheck.check_vtu(path, expected_cells=2, expected_volume=2.0, rel_tol=1e-12)
    print("%s: %s" % (os.path.basename(path), fig))
    check(fig["n_points"] == 12, "%s: %d points, expected 12" % (path, fig["n_points"]))
    check(fig["n_faces_shared"] == 1 and fig["n_faces_boundary"] == 10,
          "%s: %d shared / %d boundary faces, expected 1 / 10"
          % (path, fig["n_faces_shared"], fig["n_faces_boundary"]))
    check(abs(fig["total_volume"] - 2.0) <= 1e-12,
          "%s: total volume %.17g, expected 2" % (path, fig["total_volume"]))

    grid = vtkcheck.read_vtu(path)
    types = [grid.GetCellType(c) for c in range(grid.GetNumberOfCells())]
    check(types == [42, 42], "%s: cell types %s" % (path, types))

    cd = grid.GetCellData()
    region = cd.GetArray("region")
    seed = cd.GetArray("seed")
    volume = cd.GetArray("volume")
    check(region is not None and region.GetDataType() == vtk.VTK_INT,
          "%s: \"region\" missing or not Int32" % path)
    check(seed is not None and seed.GetDataType() in (vtk.VTK_LONG_LONG, vtk.VTK_LONG,
                                                      vtk.VTK_ID_TYPE),
          "%s: \"seed\" missing or not Int64" % path)
    check(volume is not None and volume.GetDataType() == vtk.VTK_DOUBLE,
          "%s: \"volume\" missing or not Float64" % path)
    if region is not None and seed is not None and volume is not None:
        check([region.GetValue(i) for i in range(2)] == [1, 2],
              "%s: region %s" % (path, [region.GetValue(i) for i in range(2)]))
        check([seed.GetValue(i) for i in range(2)] == [5, 6],
              "%s: seed %s" % (path, [seed.GetValue(i) for i in range(2)]))
        check([volume.GetValue(i) for i in range(2)] == [1.0, 1.0],
              "%s: volume %s" % (path, [volume.GetValue(i) for i in range(2)]))

    # VTK's own volumes equal the "volume" array (check_vtu checks it too)
    vols = vtkcheck.vtk_volumes(grid)
    check(all(abs(v - 1.0) <= 1e-12 for v in vols), "%s: VTK volumes %s" % (path, vols))
    check(abs(math.fsum(vols) - 2.0) <= 1e-12, "%s: VTK total volume %r" % (path, sum(vols)))

    # the shared face x = 1 is seen reversed from cell 1
    f0 = [f for f in vtkcheck.cell_faces(grid, 0)]
    f1 = [f for f in vtkcheck.cell_faces(grid, 1)]
    shared = set(tuple(sorted(f)) for f in f0) & set(tuple(sorted(f)) for f in f1)
    check(len(shared) == 1, "%s: cells share %d faces" % (path, len(shared)))

    b = grid.GetBounds()
    check(tuple(b) == (0.0, 2.0, 0.0, 1.0, 0.0, 1.0), "%s: bounds %s" % (path, b))


def box_grid(path):
    # must match test_vtu_grid in tests/test_io.c
    gx, gy, gz = 24, 20, 18
    xs = [i + 0.03 * i * i for i in range(gx + 1)]
    ys = [0.5 * j + 0.01 * j * j for j in range(gy + 1)]
    zs = [-3.0 + 0.25 * k for k in range(gz + 1)]
    vol = (xs[-1] - xs[0]) * (ys[-1] - ys[0]) * (zs[-1] - zs[0])
    fig = vtkcheck.check_vtu(path, expected_cells=gx * gy * gz, expected_volume=vol,
                             rel_tol=1e-12)
    print("%s: %s" % (os.path.basename(path), fig))
    interior = (gx - 1) * gy * gz + gx * (gy - 1) * gz + gx * gy * (gz - 1)
    boundary = 2 * (gx * gy + gy * gz + gx * gz)
    check(fig["n_points"] == (gx + 1) * (gy + 1) * (gz + 1), "%s: points" % path)
    check(fig["n_faces_shared"] == interior, "%s: %d shared faces, expected %d"
          % (path, fig["n_faces_shared"], interior))
    check(fig["n_faces_boundary"] == boundary, "%s: %d boundary faces, expected %d"
          % (path, fig["n_faces_boundary"], boundary))
    grid = vtkcheck.read_vtu(path)
    region = vtkcheck.cell_array(grid, "region")
    seed = vtkcheck.cell_array(grid, "seed")
    check(region == [c % 3 + 1 for c in range(gx * gy * gz)], "%s: region values" % path)
    check(seed == [c + 5 for c in range(gx * gy * gz)], "%s: seed values" % path)


def main():
    tmp = os.environ.get("VC_TMP")
    if not tmp:
        print("FAIL: VC_TMP is not set")
        return 1
    for name in ("io_two_cubes_raw.vtu", "io_two_cubes_zlib.vtu"):
        path = os.path.join(tmp, name)
        run(name, lambda p=path: two_cubes(p))
    for name in ("io_grid_raw.vtu", "io_grid_zlib.vtu"):
        path = os.path.join(tmp, name)
        run(name, lambda p=path: box_grid(p))
    if failures:
        print("%d failure(s)" % len(failures))
        return 1
    print("e2e_vtu_readback: all checks passed")
    return 0


if __name__ == "__main__":
    sys.exit(main())
