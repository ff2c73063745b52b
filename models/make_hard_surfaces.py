#!/usr/bin/python3
"""Generator of hard test surfaces for the VoroCrust sampling (issue 16).

usage: /usr/bin/python3 models/make_hard_surfaces.py OUTDIR [NAME ...]

Writes into OUTDIR one closed, consistently outward-oriented, manifold
triangle surface per case as NAME.obj, and OUTDIR/manifest.csv (name,
triangles, what the surface tests, expected Euler characteristic). Needs
Debian's VTK 9 for /usr/bin/python3 (python3-vtk9); no numpy. Deterministic:
fixed shapes, grids and seeds, the same files on every run.

Every surface is built with VTK (implicit functions sampled on a grid and
contoured with flying edges, sources, decimation, Loop subdivision) or
explicitly (the boxes), then cleaned: coincident points merged, triangles
with a repeated vertex or zero area dropped, unused points dropped, each
connected component oriented so that its signed volume is positive
(outward normals). The script then checks each surface itself (every edge
in exactly two triangles with opposite directions, every vertex link one
fan, no zero-area triangle, Euler characteristic V - E + F equal to the
expected one) and fails loudly otherwise. Check them with
`vorocrust info OUTDIR/NAME.obj --require-closed` as well.

The cases (NAME: what it tests):
  blobby          marching-cubes isosurface of a metaball field (a sum of
                  Gaussians of vtkSphere/vtkQuadric functions): slivers and
                  small folds at every vertex
  blobby_500      the same shape decimated to about 500 triangles
                  (vtkQuadricDecimation): coarse facets of a curved shape
  blobby_loop     blobby_500 after 4 rounds of vtkLoopSubdivisionFilter
                  (about 130k triangles of a smooth surface)
  blobby_fine     the same field contoured on a fine grid (about 200k
                  triangles): a fine scan-like input
  noisy_sphere    vtkSphereSource with every vertex moved along the normal
                  by seeded uniform noise of +-3 % of the radius
  thin_plate      a 1 x 1 x 0.02 box with sharp edges (long side triangles)
  thin_plate_round the same plate with its edges rounded by half the
                  thickness (8 facets per half turn)
  near_spheres    two spheres of radius 1 in one surface, 2 components,
                  gap 0.01 (1 % of the radius)
  coarse_torus    a 10 x 10 parametric torus, 200 triangles (36-degree folds)
  fillet_block    a 1 x 0.7 x 0.5 block whose edges and corners are rounded
                  by a fillet of radius 0.1 with 4 facets per quarter turn,
                  coarse flat faces (the fandisk kind of input)
  genus3          isosurface of the blend of three tori side by side:
                  genus 3, Euler characteristic -4
  knot            a tube of radius 0.12 around a trefoil (explicit rings
                  in a parallel-transported frame): a thin curved tube
  needle          an ellipsoid 16 x 2 x 2: thin, tips of curvature radius 1/8
  superellipsoid  vtkParametricSuperEllipsoid, exponents 0.25: flat faces
                  meeting in tight smooth edges
  supertoroid     vtkParametricSuperToroid, exponents 0.5
  csg_plate       marching cubes of a plate minus a cylinder (creases as
                  staircases, genus 1)
  box_fin         marching cubes of a box with a fin 0.08 thick on top
  blobby_200      blobby decimated to 200 triangles
  noisy_torus     a torus with +-2 % seeded noise along the tube's normal
  hollow_sphere   a sphere with a spherical cavity (inner surface inward)
  box_speck       a box of side 10 and, apart, a sphere of radius 0.01:
                  two components 1000 times apart in size
  cone            vtkConeSource, 32 sides, capped: an apex of valence 32
  prism12         a capped 12-sided cylinder: 30-degree folds along it
  rod             a capped 24-sided cylinder 12 long, radius 0.1: needle
                  triangles 460 times longer than wide (a CAD export)
  text            the letters VC extruded (vtkVectorText): 2 components,
                  many corners, narrow strokes
  uv_noisy        a UV sphere (vtkSphereSource 300 x 180, radius 1) with
                  +-0.002 of noise along the radius: needles at the poles
                  whose normals the noise tips 80 degrees (folds that are
                  noise, their normals far from agreeing)
  turned_needles  a UV sphere with 8 pleats: a needle whose apex crossed its
                  long edge by 0.1 to 0.45 of the error bound (turned over)
  noise_blob      sphere plus Perlin noise, marching cubes on 200^3 (about
                  170k triangles): a bumpy scan-like surface
  scan_sphere     marching cubes of a sphere (80^3), every vertex moved
                  along the normal by +-0.002 (1/7 of the error bound):
                  slivers folding by more than 60 degrees that are noise
  wing            a NACA 0012 wing 3 long tapering from chord 1 to 0.4: a
                  sharp trailing edge (a 16-degree wedge), a round leading
                  edge, flat caps (a CFD part)
  hex_prism       a capped hexagonal prism: its side edges fold by exactly
                  theta_sharp, 60 degrees
  chamfer_block   a unit cube with one edge chamfered 0.004 wide: a small
                  feature along large faces (the balls grade out from it)
  tetra, icosa    a regular tetrahedron (4 triangles), icosahedron (20)
  gear            an extruded spur gear, 24 teeth: 192 corners
  wedge5          a prism with a 5-degree edge (8 triangles)
  star            a stellated icosahedron: 20 narrow spikes
  spring          a tube along a 5-turn helix, turns 0.3 tube radii apart
  far_sphere      a sphere of radius 1 centred 3.7e5 from the origin
  thin_shell      a spherical shell 3% of its radius thick (two components,
                  the inner one facing in)
  bump_sphere     a fine sphere with a Gaussian bump 0.02 high
  mc_hemisphere   marching cubes of a half ball: a 90-degree rim of slivers
  perlin_blob     sphere plus Perlin noise of frequency 11 on 160^3 (about
                  146k triangles): vertices whose triangles spread beyond
                  theta_sharp while every fold at them stays below it, next
                  to folds that are noise (session 47: corners; before,
                  sliver elimination chased them with balls down to 1e-10
                  for two minutes, then a smoothed copy was sampled)
"""
import math
import os
import random
import sys

try:
    import vtk
except ImportError:  # e.g. a pyenv python3 first on PATH: use Debian's
    if os.path.realpath(sys.executable) != os.path.realpath("/usr/bin/python3") and \
            os.path.exists("/usr/bin/python3"):
        os.execv("/usr/bin/python3", ["/usr/bin/python3"] + sys.argv)
    raise

vtk.vtkObject.GlobalWarningDisplayOff()


# ---------------------------------------------------------------- fields

def sample(func, bounds, dims):
    """vtkSampleFunction of an implicit function on a regular grid."""
    s = vtk.vtkSampleFunction()
    s.SetImplicitFunction(func)
    s.SetModelBounds(*bounds)
    s.SetSampleDimensions(*dims)
    s.SetOutputScalarTypeToDouble()
    s.ComputeNormalsOff()
    s.CappingOff()
    s.Update()
    return s.GetOutput()


def imath(op, a, b=None, k=None, c=None):
    """One vtkImageMathematics operation on image data (b: second input)."""
    m = vtk.vtkImageMathematics()
    getattr(m, "SetOperationTo" + op)()
    m.SetInput1Data(a)
    if b is not None:
        m.SetInput2Data(b)
    if k is not None:
        m.SetConstantK(k)
    if c is not None:
        m.SetConstantC(c)
    m.Update()
    out = vtk.vtkImageData()
    out.DeepCopy(m.GetOutput())
    return out


def quadric(coeffs):
    q = vtk.vtkQuadric()
    q.SetCoefficients(*coeffs)
    return q


def ellipsoid(center, axes):
    """vtkQuadric sum ((x_i - c_i) / a_i)^2 - 1."""
    cx, cy, cz = center
    ax, ay, az = (1.0 / (a * a) for a in axes)
    return quadric((ax, ay, az, 0, 0, 0, -2 * ax * cx, -2 * ay * cy, -2 * az * cz,
                    ax * cx * cx + ay * cy * cy + az * cz * cz - 1.0))


# The blobby shape: metaballs exp(-d^2/r^2) (spheres) and exp(-(q+1))
# (an ellipsoid q = |A(x-c)|^2 - 1), contoured at exp(-1): a single ball alone
# would be its sphere of radius r.
BLOB_SPHERES = [((0.0, 0.0, 0.0), 0.62), ((0.72, 0.18, 0.08), 0.46), ((-0.52, 0.48, -0.18), 0.41),
                ((0.12, -0.58, 0.38), 0.36), ((-0.35, -0.30, -0.45), 0.33)]
BLOB_ELLIPSOIDS = [((0.25, 0.35, -0.42), (0.70, 0.24, 0.30))]
BLOB_BOUNDS = (-1.45, 1.55, -1.3, 1.35, -1.25, 1.3)


def blob_field(n):
    """Metaball field on a grid of about n points per unit length."""
    b = BLOB_BOUNDS
    dims = tuple(max(8, int(round((b[2 * i + 1] - b[2 * i]) * n)) + 1) for i in range(3))
    total = None
    for c, r in BLOB_SPHERES:
        sph = vtk.vtkSphere()
        sph.SetCenter(*c)
        sph.SetRadius(r)
        f = sample(sph, b, dims)                            # d^2 - r^2
        f = imath("MultiplyByK", f, k=-1.0 / (r * r))       # 1 - d^2/r^2
        f = imath("AddConstant", f, c=-1.0)                  # -d^2/r^2
        f = imath("Exp", f)
        total = f if total is None else imath("Add", total, f)
    for c, axes in BLOB_ELLIPSOIDS:
        f = sample(ellipsoid(c, axes), b, dims)             # q
        f = imath("MultiplyByK", f, k=-1.0)
        f = imath("AddConstant", f, c=-1.0)                  # -(q + 1)
        f = imath("Exp", f)
        total = imath("Add", total, f)
    return total


def torus_blend_field(n):
    """Sum of exp(-((rho - R)^2 + z^2) / r^2) over three tori of ring radius
    R = 1 and tube radius r = 0.35 whose centres are 2 apart on the x axis."""
    b = (-3.6, 3.6, -1.6, 1.6, -0.7, 0.7)
    dims = tuple(int(round((b[2 * i + 1] - b[2 * i]) * n)) + 1 for i in range(3))
    R, r = 1.0, 0.35
    z2 = sample(quadric((0, 0, 1, 0, 0, 0, 0, 0, 0, 0)), b, dims)
    total = None
    for cx in (-2.0, 0.0, 2.0):
        rho2 = sample(quadric((1, 1, 0, 0, 0, 0, -2 * cx, 0, 0, cx * cx)), b, dims)
        f = imath("SquareRoot", rho2)
        f = imath("AddConstant", f, c=-R)
        f = imath("Square", f)
        f = imath("Add", f, z2)
        f = imath("MultiplyByK", f, k=-1.0 / (r * r))
        f = imath("Exp", f)
        total = f if total is None else imath("Add", total, f)
    return total


