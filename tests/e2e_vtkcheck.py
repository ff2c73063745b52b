"""The test oracle checked against itself: vtkcheck's exact plane test and
divergence volume on hand-made polyhedra whose answers are known (a unit
cube, the cube with a dented corner, with one face reversed, and far from
the origin), so that a faster rewrite of the oracle cannot silently stop
rejecting anything. Environment: VC_SOURCE."""
import os
import sys

sys.path.insert(0, os.path.join(os.environ["VC_SOURCE"], "tests"))
import vtkcheck  # noqa: E402
from e2eutil import check, failures  # noqa: E402
vtk = vtkcheck.vtk
vtkcheck.SANITIZED = False  # the whole oracle, VTK's judges included, in every build


def one_cell(points, faces):
    grid = vtk.vtkUnstructuredGrid()
    pts = vtk.vtkPoints()
    pts.SetDataTypeToDouble()
    for p in points:
        pts.InsertNextPoint(p)
    grid.SetPoints(pts)
    grid.InsertNextCell(vtkcheck.VTK_POLYHEDRON, vtkcheck.face_stream(faces))
    return grid


CUBE = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0), (0, 0, 1), (1, 0, 1), (1, 1, 1), (0, 1, 1)]
FACES = [[0, 3, 2, 1], [4, 5, 6, 7], [0, 1, 5, 4], [2, 3, 7, 6], [1, 2, 6, 5], [0, 4, 7, 3]]

cube = one_cell(CUBE, FACES)
check(vtkcheck.convexity_problems(cube) == [], "the unit cube flagged as not convex")
check(abs(vtkcheck.divergence_volume(cube, 0) - 1) < 1e-15, "the unit cube's volume %r"
      % vtkcheck.divergence_volume(cube, 0))

dented = list(CUBE)
dented[6] = (0.6, 0.6, 0.6)
got = vtkcheck.convexity_problems(one_cell(dented, FACES))
check(len(got) == 1 and "above face" in got[0][1], "a dented cube not flagged: %r" % got)

reversed_face = [list(f) for f in FACES]
reversed_face[1].reverse()
got = vtkcheck.convexity_problems(one_cell(CUBE, reversed_face))
check(len(got) == 1, "a cube with a face turned inward not flagged: %r" % got)

inward = [list(reversed(f)) for f in FACES]
got = vtkcheck.convexity_problems(one_cell(CUBE, inward))
check(len(got) == 1, "a cube with every face inward not flagged: %r" % got)
check(abs(vtkcheck.divergence_volume(one_cell(CUBE, inward), 0) + 1) < 1e-15,
      "the inward cube's volume is not -1")

# 1e-9 of a unit cell off its plane, 4e6 from the origin: the plane test
# keeps its digits there (the cell's own centre is its origin)
far = [(x + 4e6, y + 5e5, z) for x, y, z in CUBE]
check(vtkcheck.convexity_problems(one_cell(far, FACES)) == [], "the far cube flagged")
far[6] = (far[6][0], far[6][1], far[6][2] + 1e-6)
got = vtkcheck.convexity_problems(one_cell(far, FACES), rel_tol=1e-8)
check(len(got) == 1, "the far cube with a corner 1e-6 out not flagged: %r" % got)
check(abs(vtkcheck.divergence_volume(one_cell([(x + 4e6, y + 5e5, z) for x, y, z in CUBE], FACES), 0)
          - 1) < 1e-9, "the far cube's volume")

print("vtkcheck self-test: %d failure(s)" % len(failures))
sys.exit(1 if failures else 0)
