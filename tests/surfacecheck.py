"""Surface helpers shared by the end-to-end tests: reading OBJ/OFF
polygons, fanning polygons into triangles, the surface quality figures
(Q = 6S / (sqrt(3) h P), angle percentages), the enclosed volume, and
the two-sided distance between two surfaces measured by VTK
(vtkImplicitPolyDataDistance, or for large surfaces a dense point sampling
and vtkStaticCellLocator). Independent of vorocrust's own code."""

import math

import vtk


def read_surface(path):
    """Vertices and polygons of an OBJ or OFF file (the formats used here)."""
    pts, polys = [], []
    with open(path) as f:
        text = f.read()
    if path.endswith(".off"):
        toks = [l.split("#")[0].split() for l in text.splitlines()]
        toks = [t for t in toks if t]
        start = 1 if toks[0][0].upper() == "OFF" else 0
        nv, nf = int(toks[start][0]), int(toks[start][1])
        for t in toks[start + 1:start + 1 + nv]:
            pts.append(tuple(map(float, t[:3])))
        for t in toks[start + 1 + nv:start + 1 + nv + nf]:
            k = int(t[0])
            polys.append([int(x) for x in t[1:1 + k]])
        return pts, polys
    for line in text.splitlines():
        t = line.split()
        if not t:
            continue
        if t[0] == "v":
            pts.append(tuple(map(float, t[1:4])))
        elif t[0] == "f":
            polys.append([int(x.split("/")[0]) - 1 for x in t[1:]])
    return pts, polys


def fan(pts, polys):
    """Triangles: triangles as they are, other polygons fanned from their centroid."""
    tris = []
    for p in polys:
        if len(p) == 3:
            tris.append(tuple(pts[i] for i in p))
            continue
        c = tuple(sum(pts[i][k] for i in p) / len(p) for k in range(3))
        for j in range(len(p)):
            tris.append((c, pts[p[j]], pts[p[(j + 1) % len(p)]]))
    return tris


def quality(tris):
    qmin, n_ang, lo, hi = 1e300, 0, 0, 0
    for a, b, c in tris:
        l = [math.dist(b, c), math.dist(a, c), math.dist(a, b)]
        s = sum(l) / 2
        S = math.sqrt(max(s * (s - l[0]) * (s - l[1]) * (s - l[2]), 0))
        h = max(l)
        qmin = min(qmin, 6 * S / (math.sqrt(3) * h * s) if h > 0 else 0)
        for k in range(3):
            x, y = l[(k + 1) % 3], l[(k + 2) % 3]
            ang = math.degrees(math.acos(max(-1, min(1, (x * x + y * y - l[k] ** 2) / (2 * x * y)))))
            n_ang += 1
            lo += ang < 30
            hi += ang > 90
    return qmin, 100 * lo / n_ang, 100 * hi / n_ang


def enclosed_volume(pts, polys):
    """Signed volume, summed about the vertices' box centre (about the
    origin, a part far from it loses the volume to cancellation: a unit
    sphere at 3.7e5 read -0.07)."""
    if not pts:
        return 0.0
    o = [0.5 * (min(p[k] for p in pts) + max(p[k] for p in pts)) for k in range(3)]
    v = 0.0
    for a, b, c in fan(pts, polys):
        a = (a[0] - o[0], a[1] - o[1], a[2] - o[2])
        b = (b[0] - o[0], b[1] - o[1], b[2] - o[2])
        c = (c[0] - o[0], c[1] - o[1], c[2] - o[2])
        v += (a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0])
              + a[2] * (b[0] * c[1] - b[1] * c[0])) / 6
    return v


def polydata(pts, polys):
    P = vtk.vtkPoints()
    P.SetDataTypeToDouble()  # float32 loses a part far from the origin
    for x in pts:
        P.InsertNextPoint(*x)
    C = vtk.vtkCellArray()
    for p in polys:
        C.InsertNextCell(len(p))
        for i in p:
            C.InsertCellPoint(i)
    pd = vtk.vtkPolyData()
    pd.SetPoints(P)
    pd.SetPolys(C)
    tf = vtk.vtkTriangleFilter()
    tf.SetInputData(pd)
    tf.Update()
    return tf.GetOutput()


def samples(pts, polys):
    """Vertices, edge midpoints and points inside every triangle."""
    out = list(pts)
    for a, b, c in fan(pts, polys):
        for (u, v, w) in ((1 / 3, 1 / 3, 1 / 3), (0.5, 0.5, 0), (0, 0.5, 0.5), (0.5, 0, 0.5),
                          (2 / 3, 1 / 6, 1 / 6), (1 / 6, 2 / 3, 1 / 6), (1 / 6, 1 / 6, 2 / 3)):
            out.append(tuple(u * a[k] + v * b[k] + w * c[k] for k in range(3)))
    return out


def max_distance(points, surface):
    d = vtk.vtkImplicitPolyDataDistance()
    d.SetInput(surface)
    return max(abs(d.EvaluateFunction(p)) for p in points)


def _area(pd):
    mp = vtk.vtkMassProperties()
    mp.SetInputData(pd)
    mp.Update()
    return mp.GetSurfaceArea()


def sampled_points(pd, n_target):
    """About n_target points spread evenly over a triangle polydata: its
    vertices, points along its edges and inside its triangles
    (vtkPolyDataPointSampler)."""
    s = vtk.vtkPolyDataPointSampler()
    s.SetInputData(pd)
    s.SetDistance(max(1e-300, math.sqrt(_area(pd) / n_target)))
    s.GenerateVertexPointsOn()
    s.GenerateEdgePointsOn()
    s.GenerateInteriorPointsOn()
    s.Update()
    return s.GetOutput().GetPoints()


def one_sided_distance(points, target):
    """The largest distance from a vtkPoints set to the surface target."""
    loc = vtk.vtkStaticCellLocator()
    loc.SetDataSet(target)
    loc.BuildLocator()
    cp = [0.0, 0.0, 0.0]
    cid, sid, d2 = vtk.mutable(0), vtk.mutable(0), vtk.mutable(0.0)
    worst = 0.0
    for i in range(points.GetNumberOfPoints()):
        loc.FindClosestPoint(points.GetPoint(i), cp, cid, sid, d2)
        worst = max(worst, d2.get())
    return math.sqrt(worst)


def _shifted(pd, c):
    """pd translated by -c, its points in double precision."""
    t = vtk.vtkTransform()
    t.Translate(-c[0], -c[1], -c[2])
    f = vtk.vtkTransformPolyDataFilter()
    f.SetInputData(pd)
    f.SetTransform(t)
    f.SetOutputPointsPrecision(vtk.vtkAlgorithm.DOUBLE_PRECISION)
    f.Update()
    return f.GetOutput()


def hausdorff_sampled(a, b, n_target=150000):
    """Two-sided Hausdorff distance between two triangle polydata, each
    sampled with about n_target points (for surfaces too large for
    samples() and max_distance()). Both are first moved so that a's box
    centre is the origin: the sampler's points are single precision, which
    far from the origin (a part at 1e5) is a sizeable share of the size."""
    bb = a.GetBounds()
    c = [0.5 * (bb[2 * k] + bb[2 * k + 1]) for k in range(3)]
    a, b = _shifted(a, c), _shifted(b, c)
    return max(one_sided_distance(sampled_points(a, n_target), b),
               one_sided_distance(sampled_points(b, n_target), a))