def contour(image, value):
    fe = vtk.vtkFlyingEdges3D()
    fe.SetInputData(image)
    fe.SetValue(0, value)
    fe.ComputeNormalsOff()
    fe.ComputeGradientsOff()
    fe.ComputeScalarsOff()
    fe.Update()
    return fe.GetOutput()


# ---------------------------------------------------------------- meshes

def polydata_to_lists(pd, tolerance=0.0):
    """Points and triangles of a polydata, triangulated, coincident points
    merged (tolerance: a fraction of the bounding-box diagonal)."""
    tf = vtk.vtkTriangleFilter()
    tf.SetInputData(pd)
    tf.PassVertsOff()
    tf.PassLinesOff()
    cl = vtk.vtkCleanPolyData()
    cl.SetInputConnection(tf.GetOutputPort())
    cl.PointMergingOn()
    cl.SetTolerance(tolerance)
    cl.ConvertLinesToPointsOff()
    cl.ConvertPolysToLinesOff()
    cl.ConvertStripsToPolysOff()
    cl.Update()
    out = cl.GetOutput()
    pts = [out.GetPoint(i) for i in range(out.GetNumberOfPoints())]
    tris = []
    polys = out.GetPolys()
    polys.InitTraversal()
    ids = vtk.vtkIdList()
    while polys.GetNextCell(ids):
        if ids.GetNumberOfIds() == 3:
            tris.append((ids.GetId(0), ids.GetId(1), ids.GetId(2)))
    return pts, tris


def lists_to_polydata(pts, tris):
    p = vtk.vtkPoints()
    p.SetDataTypeToDouble()
    for x in pts:
        p.InsertNextPoint(*x)
    cells = vtk.vtkCellArray()
    for t in tris:  # triangles, or any polygons
        cells.InsertNextCell(len(t))
        for v in t:
            cells.InsertCellPoint(v)
    pd = vtk.vtkPolyData()
    pd.SetPoints(p)
    pd.SetPolys(cells)
    return pd


def sub(a, b):
    return (a[0] - b[0], a[1] - b[1], a[2] - b[2])


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def twice_area(pts, t):
    n = cross(sub(pts[t[1]], pts[t[0]]), sub(pts[t[2]], pts[t[0]]))
    return math.sqrt(dot(n, n))


def bbox_diag(pts):
    lo = [min(p[i] for p in pts) for i in range(3)]
    hi = [max(p[i] for p in pts) for i in range(3)]
    return math.sqrt(sum((hi[i] - lo[i]) ** 2 for i in range(3)))


def components(n_pts, tris):
    """Component index of each triangle (triangles sharing a vertex)."""
    parent = list(range(n_pts))

    def find(x):
        while parent[x] != x:
            parent[x] = parent[parent[x]]
            x = parent[x]
        return x

    for a, b, c in tris:
        ra, rb, rc = find(a), find(b), find(c)
        r = min(ra, rb, rc)
        parent[ra] = parent[rb] = parent[rc] = r
    roots = {}
    return [roots.setdefault(find(t[0]), len(roots)) for t in tris], len(roots)


def clean(pts, tris):
    """Drop triangles with a repeated vertex or zero area and unused points;
    orient each component outward (positive signed volume)."""
    diag = bbox_diag(pts)
    eps = 1e-14 * diag * diag
    tris = [t for t in tris if len(set(t)) == 3 and twice_area(pts, t) > eps]
    used = sorted({v for t in tris for v in t})
    remap = {v: i for i, v in enumerate(used)}
    pts = [pts[v] for v in used]
    tris = [tuple(remap[v] for v in t) for t in tris]
    tris = orient_consistently(tris)
    comp, n_comp = components(len(pts), tris)
    vol = [0.0] * n_comp
    for t, c in zip(tris, comp):
        vol[c] += dot(pts[t[0]], cross(pts[t[1]], pts[t[2]])) / 6.0
    tris = [t if vol[c] > 0 else (t[0], t[2], t[1]) for t, c in zip(tris, comp)]
    return pts, tris


def orient_consistently(tris):
    """Flip triangles so that every edge shared by two triangles is used in
    opposite directions (breadth-first from the first triangle of each
    component; the sources' own orientation is not trusted, e.g. the seam of
    vtkParametricFunctionSource)."""
    by_edge = {}
    for i, t in enumerate(tris):
        for k in range(3):
            a, b = t[k], t[(k + 1) % 3]
            by_edge.setdefault((min(a, b), max(a, b)), []).append(i)
    tris = list(tris)
    done = [False] * len(tris)
    for s in range(len(tris)):
        if done[s]:
            continue
        done[s] = True
        queue = [s]
        while queue:
            i = queue.pop()
            t = tris[i]
            for k in range(3):
                a, b = t[k], t[(k + 1) % 3]
                for j in by_edge[(min(a, b), max(a, b))]:
                    if done[j]:
                        continue
                    u = tris[j]
                    same = any(u[m] == a and u[(m + 1) % 3] == b for m in range(3))
                    if same:
                        tris[j] = (u[0], u[2], u[1])
                    done[j] = True
                    queue.append(j)
    return tris


def check(name, pts, tris, euler, cavities=False):
    """Closed, consistently oriented, edge- and vertex-manifold, no zero-area
    triangle, positive volume per component (with cavities: in all), the
    expected Euler number."""
    directed = {}
    for t in tris:
        for i in range(3):
            e = (t[i], t[(i + 1) % 3])
            directed[e] = directed.get(e, 0) + 1
    bad = [e for e, n in directed.items() if n != 1 or directed.get((e[1], e[0]), 0) != 1]
    if bad:
        raise SystemExit("%s: %d edges not shared by exactly two opposite triangles (e.g. %s)"
                         % (name, len(bad), bad[0]))
    # vertex links: the triangles around each vertex form one fan
    nxt = {}
    for t in tris:
        for i in range(3):
            nxt.setdefault(t[i], {})[t[(i + 1) % 3]] = t[(i + 2) % 3]
    for v, m in nxt.items():
        start = next(iter(m))
        w, steps = start, 0
        while True:
            w = m[w]
            steps += 1
            if w == start:
                break
        if steps != len(m):
            raise SystemExit("%s: vertex %d is not manifold (%d of %d triangles in one fan)"
                             % (name, v, steps, len(m)))
    diag = bbox_diag(pts)
    small = sum(1 for t in tris if twice_area(pts, t) <= 1e-14 * diag * diag)
    if small:
        raise SystemExit("%s: %d zero-area triangles" % (name, small))
    n_edges = len(directed) // 2
    chi = len(pts) - n_edges + len(tris)
    if chi != euler:
        raise SystemExit("%s: Euler characteristic %d, expected %d" % (name, chi, euler))
    comp, n_comp = components(len(pts), tris)
    vol = [0.0] * n_comp
    for t, c in zip(tris, comp):
        vol[c] += dot(pts[t[0]], cross(pts[t[1]], pts[t[2]])) / 6.0
    if (sum(vol) if cavities else min(vol)) <= 0:
        raise SystemExit("%s: a component has volume %g" % (name, min(vol)))
    return n_comp, sum(vol)


def write_obj(path, pts, tris, comment):
    with open(path, "w") as f:
        f.write("# %s\n# generated by models/make_hard_surfaces.py\n" % comment)
        for p in pts:
            f.write("v %.10g %.10g %.10g\n" % p)
        for t in tris:
            f.write("f %d %d %d\n" % (t[0] + 1, t[1] + 1, t[2] + 1))


# ---------------------------------------------------------------- boxes

def box_surface(coords, a=None, r=0.0):
    """Triangulated surface of the box with grid lines at coords (three
    sorted lists from -A_i to A_i). With r > 0 every grid point g is moved to
    c + r (g - c)/|g - c|, c = g clamped to [-a_i, a_i]: the box of
    half-extents a, rounded by a fillet of radius r (A_i = a_i + r)."""
    index = {}
    pts = []

    def vertex(i, j, k):
        key = (i, j, k)
        if key not in index:
            g = (coords[0][i], coords[1][j], coords[2][k])
            if r > 0:
                c = tuple(max(-a[d], min(a[d], g[d])) for d in range(3))
                v = sub(g, c)
                n = math.sqrt(dot(v, v))
                g = tuple(c[d] + r * v[d] / n for d in range(3))
            index[key] = len(pts)
            pts.append(g)
        return index[key]

    tris = []
    n = [len(c) - 1 for c in coords]
    for axis in range(3):
        u, w = (axis + 1) % 3, (axis + 2) % 3
        for side in (0, n[axis]):
            sign = 1 if side else -1
            for i in range(n[u]):
                for j in range(n[w]):
                    quad = []
                    for di, dj in ((0, 0), (1, 0), (1, 1), (0, 1)):
                        idx = [0, 0, 0]
                        idx[axis], idx[u], idx[w] = side, i + di, j + dj
                        quad.append(vertex(*idx))
                    # (u, w, axis) is right-handed: counter-clockwise in (u, w)
                    # is outward on the + side
                    if sign < 0:
                        quad.reverse()
                    if (i + j) % 2:
                        tris += [(quad[0], quad[1], quad[2]), (quad[0], quad[2], quad[3])]
                    else:
                        tris += [(quad[0], quad[1], quad[3]), (quad[1], quad[2], quad[3])]
    return pts, tris


def fillet_coords(a, r, n_flat, k):
    """Grid coordinates of one axis: the fillet (k facets per quarter turn, k
    even) on both ends and n_flat segments across the flat part."""
    ts = [r * math.tan(math.radians(90.0 * j / k)) for j in range(1, k // 2)]
    flat = [-a + 2 * a * i / n_flat for i in range(n_flat + 1)] if a > 0 else [0.0]
    lo = [-(a + r)] + [-(a + t) for t in reversed(ts)]
    hi = [a + t for t in ts] + [a + r]
    return lo + flat + hi


# ---------------------------------------------------------------- cases

def case_blobby():
    return polydata_to_lists(contour(blob_field(22), math.exp(-1.0)))


def decimated_blobby(n_target=500):
    pd = lists_to_polydata(*clean(*case_blobby()))
    n = pd.GetNumberOfPolys()
    d = vtk.vtkQuadricDecimation()
    d.SetInputData(pd)
    d.SetTargetReduction(1.0 - float(n_target) / n)
    d.VolumePreservationOn()
    d.Update()
    return d.GetOutput()


def case_blobby_500():
    return polydata_to_lists(decimated_blobby())


def case_blobby_loop():
    pd = lists_to_polydata(*clean(*case_blobby_500()))
    s = vtk.vtkLoopSubdivisionFilter()
    s.SetInputData(pd)
    s.SetNumberOfSubdivisions(4)
    s.Update()
    return polydata_to_lists(s.GetOutput())


def case_blobby_fine():
    return polydata_to_lists(contour(blob_field(80), math.exp(-1.0)))


def case_noisy_sphere():
    s = vtk.vtkSphereSource()
    s.SetRadius(1.0)
    s.SetThetaResolution(64)
    s.SetPhiResolution(32)
    s.Update()
    pts, tris = polydata_to_lists(s.GetOutput())
    rng = random.Random(16)
    out = []
    for p in pts:
        n = math.sqrt(dot(p, p))
        f = 1.0 + rng.uniform(-0.03, 0.03)  # along the normal p/|p|, radius 1
        out.append(tuple(x / n * f for x in p))
    return out, tris


def case_thin_plate():
    cx = [-0.5 + i / 10.0 for i in range(11)]
    return box_surface([cx, cx, [-0.01, 0.01]])


def case_thin_plate_round():
    r = 0.01
    a = (0.49, 0.49, 0.0)
    coords = [fillet_coords(a[0], r, 10, 4), fillet_coords(a[1], r, 10, 4),
              fillet_coords(0.0, r, 1, 4)]
    return box_surface(coords, a, r)


def case_near_spheres():
    app = vtk.vtkAppendPolyData()
    for cx in (-1.005, 1.005):
        s = vtk.vtkSphereSource()
        s.SetRadius(1.0)
        s.SetCenter(cx, 0, 0)
        s.SetThetaResolution(48)  # a vertex at (cx +- 1, 0, 0): the gap is 0.01
        s.SetPhiResolution(24)
        app.AddInputConnection(s.GetOutputPort())
    app.Update()
    return polydata_to_lists(app.GetOutput())


def case_coarse_torus():
    t = vtk.vtkParametricTorus()
    t.SetRingRadius(1.0)
    t.SetCrossSectionRadius(0.4)
    src = vtk.vtkParametricFunctionSource()
    src.SetParametricFunction(t)
    src.SetUResolution(11)  # 11 samples with the seam shared: 10 x 10 quads
    src.SetVResolution(11)
    src.GenerateTextureCoordinatesOff()
    src.SetScalarModeToNone()
    src.SetOutputPointsPrecision(vtk.vtkAlgorithm.DOUBLE_PRECISION)
    src.Update()
    return polydata_to_lists(src.GetOutput(), tolerance=1e-9)


def case_fillet_block():
    r = 0.1
    a = (0.5 - r, 0.35 - r, 0.25 - r)
    coords = [fillet_coords(a[0], r, 3, 4), fillet_coords(a[1], r, 2, 4),
              fillet_coords(a[2], r, 1, 4)]
    return box_surface(coords, a, r)


def case_fillet_block_tiny():
    """The filleted block with fillets of radius 0.001, a fifth of the error
    bound, in 4 facets per quarter turn: rounds the bound does not resolve,
    each a crease at its scale, meeting at rounded corners."""
    r = 0.001
    a = (0.5 - r, 0.35 - r, 0.25 - r)
    coords = [fillet_coords(a[0], r, 3, 4), fillet_coords(a[1], r, 2, 4),
              fillet_coords(a[2], r, 1, 4)]
    return box_surface(coords, a, r)


def case_can_round_rims(radius=1.0, height=2.0, rho=0.002, n_around=128, n_round=4, n_face=20,
                        n_side=20):
    """A can (cylinder of radius 1, height 2) whose two rims are rounded to
    0.002 (0.14 of the error bound) in n_round facets: two closed rounds
    below the bound's resolution, each a closed crease at its scale."""
    prof = [((radius - rho) * i / n_face, 0.0) for i in range(1, n_face + 1)]
    prof += [(radius - rho + rho * math.cos(a), rho + rho * math.sin(a))
             for a in (-math.pi / 2 + (math.pi / 2) * j / n_round for j in range(1, n_round))]
    prof += [(radius, rho + (height - 2 * rho) * i / n_side) for i in range(n_side + 1)]
    prof += [(radius - rho + rho * math.cos(a), height - rho + rho * math.sin(a))
             for a in ((math.pi / 2) * j / n_round for j in range(1, n_round))]
    prof += [((radius - rho) * i / n_face, height) for i in range(n_face, 0, -1)]
    pts = [(0.0, 0.0, 0.0), (0.0, 0.0, height)]
    for r, z in prof:
        pts += [(r * math.cos(2 * math.pi * k / n_around), r * math.sin(2 * math.pi * k / n_around), z)
                for k in range(n_around)]
    m = len(prof)

    def idx(i, k):
        return 2 + i * n_around + k % n_around
    tris = []
    for k in range(n_around):
        tris += [(0, idx(0, k + 1), idx(0, k)), (1, idx(m - 1, k), idx(m - 1, k + 1))]
    for i in range(m - 1):
        for k in range(n_around):
            a, b, c, d = idx(i, k), idx(i, k + 1), idx(i + 1, k + 1), idx(i + 1, k)
            tris += [(a, b, c), (a, c, d)]
    return pts, tris


def case_genus3():
    return polydata_to_lists(contour(torus_blend_field(14), math.exp(-1.0)))


def param_surface(fn, ures, vres, tolerance=1e-9):
    """A closed vtkParametricFunction sampled on ures x vres, the seam merged."""
    src = vtk.vtkParametricFunctionSource()
    src.SetParametricFunction(fn)
    src.SetUResolution(ures)
    src.SetVResolution(vres)
    src.GenerateTextureCoordinatesOff()
    src.SetScalarModeToNone()
    src.SetOutputPointsPrecision(vtk.vtkAlgorithm.DOUBLE_PRECISION)
    src.Update()
    return polydata_to_lists(src.GetOutput(), tolerance=tolerance)


def knot_point(t):
    """The (2, 3) torus knot on a torus of radii 1 and 0.35."""
    r = 1.0 + 0.35 * math.cos(3 * t)
    return (r * math.cos(2 * t), r * math.sin(2 * t), 0.35 * math.sin(3 * t))


def case_knot(n_along=240, n_around=12, radius=0.12):
    """A tube of the given radius around the trefoil: rings of n_around
    points in a parallel-transported frame, whose closing twist is spread
    evenly along the curve so that the last ring meets the first."""
    c = [knot_point(2 * math.pi * i / n_along) for i in range(n_along)]

    def unit(v):
        n = math.sqrt(dot(v, v))
        return tuple(x / n for x in v)

    tang = [unit(sub(c[(i + 1) % n_along], c[i - 1])) for i in range(n_along)]
    seed = (0.0, 0.0, 1.0)
    u = [unit(sub(seed, tuple(dot(seed, tang[0]) * x for x in tang[0])))]
    for i in range(1, n_along + 1):
        t = tang[i % n_along]
        prev = u[-1]
        u.append(unit(sub(prev, tuple(dot(prev, t) * x for x in t))))
    # the transported frame comes back turned by some angle: undo it gradually
    w0 = cross(tang[0], u[0])
    twist = math.atan2(dot(u[n_along], w0), dot(u[n_along], u[0]))
    pts = []
    for i in range(n_along):
        t = tang[i]
        w = cross(t, u[i])
        for j in range(n_around):
            a = 2 * math.pi * j / n_around - twist * i / n_along
            pts.append(tuple(c[i][d] + radius * (math.cos(a) * u[i][d] + math.sin(a) * w[d])
                             for d in range(3)))
    tris = []
    for i in range(n_along):
        i1 = (i + 1) % n_along
        for j in range(n_around):
            j1 = (j + 1) % n_around
            a, b, cc, d = i * n_around + j, i1 * n_around + j, i1 * n_around + j1, i * n_around + j1
            tris += [(a, b, cc), (a, cc, d)]
    return pts, tris


def case_needle():
    s = vtk.vtkSphereSource()
    s.SetRadius(1.0)
    s.SetThetaResolution(40)
    s.SetPhiResolution(40)
    s.Update()
    pts, tris = polydata_to_lists(s.GetOutput())
    return [(8.0 * x, y, z) for x, y, z in pts], tris


def case_superellipsoid():
    f = vtk.vtkParametricSuperEllipsoid()
    f.SetN1(0.25)
    f.SetN2(0.25)
    f.SetXRadius(1.0)
    f.SetYRadius(0.7)
    f.SetZRadius(0.5)
    return param_surface(f, 64, 64)


def case_supertoroid():
    f = vtk.vtkParametricSuperToroid()
    f.SetN1(0.5)
    f.SetN2(0.5)
    f.SetRingRadius(1.0)
    f.SetCrossSectionRadius(0.4)
    return param_surface(f, 80, 40, tolerance=1e-6)


def box(bounds):
    b = vtk.vtkBox()
    b.SetBounds(*bounds)
    return b


def csg_contour(op, functions, bounds, dims):
    """Marching cubes (flying edges) of the zero level of a vtkImplicitBoolean
    (op: "Union", "Difference", ...) sampled on a grid."""
    f = vtk.vtkImplicitBoolean()
    getattr(f, "SetOperationTypeTo" + op)()
    for g in functions:
        f.AddFunction(g)
    return polydata_to_lists(contour(sample(f, bounds, dims), 0.0))


def case_csg_plate():
    hole = vtk.vtkCylinder()
    hole.SetRadius(0.3)
    hole.SetAxis(0, 0, 1)
    hole.SetCenter(0.3, 0, 0)
    return csg_contour("Difference", [box((-1, 1, -0.6, 0.6, -0.25, 0.25)), hole],
                       (-1.2, 1.2, -0.8, 0.8, -0.45, 0.45), (61, 41, 24))


def case_box_fin():
    return csg_contour("Union", [box((-1, 1, -1, 1, -1, 0)), box((-0.8, 0.8, -0.04, 0.04, -0.1, 0.9))],
                       (-1.2, 1.2, -1.2, 1.2, -1.2, 1.1), (49, 49, 47))


def case_csg_animal():
    """Marching cubes of the union of chains of spheres (a body and four
    legs) on 114 x 62 x 83 samples, about 42k triangles: where the legs
    meet the body the creases (60 to 90 degrees) are drawn as staircases of
    folds, part above theta_sharp and part below, where sliver elimination
    stalls (the folds where it is stuck become creases by default since
    session 31)."""
    spheres = []

    def chain(a, b, r, n=12):
        for i in range(n + 1):
            t = i / n
            s = vtk.vtkSphere()
            s.SetCenter(*[a[d] + (b[d] - a[d]) * t for d in range(3)])
            s.SetRadius(r)
            spheres.append(s)
    chain((-0.6, 0, 0), (0.6, 0, 0), 0.35)
    for x in (-0.45, 0.45):
        for y in (-0.2, 0.2):
            chain((x, y, 0), (x * 1.1, y * 1.3, -0.9), 0.09)
    return csg_contour("Union", spheres, (-1.1, 1.1, -0.6, 0.6, -1.1, 0.5), (114, 62, 83))


def case_gyroid_lattice():
    """A porous lattice: the solid side of a gyroid (two periods) clipped by
    a cube, marching cubes (flying edges) on 40^3 samples: smooth saddles,
    and where the lattice meets the cube's faces, creases drawn as
    staircases of folds on which sliver elimination does not converge
    (session 41: three rounds of folds made creases took 144 s on 60^3)."""
    n, L, pad = 40, 1.0, 0.1
    h = 2 * (L + pad) / (n - 1)
    k = 2 * math.pi  # two periods across the cube
    img = vtk.vtkImageData()
    img.SetDimensions(n, n, n)
    img.SetOrigin(-L - pad, -L - pad, -L - pad)
    img.SetSpacing(h, h, h)
    arr = vtk.vtkDoubleArray()
    arr.SetNumberOfTuples(n * n * n)
    i = 0
    for iz in range(n):
        z = -L - pad + iz * h
        for iy in range(n):
            y = -L - pad + iy * h
            for ix in range(n):
                x = -L - pad + ix * h
                g = (math.sin(k * x) * math.cos(k * y) + math.sin(k * y) * math.cos(k * z) +
                     math.sin(k * z) * math.cos(k * x))
                arr.SetValue(i, max(g / k, max(abs(x), abs(y), abs(z)) - L))
                i += 1
    img.GetPointData().SetScalars(arr)
    return polydata_to_lists(contour(img, 0.0))


def case_blobby_200():
    return polydata_to_lists(decimated_blobby(200))


def case_noisy_torus():
    t = vtk.vtkParametricTorus()
    t.SetRingRadius(1.0)
    t.SetCrossSectionRadius(0.35)
    pts, tris = param_surface(t, 90, 40)
    rng = random.Random(7)
    out = []
    for p in pts:
        rho = math.hypot(p[0], p[1])
        n = (p[0] - p[0] / rho, p[1] - p[1] / rho, p[2])  # from the tube's axis
        ln = math.sqrt(dot(n, n))
        f = rng.uniform(-0.02, 0.02)
        out.append(tuple(p[i] + f * n[i] / ln for i in range(3)))
    return out, tris


def case_hollow_sphere():
    """A sphere of radius 1 with a spherical cavity of radius 0.6: the inner
    surface oriented inward (flipped after clean, see CAVITIES)."""
    app = vtk.vtkAppendPolyData()
    for r, res in ((1.0, 48), (0.6, 32)):
        s = vtk.vtkSphereSource()
        s.SetRadius(r)
        s.SetThetaResolution(res)
        s.SetPhiResolution(res // 2)
        app.AddInputConnection(s.GetOutputPort())
    app.Update()
    return polydata_to_lists(app.GetOutput())


def case_box_speck():
    """A cube of side 10 (two triangles per face) and a sphere of radius
    0.01 (16 x 8) at (7, 0, 0), outside it: the sampling's darts go by
    area, and the speck's share is 1e-6 of it."""
    app = vtk.vtkAppendPolyData()
    cube = vtk.vtkCubeSource()
    cube.SetXLength(10)
    cube.SetYLength(10)
    cube.SetZLength(10)
    speck = vtk.vtkSphereSource()
    speck.SetRadius(0.01)
    speck.SetCenter(7, 0, 0)
    speck.SetThetaResolution(16)
    speck.SetPhiResolution(8)
    app.AddInputConnection(cube.GetOutputPort())
    app.AddInputConnection(speck.GetOutputPort())
    app.Update()
    return polydata_to_lists(app.GetOutput())


def case_cone():
    """vtkConeSource, 32 sides, capped: an apex where 32 creases-to-be meet
    at a point (a corner of high valence) and a sharp rim."""
    c = vtk.vtkConeSource()
    c.SetResolution(32)
    c.SetHeight(2.0)
    c.SetRadius(0.7)
    c.CappingOn()
    c.Update()
    return polydata_to_lists(c.GetOutput(), tolerance=1e-9)


def case_prism12():
    """vtkCylinderSource with 12 sides, 3 long: 30-degree folds along the
    whole length (coarse tessellation of a cylinder), sharp rims, caps of
    long thin triangles."""
    c = vtk.vtkCylinderSource()
    c.SetResolution(12)
    c.SetHeight(3.0)
    c.SetRadius(0.5)
    c.CappingOn()
    c.Update()
    return polydata_to_lists(c.GetOutput(), tolerance=1e-9)


def case_rod():
    """vtkCylinderSource with 24 sides, 12 long, radius 0.1, capped: each
    side is two right triangles 12 x 0.026, needles of aspect 460, as a CAD
    program exports a pin or a shaft. Their subfaces used to be halved
    across their longest edge, which keeps a right needle's aspect for
    ever (rmps.c, mps)."""
    c = vtk.vtkCylinderSource()
    c.SetResolution(24)
    c.SetHeight(12.0)
    c.SetRadius(0.1)
    c.CappingOn()
    c.Update()
    return polydata_to_lists(c.GetOutput(), tolerance=1e-9)


def case_pipe():
    """vtkCylinderSource with 96 sides, 2 long, radius 0.08, capped: a pipe
    10 error bounds in radius, 3 to 4 balls across its half turn. The
    balls there sit in near-quartets, which the centre lift's moves turned
    over; halving those lifts left -2.5% of the volume (centre_lift.c,
    reduce_lifts)."""
    c = vtk.vtkCylinderSource()
    c.SetResolution(96)
    c.SetHeight(2.0)
    c.SetRadius(0.08)
    c.CappingOn()
    c.Update()
    return polydata_to_lists(c.GetOutput(), tolerance=1e-9)


def case_thin_torus():
    """A torus of ring radius 1 and tube radius 0.05 (4.4 error bounds),
    600 x 40: a thin smooth tube (-0.54% of volume before the centre
    lift's near-quartets moved together)."""
    t = vtk.vtkParametricTorus()
    t.SetRingRadius(1.0)
    t.SetCrossSectionRadius(0.05)
    return param_surface(t, 600, 40)


def case_uv_noisy():
    """vtkSphereSource 300 x 180 of radius 1, every vertex moved along the
    radius by seeded noise of +-0.002 (1/7 of the error bound): 300
    needles meet at each pole, 0.0002 wide at their first ring, and the
    noise tips their normals by up to 85 degrees either way: thousands of
    folds over 60 degrees whose walks' normals mostly disagree, yet every
    needle still faces outward (vc_flat_near's least-squares plane)."""
    s = vtk.vtkSphereSource()
    s.SetRadius(1.0)
    s.SetThetaResolution(300)
    s.SetPhiResolution(180)
    s.Update()
    pts, tris = polydata_to_lists(s.GetOutput(), tolerance=1e-9)
    rng = random.Random(11)
    out = []
    for p in pts:
        ln = math.sqrt(dot(p, p))
        f = rng.uniform(-0.002, 0.002)
        out.append(tuple(v * (1 + f / ln) for v in p))
    return out, tris


def case_uv_tight():
    """vtkSphereSource 24 x 12 of radius 1: a coarse faceted sphere (folds
    of 15 to 30 degrees between facets 0.26 wide), meshed at an error bound
    of 1e-4 of its diagonal (e2e_hard_surfaces' OPTIONS), which sees every
    fold: until session 33 they were sampled as smooth, sliver elimination
    diverged (395,000 balls) and a second sampling made them creases (63,459
    balls, 76 s); now they are creases from the start."""
    s = vtk.vtkSphereSource()
    s.SetRadius(1.0)
    s.SetThetaResolution(24)
    s.SetPhiResolution(12)
    s.Update()
    return polydata_to_lists(s.GetOutput(), tolerance=1e-9)


def case_text():
    """The letters "VC" (vtkVectorText) extruded by 0.3: two components,
    many corners and creases, narrow strokes, caps of long thin triangles."""
    t = vtk.vtkVectorText()
    t.SetText("VC")
    e = vtk.vtkLinearExtrusionFilter()
    e.SetInputConnection(t.GetOutputPort())
    e.SetExtrusionTypeToVectorExtrusion()
    e.SetVector(0, 0, 0.3)
    e.CappingOn()
    e.Update()
    return polydata_to_lists(e.GetOutput(), tolerance=1e-9)


def perlin_sphere(freq, amp, half, res):
    """The unit sphere's quadric plus vtkPerlinNoise (frequency freq,
    amplitude amp) contoured on a res^3 grid over [-half, half]^3, the
    largest component: a bumpy marching-cubes surface."""
    q = quadric((1, 1, 1, 0, 0, 0, 0, 0, 0, -1))
    n = vtk.vtkPerlinNoise()
    n.SetFrequency(freq, freq, freq)
    n.SetAmplitude(amp)
    f = vtk.vtkImplicitSum()
    f.AddFunction(q)
    f.AddFunction(n)
    surf = contour(sample(f, (-half, half, -half, half, -half, half), (res, res, res)), 0.0)
    conn = vtk.vtkPolyDataConnectivityFilter()
    conn.SetInputData(surf)
    conn.SetExtractionModeToLargestRegion()
    conn.Update()
    return polydata_to_lists(conn.GetOutput())


def case_noise_blob(res=200):
    """Perlin noise of frequency 6 and amplitude 0.2 on the sphere, contoured
    on a res^3 grid (200: about 170k triangles): a bumpy, scan-like
    marching-cubes surface."""
    return perlin_sphere(6, 0.2, 1.6, res)


def case_perlin_blob(res=100):
    """Perlin noise of frequency 13 and amplitude 0.1 on the sphere, on a
    res^3 grid over [-1.4, 1.4]^3: bumps a few error bounds wide."""
    return perlin_sphere(13, 0.1, 1.4, res)


def jitter(pts, amplitude, seed):
    """Every point of the unit sphere's surface moved along its normal by
    seeded uniform noise of +-amplitude."""
    rng = random.Random(seed)
    out = []
    for p in pts:
        n = math.sqrt(dot(p, p))
        t = rng.uniform(-amplitude, amplitude)
        out.append(tuple(x + t * x / n for x in p))
    return out


def case_scan_sphere():
    """Marching cubes of the unit sphere (80^3 samples), every vertex moved
    along the normal by +-0.002: 1/7 of the default error bound, but the
    slivers' normals swing by more than 60 degrees."""
    s = vtk.vtkSphere()
    s.SetRadius(1.0)
    pts, tris = polydata_to_lists(contour(sample(s, (-1.3, 1.3, -1.3, 1.3, -1.3, 1.3), (80, 80, 80)), 0.0))
    return jitter(pts, 0.002, 23), tris


def normal_jitter(pts, tris, amplitude, seed):
    """Every vertex moved along its area-weighted normal by seeded uniform
    noise of +-amplitude."""
    nrm = [[0.0, 0.0, 0.0] for _ in pts]
    for t in tris:
        a, b, c = (pts[i] for i in t)
        n = cross(sub(b, a), sub(c, a))
        for i in t:
            for d in range(3):
                nrm[i][d] += n[d]
    rng = random.Random(seed)
    out = []
    for p, n in zip(pts, nrm):
        ln = math.sqrt(dot(n, n)) or 1.0
        t = rng.uniform(-amplitude, amplitude)
        out.append(tuple(p[d] + t * n[d] / ln for d in range(3)))
    return out


def case_rough_blob():
    """An icosahedron Loop-subdivided 5 times (20,480 triangles), projected
    onto a bumpy star-shaped surface, every vertex moved radially by up to
    0.7 of the default error bound: noise at the facets' own scale (a rough
    scan). A radial graph: the noise cannot make it intersect itself."""
    ico = vtk.vtkPlatonicSolidSource()
    ico.SetSolidTypeToIcosahedron()
    loop = vtk.vtkLoopSubdivisionFilter()
    loop.SetInputConnection(ico.GetOutputPort())
    loop.SetNumberOfSubdivisions(5)
    loop.Update()
    pts, tris = clean(*polydata_to_lists(loop.GetOutput()))

    def radius(u):
        x, y, z = u
        return 1.0 + 0.22 * math.sin(3 * x + 1) * math.cos(2 * y) + 0.15 * math.sin(4 * z + 2 * x)

    bumpy = []
    for p in pts:
        n = math.sqrt(dot(p, p))
        u = tuple(c / n for c in p)
        bumpy.append(tuple(c * radius(u) for c in u))
    amp = 0.7 * 0.004 * bbox_diag(bumpy)
    rng = random.Random(37)
    out = []
    for q in bumpy:
        n = math.sqrt(dot(q, q))
        t = rng.uniform(-amp, amp)
        out.append(tuple(c + t * c / n for c in q))
    return out, tris


def case_noisy_plate():
    """csg_plate Loop-subdivided once (marching-cubes staircases and a
    hole, 40k triangles), every vertex moved along its normal by up to 0.4
    of the default error bound: folds everywhere between facets smaller
    than the bound (a jittered fine tessellation)."""
    pts, tris = clean(*case_csg_plate())
    loop = vtk.vtkLoopSubdivisionFilter()
    loop.SetInputData(lists_to_polydata(pts, tris))
    loop.SetNumberOfSubdivisions(1)
    loop.Update()
    pts, tris = clean(*polydata_to_lists(loop.GetOutput()))
    return normal_jitter(pts, tris, 0.4 * 0.004 * bbox_diag(pts), 41), tris


def uv_sphere_with_edges(theta, phi):
    """A unit UV sphere, consistently oriented: its points, triangles and
    the triangle holding each directed edge."""
    s = vtk.vtkSphereSource()
    s.SetRadius(1.0)
    s.SetThetaResolution(theta)
    s.SetPhiResolution(phi)
    s.Update()
    pts, tris = clean(*polydata_to_lists(s.GetOutput()))
    tris = [tuple(t) for t in orient_consistently(tris)]
    edge_tri = {}
    for k, (a, b, c) in enumerate(tris):
        for u, v in ((a, b), (b, c), (c, a)):
            edge_tri[(u, v)] = k
    return pts, tris, edge_tri


def split_edges(pts, tris, edge_tri, first, count, limit, place):
    """Splits up to limit (None: no limit) triangles (u, v, o) taken every
    len(tris) // count from index first, none next to an earlier one across
    its edge u v: place(u, v, o, k2, made) gives the new point w and the
    triangle's three replacements, w written as None (the first takes the
    triangle's index, the others are appended); k2 is the triangle across
    u v, made the count so far."""
    done = set()
    made = 0
    for k in range(first, len(tris), len(tris) // count):
        u, v, o = tris[k]
        k2 = edge_tri[(v, u)]
        if k in done or k2 in done or made == limit:
            continue
        w, new = place(u, v, o, k2, made)
        pts.append(w)
        iw = len(pts) - 1
        new = [tuple(iw if x is None else x for x in t) for t in new]
        tris[k] = new[0]
        tris.extend(new[1:])
        done.update((k, k2))
        made += 1
    return pts, tris


def case_turned_needles():
    """A UV sphere with eight pleats: in eight triangles (u, v, o) a point w
    near the middle of the edge u v, moved across it onto the neighbouring
    triangle (v, u, a) by 0.1 to 0.45 of the default error bound (and a
    third of that off its plane), the triangle split into (u, v, w),
    (v, o, w), (o, u, w): the needle (u, v, w) turned over, as decimation
    and scan meshing leave them (cow.off has two)."""
    pts, tris, edge_tri = uv_sphere_with_edges(48, 24)
    bound = 0.004 * bbox_diag(pts)

    def pleat(u, v, o, k2, made):
        a = [x for x in tris[k2] if x not in (u, v)][0]
        m = [(pts[u][i] + pts[v][i]) / 2 for i in range(3)]
        d = sub(pts[a], m)
        ld = math.sqrt(dot(d, d))
        n2 = cross(sub(pts[u], pts[v]), sub(pts[a], pts[v]))
        ln = math.sqrt(dot(n2, n2))
        h = (0.1 + 0.05 * made) * bound
        w = tuple(m[i] + h * d[i] / ld + h / 3 * n2[i] / ln for i in range(3))
        return w, [(u, v, None), (v, o, None), (o, u, None)]

    return split_edges(pts, tris, edge_tri, 40, 8, None, pleat)


def case_fin_sphere():
    """A UV sphere with twelve T-junctions closed by slivers standing up:
    in twelve triangles (u, v, o) a point w 1e-6 (to 3e-6) outside the
    middle of the edge u v splits it into (u, w, o), (w, v, o), and the
    sliver (u, v, w) closes the junction against the triangle (v, u, a)
    across: a fin of that height, folding by about 90 degrees against
    both sides, as CAD exporters and T-junction repairs leave them. Its
    fold set the radius bound to 2.5e-9 (2.8e9 balls predicted, refused)
    until session 41."""
    pts, tris, edge_tri = uv_sphere_with_edges(40, 20)

    def fin(u, v, o, k2, made):
        m = [(pts[u][i] + pts[v][i]) / 2 for i in range(3)]
        lm = math.sqrt(dot(m, m))
        h = (1 + made / 6.0) * 1e-6
        w = tuple(m[i] * (1 + h / lm) for i in range(3))
        return w, [(u, None, o), (None, v, o), (u, v, None)]

    return split_edges(pts, tris, edge_tri, 30, 12, 12, fin)


def plant_needle(pts, tris, near, bound, tilt_deg=70.0, width=2e-7):
    """Splits the triangle (a, b, c) nearest the point near whose edge a b
    is shorter than half the error bound at a point m 'width' off the
    middle of a b towards c and tilted out of the plane: (a, b, m) is a
    needle whose normal leans tilt_deg from its neighbours', as marching
    cubes leave them where the contour passes a grid node."""
    best = None
    for k, t in enumerate(tris):
        for i in range(3):
            a, b, c = t[i], t[(i + 1) % 3], t[(i + 2) % 3]
            if math.sqrt(dot(sub(pts[a], pts[b]), sub(pts[a], pts[b]))) >= 0.5 * bound:
                continue
            d = sum((pts[a][j] - near[j]) ** 2 for j in range(3))
            if best is None or d < best[0]:
                best = (d, k, a, b, c)
    _, k, a, b, c = best
    ab = sub(pts[b], pts[a])
    n = cross(ab, sub(pts[c], pts[a]))
    ln = math.sqrt(dot(n, n))
    n = [x / ln for x in n]
    towards = cross(n, ab)  # in the plane, perpendicular to a b, towards c
    lt = math.sqrt(dot(towards, towards))
    up = width * math.tan(math.radians(tilt_deg))
    m = tuple(0.5 * (pts[a][j] + pts[b][j]) + width * towards[j] / lt + up * n[j] for j in range(3))
    pts.append(m)
    im = len(pts) - 1
    tris[k] = (a, b, im)
    tris.append((b, c, im))
    tris.append((c, a, im))


def case_mc_needles():
    """The noise blob (200^3) with four marching-cubes needles planted
    (plant_needle) on its bumps, where the ground within four error bounds
    is curved beyond a quadric's slab: each needle's three folds of 70
    degrees are a network of sharp edges smaller than the error bound."""
    pts, tris = case_noise_blob()
    pts, tris = clean(pts, tris)
    tris = [tuple(t) for t in tris]
    bound = 0.004 * bbox_diag(pts)
    for near in ((-0.8518, -0.2839, 0.4576), (0.3, 0.85, -0.35), (-0.2, -0.5, -0.85), (0.75, -0.4, 0.5)):
        plant_needle(pts, tris, near, bound)
    return pts, tris


def capped_sweep(rings, caps=True):
    """Triangles between consecutive closed rings of equal size (lists of
    points), each end closed by a fan from its ring's centroid; outward when
    the rings turn counter-clockwise seen from beyond the last ring."""
    m = len(rings[0])
    pts = [p for ring in rings for p in ring]
    tris = []
    for k in range(len(rings) - 1):
        for i in range(m):
            a, b = k * m + i, k * m + (i + 1) % m
            c, d = (k + 1) * m + (i + 1) % m, (k + 1) * m + i
            tris += [(a, b, c), (a, c, d)]
    for k, sign in ((0, -1), (len(rings) - 1, 1)):
        ring = rings[k]
        ci = len(pts)
        pts.append(tuple(sum(p[d] for p in ring) / m for d in range(3)))
        for i in range(m):
            a, b = k * m + i, k * m + (i + 1) % m
            tris.append((ci, b, a) if sign < 0 else (ci, a, b))
    return pts, tris


def naca4_half_thickness(t, x):
    """Half thickness of a symmetric NACA 4-digit section of thickness t at
    chord fraction x, with the closed trailing edge (-0.1036 x^4)."""
    return 5 * t * (0.2969 * math.sqrt(x) - 0.1260 * x - 0.3516 * x * x + 0.2843 * x ** 3
                    - 0.1036 * x ** 4)


def case_wing(n_chord=80, n_span=20, span=3.0, taper=0.4):
    """A NACA 0012 wing 3 long, its chord tapering from 1 to 0.4: a sharp
    trailing edge (a wedge of about 16 degrees), a blunt rounded leading
    edge, flat caps; cosine spacing along the chord."""
    xs = [0.5 * (1 - math.cos(math.pi * i / n_chord)) for i in range(n_chord + 1)]
    section = [(x, naca4_half_thickness(0.12, x)) for x in reversed(xs)] + \
              [(x, -naca4_half_thickness(0.12, x)) for x in xs[1:-1]]
    return tapered_wing(section, n_span, span, taper)


def tapered_wing(section, n_span, span, taper):
    """The section (a closed counter-clockwise list of (x, y), chord 1)
    swept along z over span in n_span steps, its chord tapering from 1 to
    taper about x = 0, capped, outward."""
    rings = []
    for k in range(n_span + 1):
        c = 1.0 - (1.0 - taper) * k / n_span
        rings.append([(c * x, c * y, span * k / n_span) for x, y in section])
    pts, tris = capped_sweep(rings)
    return pts, [(a, c, b) for a, b, c in tris]


def case_wing_round_te(n_chord=80, n_span=20, span=3.0, taper=0.4, te_radius=0.003, n_te=8):
    """The wing of case_wing with its trailing edge cut where the section is
    2 te_radius thick and rounded there by a half circle in n_te facets
    (0.24 of the error bound: a round the bound does not resolve, each of
    its folds below theta_sharp), the chord scaled back to 1."""
    def half(x):  # open trailing edge (the standard -0.1015 x^4)
        return 5 * 0.12 * (0.2969 * math.sqrt(x) - 0.1260 * x - 0.3516 * x * x + 0.2843 * x ** 3
                           - 0.1015 * x ** 4)
    lo, hi = 0.5, 1.0
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if half(mid) > te_radius else (lo, mid)
    xe = lo
    xs = [xe * 0.5 * (1 - math.cos(math.pi * i / n_chord)) for i in range(n_chord + 1)]
    section = [(x, half(x)) for x in reversed(xs)] + [(x, -half(x)) for x in xs[1:]]
    section += [(xe + te_radius * math.cos(a), te_radius * math.sin(a))
                for a in (-math.pi / 2 + math.pi * j / n_te for j in range(1, n_te))]
    return tapered_wing(section, n_span, span, taper)


def case_twisted_blade(n_chord=80, n_span=60, chord=0.3, span=1.5, twist=40.0):
    """A slender blade: the NACA 0012 section of case_wing, chord 0.3, swept
    1.5 along z and twisted by 40 degrees about its quarter chord, flat
    tips. Its 16-degree trailing edge spans a large share of the section at
    the error bound (0.0062, 2% of the chord): edge balls there as large as
    the tangent slab allows (21 bounds) took 0.5% off the volume."""
    xs = [0.5 * (1 - math.cos(math.pi * i / n_chord)) for i in range(n_chord + 1)]
    section = [(x, naca4_half_thickness(0.12, x)) for x in reversed(xs)] + \
              [(x, -naca4_half_thickness(0.12, x)) for x in xs[1:-1]]
    rings = []
    for k in range(n_span + 1):
        a = math.radians(twist * k / n_span)
        ca, sa = math.cos(a), math.sin(a)
        rings.append([(ca * chord * (x - 0.25) - sa * chord * y, sa * chord * (x - 0.25) + ca * chord * y,
                       span * k / n_span) for x, y in section])
    pts, tris = capped_sweep(rings)
    return pts, [(a, c, b) for a, b, c in tris]


def case_propeller(n=90, thickness=0.045):
    """A hub (sphere of radius 0.25) and three blades twisted by 35 degrees
    from root to tip, 0.045 thick (under two grid steps: marching cubes draws
    sheets a fraction of the error bound thick with ragged rims), the union
    contoured on n^3 samples. Session 49: the denoised copy's Taubin steps
    pulled the two sides of a blade together (0.0017 apart, then 1e-7) and
    the cells there failed validation."""
    L = 1.1
    h = 2 * L / (n - 1)
    img = vtk.vtkImageData()
    img.SetDimensions(n, n, n)
    img.SetOrigin(-L, -L, -L)
    img.SetSpacing(h, h, h)
    arr = vtk.vtkDoubleArray()
    arr.SetNumberOfTuples(n * n * n)
    axes = [(math.cos(2 * math.pi * k / 3), math.sin(2 * math.pi * k / 3)) for k in range(3)]
    i = 0
    for iz in range(n):
        z = -L + iz * h
        for iy in range(n):
            y = -L + iy * h
            for ix in range(n):
                x = -L + ix * h
                f = math.sqrt(x * x + y * y + z * z) - 0.25
                for ax, ay in axes:
                    r = x * ax + y * ay              # along the blade
                    s = -x * ay + y * ax             # across it, in the hub's plane
                    a = math.radians(35.0) * r
                    u = s * math.cos(a) - z * math.sin(a)
                    w = s * math.sin(a) + z * math.cos(a)
                    chord = 0.14 + 0.1 * r
                    f = min(f, max(abs(w) - thickness / 2, abs(u) - chord, r - 1.0, 0.1 - r))
                arr.SetValue(i, f)
                i += 1
    img.GetPointData().SetScalars(arr)
    return polydata_to_lists(contour(img, 0.0))


def case_pipe_bend(n=64, r=0.5, bend=1.5, straight=5.0):
    """A CFD pipe: radius 0.5, 5 straight, a 90-degree bend of radius 1.5,
    5 straight, 64 facets around, flat end caps (a fluid domain)."""
    frames = [((0.0, 0.0, -straight + straight * i / 50), (1.0, 0.0, 0.0)) for i in range(51)]
    for i in range(1, 41):
        a = (math.pi / 2) * i / 40
        frames.append(((bend - bend * math.cos(a), 0.0, bend * math.sin(a)), (math.cos(a), 0.0, -math.sin(a))))
    frames += [((bend + straight * i / 50, 0.0, bend), (0.0, 0.0, -1.0)) for i in range(1, 51)]
    rings = [[tuple(c[d] + r * (math.cos(2 * math.pi * k / n) * u[d] + math.sin(2 * math.pi * k / n) * (d == 1))
                    for d in range(3)) for k in range(n)] for c, u in frames]
    pts, tris = capped_sweep(rings)
    if sum(twice_volume6(pts, t) for t in tris) < 0:
        tris = [(a, c, b) for a, b, c in tris]
    return pts, tris


def twice_volume6(pts, t):
    a, b, c = (pts[i] for i in t)
    return dot(a, cross(b, c))


def case_dumbbell_thin(rn=0.01, n=96):
    """Two unit spheres 3 apart joined by a neck of radius 0.01 (a tenth of
    the error bound), sharp concave junctions, 96 facets around."""
    a0 = math.asin(rn)
    prof = []
    for i in range(1, 61):  # the lower sphere, from near its south pole to the neck
        th = math.pi - (math.pi - a0) * i / 60
        prof.append((math.sin(th), math.cos(th)))
    z0 = math.cos(a0)
    prof += [(rn, z0 + (3.0 - 2 * z0) * i / 40) for i in range(1, 40)]
    for i in range(0, 60):  # the upper sphere, from the neck to near its north pole
        th = math.pi - a0 - (math.pi - a0) * i / 60
        prof.append((math.sin(th), 3.0 + math.cos(th)))
    rings = [[(rho * math.cos(2 * math.pi * k / n), rho * math.sin(2 * math.pi * k / n), z) for k in range(n)]
             for rho, z in prof]
    return capped_sweep(rings)


def case_bracket_decimated():
    """An L bracket in millimetres (base 60 x 40 x 6, upright 6 x 40 x 50, a
    boss of radius 9 around the upright's hole, three holes), marching cubes
    (flying edges) on a 0.4 grid, then vtkQuadricDecimation to 10%: where
    the grid passes within 0.009 of the boss's rim, a ribbon of needle
    triangles 0.026 of the error bound wide, folding 80-86 degrees to one
    face and 44 to the other, the sharp side switching from edge to edge
    (session 50: 119,379 balls, 55 s on 2 threads; the same bracket on a
    grid shifted by 0.01, 29,076). Session 51: six hairpins collapsed
    before sampling, 44,500 balls, 26 s."""
    def cylinder(center, axis, r):
        c = vtk.vtkCylinder()  # about y
        c.SetRadius(r)
        t = vtk.vtkTransform()
        t.PostMultiply()
        t.Translate(-center[0], -center[1], -center[2])
        if axis == "z":
            t.RotateX(-90)
        elif axis == "x":
            t.RotateZ(90)
        c.SetTransform(t)
        return c
    boss = vtk.vtkImplicitBoolean()
    boss.SetOperationTypeToIntersection()
    boss.AddFunction(cylinder((6, 20, 32), "x", 9))
    boss.AddFunction(box((0, 10, 0, 40, 0, 50)))
    union = vtk.vtkImplicitBoolean()
    union.SetOperationTypeToUnion()
    for f in (box((0, 60, 0, 40, 0, 6)), box((0, 6, 0, 40, 0, 50)), boss):
        union.AddFunction(f)
    part = vtk.vtkImplicitBoolean()
    part.SetOperationTypeToDifference()
    for f in (union, cylinder((40, 12, 0), "z", 4), cylinder((40, 28, 0), "z", 4), cylinder((0, 20, 32), "x", 5)):
        part.AddFunction(f)
    image = sample(part, (-2.013, 62.007, -2.011, 42.009, -2.017, 52.003), (161, 111, 136))
    cl = vtk.vtkCleanPolyData()
    cl.SetInputData(contour(image, 0.0))
    cl.Update()
    dec = vtk.vtkQuadricDecimation()
    dec.SetInputConnection(cl.GetOutputPort())
    dec.SetTargetReduction(0.9)
    dec.Update()
    pts, tris = polydata_to_lists(dec.GetOutput())
    if sum(twice_volume6(pts, t) for t in tris) < 0:
        tris = [(a, c, b) for a, b, c in tris]
    return pts, tris


def case_flange_decimated():
    """A flange in millimetres (a disc of radius 40 and 12 thick, a hub of
    radius 20 up to 32, a bore of radius 11, six bolt holes of radius 4 on a
    circle of radius 30), flying edges on a 0.63 grid, then
    vtkQuadricDecimation to 10% with volume preservation. Session 51: 43,021
    balls, 19 s on one thread, for 1.9e4 predicted (the first coverage about
    22,000, sliver elimination doubles them), surface Q min 0.000; 3,458 of
    them (radius down to 5e-5) stacked on one 54.6-degree fold of the bottom
    face's chamfer, inside a patch, between two sector corners 0.9 apart."""
    def zcyl(cx, cy, r, z0, z1):
        c = vtk.vtkCylinder()
        c.SetRadius(r)
        c.SetCenter(cx, cy, 0.0)
        c.SetAxis(0.0, 0.0, 1.0)
        top, bottom = vtk.vtkPlane(), vtk.vtkPlane()
        top.SetOrigin(0.0, 0.0, z1)
        top.SetNormal(0.0, 0.0, 1.0)
        bottom.SetOrigin(0.0, 0.0, z0)
        bottom.SetNormal(0.0, 0.0, -1.0)
        b = vtk.vtkImplicitBoolean()
        b.SetOperationTypeToIntersection()
        for f in (c, top, bottom):
            b.AddFunction(f)
        return b
    body = vtk.vtkImplicitBoolean()
    body.SetOperationTypeToUnion()
    body.AddFunction(zcyl(0, 0, 40, 0, 12))
    body.AddFunction(zcyl(0, 0, 20, 0, 32))
    part = vtk.vtkImplicitBoolean()
    part.SetOperationTypeToDifference()
    part.AddFunction(body)
    part.AddFunction(zcyl(0, 0, 11, -5, 40))
    for k in range(6):
        a = 2 * math.pi * k / 6 + 0.3
        part.AddFunction(zcyl(30 * math.cos(a), 30 * math.sin(a), 4, -5, 20))
    h = 88.0 / 139
    dims = (140, 140, 64)
    sf = vtk.vtkSampleFunction()
    sf.SetImplicitFunction(part)
    sf.SetModelBounds(-44, -44 + 139 * h, -44, -44 + 139 * h, -4, -4 + 63 * h)
    sf.SetSampleDimensions(*dims)
    sf.ComputeNormalsOff()
    sf.SetOutputScalarTypeToDouble()
    sf.CappingOn()
    sf.SetCapValue(1.0e3)
    sf.Update()
    tri = vtk.vtkTriangleFilter()
    tri.SetInputData(contour(sf.GetOutput(), 0.0))
    cl = vtk.vtkCleanPolyData()
    cl.SetInputConnection(tri.GetOutputPort())
    cl.Update()
    dec = vtk.vtkQuadricDecimation()
    dec.SetTargetReduction(0.9)
    dec.VolumePreservationOn()
    dec.SetInputData(cl.GetOutput())
    dec.Update()
    tri2 = vtk.vtkTriangleFilter()
    tri2.SetInputData(dec.GetOutput())
    cl2 = vtk.vtkCleanPolyData()
    cl2.SetInputConnection(tri2.GetOutputPort())
    cl2.Update()
    pts, tris = polydata_to_lists(cl2.GetOutput())
    if sum(twice_volume6(pts, t) for t in tris) < 0:
        tris = [(a, c, b) for a, b, c in tris]
    return pts, tris


def case_hex_prism():
    """A capped hexagonal prism: its six side edges fold by exactly 60
    degrees, theta_sharp itself (to rounding), the caps' rims by 90."""
    ring = lambda z: [(math.cos(math.pi * i / 3), math.sin(math.pi * i / 3), z) for i in range(6)]
    return capped_sweep([ring(0.0), ring(1.5)])


def case_slot_block():
    """A 1 x 0.4 x 0.15 block with a saw cut 0.006 wide and 0.15 deep across
    its top (a profile extruded, vtkLinearExtrusionFilter): clean and sharp,
    but its 8 long slot edges fold at right angles like noise would, and a
    copy smoothed within half the error bound widens the slot (half the
    balls predicted) and loses 1.9% of the volume (session 38)."""
    L, H, w, depth, ext = 1.0, 0.4, 0.006, 0.15, 0.15
    return extruded([(0, 0), (L, 0), (L, H), (L / 2 + w / 2, H), (L / 2 + w / 2, H - depth),
                     (L / 2 - w / 2, H - depth), (L / 2 - w / 2, H), (0, H)], ext)


def case_chamfer_block():
    """A unit cube with one of its edges chamfered 0.004 wide (a profile
    extruded): the balls at the chamfer are a few thousandths wide and grow
    out over the two large faces beside it, where most of them lie. The
    prediction, the sizing at a fixed depth of sub-triangles, was 0.23 of
    the balls made (0.16 at 0.002 wide); refined where the bound falls,
    0.38 (session 39)."""
    w = 0.004
    return extruded([(0, 0), (1, 0), (1, 1 - w), (1 - w, 1), (0, 1)], 1.0)


def inner_sphere_inward(pts, tris):
    return [(a, c, b) if dot(pts[a], pts[a]) < 0.5 else (a, b, c) for a, b, c in tris]


def platonic(kind):
    """vtkPlatonicSolidSource of the given type (0 tetrahedron, 3
    icosahedron), triangulated."""
    src = vtk.vtkPlatonicSolidSource()
    src.SetSolidType(kind)
    tri = vtk.vtkTriangleFilter()
    tri.SetInputConnection(src.GetOutputPort())
    tri.Update()
    return polydata_to_lists(tri.GetOutput(), tolerance=1e-9)


def case_tetra():
    """A regular tetrahedron, 4 triangles: nothing but corners and sharp
    edges (70.5-degree dihedral angles)."""
    return platonic(0)


def case_icosa():
    """A regular icosahedron, 20 triangles: 12 corners of valence 5, every
    edge folding by 41.8 degrees (below theta_sharp)."""
    return platonic(3)


def extruded(outline, height):
    """A closed polygon (x, y) in the plane z = 0 extruded along z by height
    and capped (vtkLinearExtrusionFilter over the triangulated polygon)."""
    profile = [(x, y, 0.0) for x, y in outline]
    tri = vtk.vtkTriangleFilter()
    tri.SetInputData(lists_to_polydata(profile, [range(len(profile))]))
    e = vtk.vtkLinearExtrusionFilter()
    e.SetInputConnection(tri.GetOutputPort())
    e.SetExtrusionTypeToVectorExtrusion()
    e.SetVector(0, 0, height)
    e.CappingOn()
    tri2 = vtk.vtkTriangleFilter()
    tri2.SetInputConnection(e.GetOutputPort())
    tri2.Update()
    return polydata_to_lists(tri2.GetOutput(), tolerance=1e-9)


def case_gear():
    """A spur gear 0.4 thick, 24 trapezoidal teeth (radii 1 and 1.15): 192
    corners and their creases, caps triangulated as long fans (a CAD
    part)."""
    n, outline = 24, []
    for i in range(n):
        for rr, da in ((1.0, 0.0), (1.0, 0.3), (1.15, 0.45), (1.15, 0.75), (1.0, 0.9)):
            a = 2 * math.pi * (i + da) / n
            outline.append((rr * math.cos(a), rr * math.sin(a)))
    return extruded(outline, 0.4)


def case_wedge5():
    """A triangular prism whose section has a 5-degree angle (3 long, 1
    high): two faces meeting at 5 degrees along an edge, 8 triangles."""
    a = math.radians(5.0)
    return extruded([(0.0, 0.0), (3.0, 0.0), (3.0 * math.cos(a), 3.0 * math.sin(a))], 1.0)


def case_star():
    """A stellated icosahedron: a spike 2.5 from the centre on each of its
    20 faces, 60 triangles: narrow apexes and concave creases between the
    spikes."""
    pts, tris = platonic(3)
    pts = list(pts)
    out = []
    for a, b, c in tris:
        m = [(pts[a][k] + pts[b][k] + pts[c][k]) / 3.0 for k in range(3)]
        nm = math.sqrt(dot(m, m))
        pts.append(tuple(2.5 * x / nm for x in m))
        k = len(pts) - 1
        out += [(a, b, k), (b, c, k), (c, a, k)]
    return pts, out


def case_spring():
    """A helical spring: a tube of radius 0.1 (16 around) along 5 turns of a
    helix of radius 1 and pitch 0.23, its ends capped by fans: the turns
    0.03 apart (0.3 tube radii), a surface nearly touching itself along
    curves."""
    R, r, turns, pitch, n_along, n_around = 1.0, 0.1, 5, 0.23, 600, 16

    def helix(t):
        return (R * math.cos(t), R * math.sin(t), pitch * t / (2 * math.pi))

    pts, tris = [], []
    for i in range(n_along + 1):
        t = 2 * math.pi * turns * i / n_along
        c = helix(t)
        d = (-R * math.sin(t), R * math.cos(t), pitch / (2 * math.pi))
        ld = math.sqrt(dot(d, d))
        d = tuple(x / ld for x in d)
        n1 = (math.cos(t), math.sin(t), 0.0)
        n2 = cross(d, n1)
        for j in range(n_around):
            a = 2 * math.pi * j / n_around
            pts.append(tuple(c[k] + r * (math.cos(a) * n1[k] + math.sin(a) * n2[k]) for k in range(3)))
    for i in range(n_along):
        for j in range(n_around):
            a, b = i * n_around + j, i * n_around + (j + 1) % n_around
            tris += [(a, b, b + n_around), (a, b + n_around, a + n_around)]
    for i, end in ((0, 0), (n_along, 1)):
        pts.append(helix(2 * math.pi * turns * i / n_along))
        k = len(pts) - 1
        for j in range(n_around):
            a, b = i * n_around + j, i * n_around + (j + 1) % n_around
            tris.append((a, b, k) if end else (b, a, k))
    return pts, tris


def uv_sphere(theta, phi, radius=1.0, center=(0.0, 0.0, 0.0)):
    """vtkSphereSource's points and triangles, coincident points merged."""
    src = vtk.vtkSphereSource()
    src.SetThetaResolution(theta)
    src.SetPhiResolution(phi)
    src.SetRadius(radius)
    src.SetCenter(*center)
    src.Update()
    return polydata_to_lists(src.GetOutput(), tolerance=1e-12)


def case_far_sphere():
    """A UV sphere (40 x 20, radius 1) centred at (1e5, -2e5, 3e5): a part
    far from the origin, where single-precision tools lose a percent."""
    return uv_sphere(40, 20, 1.0, (1e5, -2e5, 3e5))


def case_thin_shell():
    """A spherical shell of radius 1, 0.03 thick (a sphere and, inside it,
    one of radius 0.97 facing in): two surfaces 3 percent of the size apart
    everywhere, the balls graded down to the gap."""
    pts, tris = uv_sphere(40, 20)
    n = len(pts)
    inner = [(0.97 * x, 0.97 * y, 0.97 * z) for x, y, z in pts]
    return pts + inner, tris + [(a + n, b + n, c + n) for a, b, c in tris]


def shell_inner_inward(pts, tris):
    return [(a, c, b) if dot(pts[a], pts[a]) < 0.97 else (a, b, c) for a, b, c in tris]


def case_bump_sphere():
    """A fine UV sphere of radius 2 (200 x 100) with a Gaussian bump 0.02
    high and about 0.06 wide: a feature a few error bounds across on a
    smooth surface."""
    pts, tris = uv_sphere(200, 100)
    c = (0.5, 0.0, 0.5 * math.sqrt(2.0))
    out = []
    for p in pts:
        g = math.exp(-sum((p[k] - c[k]) ** 2 for k in range(3)) / 0.0008)
        out.append(tuple(2.0 * x * (1.0 + 0.01 * g) for x in p))
    return out, tris


def case_mc_hemisphere():
    """Marching cubes of a half ball (a sphere cut by a plane through its
    centre, 90 x 90 x 60 samples): a smooth dome, a flat disc, and the
    90-degree rim between them as a staircase of slivers."""
    sph = vtk.vtkSphere()
    sph.SetRadius(1.0)
    plane = vtk.vtkPlane()
    plane.SetNormal(0, 0, -1)
    return csg_contour("Intersection", [sph, plane], (-1.2, 1.2, -1.2, 1.2, -0.3, 1.2), (90, 90, 60))


# cases whose clean surface is changed afterwards (cavities made inward)
POST_CLEAN = {"hollow_sphere": inner_sphere_inward, "thin_shell": shell_inner_inward}


# name, builder, what it tests, expected Euler characteristic
CASES = [
    ("blobby", case_blobby, "marching-cubes metaball isosurface: slivers and folds at every vertex", 2),
    ("blobby_500", case_blobby_500, "blobby decimated to ~500 triangles (vtkQuadricDecimation): coarse facets of a curved shape", 2),
    ("blobby_loop", case_blobby_loop, "blobby_500 after 4 Loop subdivisions: smooth, ~130k triangles", 2),
    ("blobby_fine", case_blobby_fine, "blobby contoured on a fine grid: ~200k marching-cubes triangles", 2),
    ("noisy_sphere", case_noisy_sphere, "sphere with seeded +-3% radial noise per vertex: kinks everywhere", 2),
    ("thin_plate", case_thin_plate, "1 x 1 x 0.02 box with sharp edges: thin part, long side triangles", 2),
    ("thin_plate_round", case_thin_plate_round, "1 x 1 x 0.02 plate with rounded edges (8 facets per half turn)", 2),
    ("near_spheres", case_near_spheres, "two spheres, 2 components, gap 1% of the radius", 4),
    ("coarse_torus", case_coarse_torus, "200-triangle parametric torus: 36-degree folds at every edge", 0),
    ("fillet_block", case_fillet_block, "1 x 0.7 x 0.5 block, fillets of radius 0.1 in 4 facets per quarter turn (fandisk kind)", 2),
    ("genus3", case_genus3, "blend of three tori: genus 3 marching-cubes isosurface", -4),
    ("knot", case_knot, "tube of radius 0.12 around a trefoil knot (240 x 12 quads): a thin curved tube", 0),
    ("needle", case_needle, "ellipsoid 16 x 2 x 2: a long thin part, curvature radius 1/8 at its tips", 2),
    ("superellipsoid", case_superellipsoid, "superellipsoid of exponent 0.25: flat faces meeting in tight smooth edges", 2),
    ("supertoroid", case_supertoroid, "supertoroid of exponent 0.5: a torus of nearly square cross-section", 0),
    ("csg_plate", case_csg_plate, "marching cubes of a plate minus a cylinder: creases as staircases, a hole", 0),
    ("box_fin", case_box_fin, "marching cubes of a box with a thin fin (0.08 thick) on top", 2),
    ("blobby_200", case_blobby_200, "blobby decimated to 200 triangles: very coarse facets of a curved shape", 2),
    ("noisy_torus", case_noisy_torus, "torus with seeded +-2% noise along the tube's normal: kinks everywhere", 0),
    ("hollow_sphere", case_hollow_sphere, "sphere with a spherical cavity (inner surface inward): 2 components", 4),
    ("box_speck", case_box_speck, "box of side 10 and apart a sphere of radius 0.01: 2 components 1000 times apart in size", 4),
    ("cone", case_cone, "capped 32-sided cone: an apex of valence 32 and a sharp rim", 2),
    ("prism12", case_prism12, "capped 12-sided cylinder 3 long: 30-degree folds along its length, sharp rims", 2),
    ("rod", case_rod, "capped 24-sided cylinder 12 long, radius 0.1: needle triangles of aspect 460", 2),
    ("pipe", case_pipe, "capped 96-sided cylinder 2 long, radius 0.08 (10 error bounds): a pipe a few balls across", 2),
    ("thin_torus", case_thin_torus, "parametric torus 600 x 40, tube radius 0.05 (4.4 error bounds): a thin smooth tube", 0),
    ("text", case_text, "the letters VC extruded: 2 components, many corners, narrow strokes", 4),
    ("scan_sphere", case_scan_sphere, "marching-cubes sphere, +-0.002 noise along the normal: folds over 60 degrees that are noise", 2),
    ("uv_noisy", case_uv_noisy, "UV sphere 300 x 180 with +-0.002 radial noise: noise-tipped needles at the poles", 2),
    ("turned_needles", case_turned_needles, "UV sphere with 8 turned-over needles (apex 0.1 to 0.45 of the error bound across its long edge)", 2),
    ("noise_blob", case_noise_blob, "sphere plus Perlin noise, marching cubes on 200^3: bumpy, scan-like, ~170k triangles", 2),
    ("csg_animal", case_csg_animal, "marching cubes of a union of sphere chains (a body, four legs): junction creases as staircases of folds", 2),
    ("wing", case_wing, "tapered NACA 0012 wing: a sharp trailing edge (16-degree wedge), a round leading edge, flat caps", 2),
    ("fillet_block_tiny", case_fillet_block_tiny, "block with fillets of radius a fifth of the error bound (rounds below the bound's resolution meeting at rounded corners)", 2),
    ("can_round_rims", case_can_round_rims, "cylinder whose rims are rounded to a seventh of the error bound (two closed rounds: closed creases at the bound's scale)", 2),
    ("twisted_blade", case_twisted_blade, "a slender NACA 0012 blade, chord 0.3, twisted 40 degrees over 1.5: a 16-degree trailing edge a sixth of the chord wide at the error bound's balls", 2),
    ("propeller", case_propeller, "marching cubes of a hub and three twisted blades 0.045 thick (under two grid steps): thin ragged sheets, noise-like folds", 2),
    ("pipe_bend", case_pipe_bend, "a CFD pipe of radius 0.5 with a 90-degree bend of radius 1.5 and flat caps (a fluid domain)", 2),
    ("dumbbell_thin", case_dumbbell_thin, "two unit spheres joined by a neck of radius 0.01 (a tenth of the error bound): a thin part between large ones", 2),
    ("flange_decimated", case_flange_decimated, "marching-cubes flange in mm decimated to 10%: sliver elimination stacks thousands of balls on a 55-degree fold inside a patch", -12),
    ("bracket_decimated", case_bracket_decimated, "marching-cubes L bracket in mm decimated to 10%: a ribbon of needles a fortieth of the error bound wide along a rim, its crease switching sides", -4),
    ("wing_round_te", case_wing_round_te, "the wing with its trailing edge rounded to a quarter of the error bound (a round below the bound's resolution: a crease at its scale)", 2),
    ("hex_prism", case_hex_prism, "capped hexagonal prism: side edges folding by exactly theta_sharp (60 degrees)", 2),
    ("uv_tight", case_uv_tight, "UV sphere 24 x 12 at an error bound of 1e-4: every fold of its facets seen by the bound", 2),
    ("rough_blob", case_rough_blob, "bumpy star-shaped subdivided icosahedron, every vertex moved radially by up to 0.7 of the default error bound: noise at the facets' scale", 2),
    ("noisy_plate", case_noisy_plate, "csg_plate Loop-subdivided, every vertex moved along its normal by up to 0.4 of the default error bound", 0),
    ("slot_block", case_slot_block, "block with a saw cut 0.006 wide (0.6% of its size): clean and sharp, not noise; a smoothed copy would widen the cut", 2),
    ("chamfer_block", case_chamfer_block, "unit cube with one edge chamfered 0.004 wide: a small feature along large faces, the balls graded out from it", 2),
    ("gyroid_lattice", case_gyroid_lattice, "gyroid lattice (2 periods) clipped by a cube, marching cubes on 40^3: saddles, and staircase creases where it meets the faces", -52),
    ("fin_sphere", case_fin_sphere, "UV sphere with 12 T-junctions closed by slivers standing 1e-6 to 3e-6 up (fins at 90 degrees)", 2),
    ("mc_needles", case_mc_needles, "noise_blob with 4 needles planted on its bumps: folds of 70 degrees, networks smaller than the error bound", 2),
    ("tetra", case_tetra, "regular tetrahedron, 4 triangles: corners and sharp edges only", 2),
    ("icosa", case_icosa, "regular icosahedron, 20 triangles: 42-degree folds at every edge, corners of valence 5", 2),
    ("gear", case_gear, "extruded spur gear, 24 teeth: 192 corners, long fan triangles on the caps (a CAD part)", 2),
    ("wedge5", case_wedge5, "triangular prism with a 5-degree edge: the thinnest wedge, 8 triangles", 2),
    ("star", case_star, "stellated icosahedron: 20 narrow spikes, concave creases between them", 2),
    ("spring", case_spring, "tube of radius 0.1 along a 5-turn helix, turns 0.3 tube radii apart: a surface nearly touching itself", 2),
    ("far_sphere", case_far_sphere, "UV sphere of radius 1 centred 3.7e5 from the origin", 2),
    ("thin_shell", case_thin_shell, "spherical shell 3% of its radius thick: two surfaces close everywhere", 4),
    ("bump_sphere", case_bump_sphere, "fine UV sphere of radius 2 with a Gaussian bump 0.02 high: a small smooth feature", 2),
    ("mc_hemisphere", case_mc_hemisphere, "marching cubes of a half ball: smooth dome, flat disc, a 90-degree rim as staircase slivers", 2),
    ("perlin_blob", case_perlin_blob, "sphere plus Perlin noise of frequency 11, marching cubes on 160^3: vertices whose triangles spread beyond theta_sharp with every fold below it", 2),
]


def main():
    if len(sys.argv) < 2 or sys.argv[1].startswith("-"):
        sys.stderr.write(__doc__)
        return 2
    outdir = sys.argv[1]
    only = set(sys.argv[2:])
    unknown = only - {c[0] for c in CASES}
    if unknown:
        sys.stderr.write("unknown case(s): %s\n" % ", ".join(sorted(unknown)))
        return 2
    os.makedirs(outdir, exist_ok=True)
    rows = []
    for name, build, what, euler in CASES:
        if only and name not in only:
            continue
        pts, tris = clean(*build())
        if name in POST_CLEAN:
            tris = POST_CLEAN[name](pts, tris)
        n_comp, vol = check(name, pts, tris, euler, cavities=name in POST_CLEAN)
        write_obj(os.path.join(outdir, name + ".obj"), pts, tris, what)
        rows.append((name, len(tris), what, euler))
        print("%-17s %7d triangles %7d vertices  euler %3d  components %d  volume %.6g"
              % (name, len(tris), len(pts), euler, n_comp, vol))
    with open(os.path.join(outdir, "manifest.csv"), "w") as f:
        f.write("name,triangles,tests,euler\n")
        for name, n, what, euler in rows:
            f.write('%s,%d,"%s",%d\n' % (name, n, what.replace('"', "'"), euler))
    return 0


if __name__ == "__main__":
    sys.exit(main())
