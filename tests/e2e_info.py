"""End-to-end test of `vorocrust info`: output and exit codes for good and
bad inputs. Environment: VC_BIN (the vorocrust executable), VC_MODELS (the
shared models), VC_TMP (a writable directory), VC_SOURCE (the source tree)."""
import os
import sys

sys.path.insert(0, os.path.join(os.environ["VC_SOURCE"], "tests"))
import e2eutil  # noqa: E402
from e2eutil import check, failures, field  # noqa: E402

BIN = os.environ["VC_BIN"]
# Two parts, one ctest test each (tests/CMakeLists.txt): "models" (fertility.off
# and cube.off from the shared models: skipped, exit 77, without them) and
# "cli" (help and bad input, from the repository alone).
if len(sys.argv) != 2 or sys.argv[1] not in ("models", "cli"):
    print("usage: e2e_info.py models|cli", file=sys.stderr)
    sys.exit(2)
PART = sys.argv[1]
MODELS = e2eutil.models_dir() if PART == "models" else None
TMP = os.environ.get("VC_TMP", "/tmp")


def write_obj(path, pts, tris):
    """An OBJ of points and 0-based triangles, coordinates to the last bit."""
    with open(path, "w") as f:
        f.writelines("v %.17g %.17g %.17g\n" % tuple(p) for p in pts)
        f.writelines("f %d %d %d\n" % (a + 1, b + 1, c + 1) for a, b, c in tris)


def run(*args):
    return e2eutil.run([BIN, "info", *args], timeout=60)


if PART == "models":
    # A good model: fertility (genus 4).
    path = os.path.join(MODELS, "fertility.off")
    rc, out, err = run(path)
    check(rc == 0, "fertility.off: exit %d, stderr %r" % (rc, err))
    check(err == "", "fertility.off: unexpected stderr %r" % err)
    check(field(out, "vertices") == "4494", "fertility vertices %r" % field(out, "vertices"))
    check(field(out, "triangles") == "9000", "fertility triangles %r" % field(out, "triangles"))
    check(field(out, "euler characteristic") == "-6", "fertility euler %r" % field(out, "euler characteristic"))
    check(field(out, "genus") == "4", "fertility genus %r" % field(out, "genus"))
    check(field(out, "boundary edges") == "0", "fertility boundary edges")
    check(field(out, "non-manifold edges") == "0", "fertility non-manifold edges")
    check(field(out, "closed") == "yes", "fertility closed")
    vol = field(out, "enclosed volume")
    check(vol is not None and float(vol.split()[0]) > 0, "fertility volume %r" % vol)
    check(field(out, "bounding box") is not None, "fertility bounding box missing")
    check(field(out, "turned-over needles") == "0", "fertility turned-over needles %r"
          % field(out, "turned-over needles"))

    # cow.off: four turned-over needles, flipped as vorocrust mesh flips
    # them, then the union of its parts (session 30)
    rc, out, err = run(os.path.join(MODELS, "cow.off"))
    needles = field(out, "turned-over needles") or ""
    check(rc == 0 and needles.startswith("4 flipped, as vorocrust mesh flips them") and
          field(out, "self-intersections") == "79" and
          (field(out, "union") or "").startswith("5638 triangles"),
          "cow.off: exit %d, needles %r, self-intersections %r, union %r"
          % (rc, needles, field(out, "self-intersections"), field(out, "union")))

    # Quads: a warning line on stderr, exit 0.
    rc, out, err = run(os.path.join(MODELS, "cube.off"))
    check(rc == 0, "cube.off exit %d" % rc)
    lines = err.strip().splitlines()
    check(len(lines) == 1 and "cube.off: 6 non-triangle faces triangulated" in lines[0],
          "cube.off stderr %r" % err)
    check(abs(float(field(out, "enclosed volume").split()[0]) - 4.0) < 1e-9, "cube.off volume")

if PART == "cli":
    # Help.
    rc, out, err = run("--help")
    check(rc == 0 and "usage: vorocrust info" in out, "--help: exit %d, %r" % (rc, out))


    def expect_error(args, needle, name):
        rc, out, err = run(*args)
        lines = err.strip().splitlines()
        check(rc != 0, "%s: exit code 0" % name)
        check(len(lines) == 1, "%s: %d stderr lines: %r" % (name, len(lines), err))
        check(lines and lines[-1].startswith("vorocrust: ") and name in lines[-1] and needle in lines[-1],
              "%s: stderr %r lacks %r" % (name, err, needle))


    missing = os.path.join(TMP, "e2e_info_missing.obj")
    expect_error([missing], "cannot open", missing)

    nan = os.path.join(TMP, "e2e_info_nan.obj")
    with open(nan, "w") as f:
        f.write("v 0 0 0\nv 1 0 0\nv 0 nan 0\nf 1 2 3\n")
    expect_error([nan], "non-finite", nan)

    bad_ext = os.path.join(TMP, "e2e_info.xyz")
    with open(bad_ext, "w") as f:
        f.write("0 0 0\n")
    expect_error([bad_ext], "unsupported file extension", bad_ext)

    empty = os.path.join(TMP, "e2e_info_empty.stl")
    open(empty, "w").close()
    expect_error([empty], "empty file", empty)

    # Open surface: a warning, exit 0; with --require-closed exit 1.
    tet_open = os.path.join(TMP, "e2e_info_open.obj")
    with open(tet_open, "w") as f:
        f.write("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\n")
    rc, out, err = run(tet_open)
    check(rc == 0 and field(out, "boundary edges") == "3", "open tet: exit %d, out %r" % (rc, out))
    check("3 open boundary edges" in err and len(err.strip().splitlines()) == 1, "open tet stderr %r" % err)
    rc, out, err = run(tet_open, "--require-closed")
    check(rc == 1 and err.strip().splitlines()[-1] ==
          "vorocrust: %s: 3 open boundary edges (surface is not closed)" % tet_open,
          "--require-closed: exit %d, stderr %r" % (rc, err))

    # A surface open only by rounding (a seam's vertices written twice, 1e-15
    # apart, as VTK's parametric sources write them): info and mesh weld
    # them and go on; a real gap (1e-4 of the size) stays open and is
    # refused with one line.
    def split_sphere(path, offset):
        """A UV sphere whose meridian at longitude 0 is written twice, the
        second copy moved by offset along y (the last column of quads
        uses it)."""
        import math
        nu, nv = 16, 8
        pts, tris = [(0, 0, 1), (0, 0, -1)], []
        idx = {}
        for j in range(1, nv):
            for i in range(nu + 1):
                th, ph = math.pi * j / nv, 2 * math.pi * (i % nu) / nu
                p = (math.sin(th) * math.cos(ph), math.sin(th) * math.sin(ph) + (offset if i == nu else 0),
                     math.cos(th))
                idx[(i, j)] = len(pts)
                pts.append(p)
        for i in range(nu):
            tris.append((0, idx[(i, 1)], idx[(i + 1, 1)]))
            tris.append((1, idx[(i + 1, nv - 1)], idx[(i, nv - 1)]))
            for j in range(1, nv - 1):
                a, b, c, d = idx[(i, j)], idx[(i, j + 1)], idx[(i + 1, j + 1)], idx[(i + 1, j)]
                tris += [(a, b, c), (a, c, d)]
        write_obj(path, pts, tris)

    seam = os.path.join(TMP, "e2e_info_seam.obj")
    split_sphere(seam, 1e-15)
    rc, out, err = run(seam, "--require-closed")
    check(rc == 0 and (field(out, "seam welding") or "").startswith("16 open edges closed by welding 7 vertices")
          and field(out, "boundary edges") == "0" and field(out, "solid") == "yes" and err == "",
          "seam split by 1e-15: exit %d, stdout %r, stderr %r" % (rc, out[:600], err))
    p = e2eutil.run([BIN, "mesh", seam, "-o", os.path.join(TMP, "e2e_info_seam.vtu")], timeout=120)
    check(p[0] == 0 and "7 vertices within" in p[2] and "the surface closed" in p[2] and
          "euler 2 (input 2), closed 2-manifold" in p[2],
          "mesh of the seam split by 1e-15: exit %d, stderr %r" % (p[0], p[2][-800:]))
    gap = os.path.join(TMP, "e2e_info_gap.obj")
    split_sphere(gap, 2e-4)
    rc, out, err = run(gap)
    check(rc == 0 and field(out, "seam welding") is None and field(out, "boundary edges") == "16",
          "seam split by 2e-4: exit %d, stdout %r" % (rc, out[:600]))
    p = e2eutil.run([BIN, "mesh", gap, "-o", os.path.join(TMP, "e2e_info_gap.vtu")], timeout=120)
    lines = p[2].strip().splitlines()
    check(p[0] == 1 and len(lines) == 1 and "the surface is open: 16 boundary edges" in lines[0] and
          "welding the vertices within" in lines[0] and "does not close it" in lines[0] and
          not os.path.exists(os.path.join(TMP, "e2e_info_gap.vtu")),
          "mesh of the seam split by 2e-4: exit %d, stderr %r" % (p[0], p[2]))

    # T-junctions: a unit cube whose top face has three vertices on its front
    # edge (1e-12 off it), which the front face does not have: info and mesh
    # split the front face's triangle there; 1e-5 off the edge stays open.
    def t_junction_cube(path, eps):
        v = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0), (0, 0, 1), (1, 0, 1), (1, 1, 1), (0, 1, 1),
             (0.25, eps, 1), (0.5, -eps, 1), (0.75, 0, 1)]
        t = []
        for a, b, c, d in ((0, 3, 2, 1), (0, 1, 5, 4), (1, 2, 6, 5), (2, 3, 7, 6), (3, 0, 4, 7)):
            t += [(a, b, c), (a, c, d)]
        top = [4, 8, 9, 10, 5, 6, 7]
        t += [(top[-1], top[i], top[i + 1]) for i in range(len(top) - 2)]
        write_obj(path, v, t)

    tj = os.path.join(TMP, "e2e_info_tjunction.obj")
    t_junction_cube(tj, 1e-12)
    rc, out, err = run(tj, "--require-closed")
    check(rc == 0 and "splitting 1 triangles at vertices on their edges" in (field(out, "seam welding") or "")
          and field(out, "solid") == "yes" and field(out, "enclosed volume") == "1",
          "T-junction cube: exit %d, stdout %r, stderr %r" % (rc, out[:700], err))
    p = e2eutil.run([BIN, "mesh", tj, "-o", os.path.join(TMP, "e2e_info_tjunction.vtu")], timeout=120)
    check(p[0] == 0 and "1 triangles split at vertices on their edges (T-junctions)" in p[2] and
          "euler 2 (input 2), closed 2-manifold" in p[2] and "volume 1 (reconstructed surface 1, input 1)" in p[2],
          "mesh of the T-junction cube: exit %d, stderr %r" % (p[0], p[2][-800:]))
    # the same far from the origin in single precision (a binary STL's
    # rounding: half a float ulp at 10,000 is 5e-4, 2e-6 of the part): the
    # tolerance grows with the coordinates' magnitude
    import math
    import struct
    t_junction_cube(tj, 0)
    with open(tj) as f:
        lines = f.read().splitlines()
    f32 = lambda x: struct.unpack("f", struct.pack("f", x))[0]
    far = os.path.join(TMP, "e2e_info_tjunction_far_f32.obj")
    with open(far, "w") as f:
        for line in lines:
            w = line.split()
            if w[0] == "v":
                x, y, z = map(float, w[1:])
                x, y = x * math.cos(0.7) - y * math.sin(0.7), x * math.sin(0.7) + y * math.cos(0.7)
                y, z = y * math.cos(0.3) - z * math.sin(0.3), y * math.sin(0.3) + z * math.cos(0.3)
                line = "v %.9g %.9g %.9g" % (f32(137 * x + 10000), f32(137 * y + 2000), f32(137 * z - 300))
            f.write(line + "\n")
    p = e2eutil.run([BIN, "mesh", far, "-o", os.path.join(TMP, "e2e_info_tjunction_far_f32.vtu")], timeout=120)
    check(p[0] == 0 and "1 triangles split at vertices on their edges (T-junctions)" in p[2] and
          "euler 2 (input 2), closed 2-manifold" in p[2],
          "mesh of the T-junction cube far away in single precision: exit %d, stderr %r" % (p[0], p[2][-800:]))
    t_junction_cube(tj, 1e-5)
    p = e2eutil.run([BIN, "mesh", tj, "-o", os.path.join(TMP, "e2e_info_tjunction_far.vtu")], timeout=120)
    check(p[0] == 1 and "the surface is open: 5 boundary edges" in p[2] and len(p[2].strip().splitlines()) == 1,
          "mesh of the cube with vertices 1e-5 off the edge: exit %d, stderr %r" % (p[0], p[2]))

    # The same cube closed by three zero-area caps along that edge (an
    # exporter's slivers): info and mesh split the front face's triangle at
    # the caps' vertices instead; nothing else changes.
    caps = os.path.join(TMP, "e2e_info_caps.obj")
    t_junction_cube(caps, 0)
    with open(caps, "a") as f:
        f.write("f 5 6 11\nf 5 11 10\nf 5 10 9\n")
    rc, out, err = run(caps, "--require-closed")
    check(rc == 0 and (field(out, "zero-area repair") or "").startswith("3 of 3 zero-area triangles were caps")
          and field(out, "degenerate triangles") == "0" and field(out, "solid") == "yes"
          and field(out, "enclosed volume") == "1" and field(out, "seam welding") is None,
          "capped cube: exit %d, stdout %r, stderr %r" % (rc, out[:800], err))
    p = e2eutil.run([BIN, "mesh", caps, "-o", os.path.join(TMP, "e2e_info_caps.vtu")], timeout=120)
    check(p[0] == 0 and "3 of its 3 zero-area triangles were caps" in p[2] and
          "euler 2 (input 2), closed 2-manifold" in p[2] and "volume 1 (reconstructed surface 1, input 1)" in p[2],
          "mesh of the capped cube: exit %d, stderr %r" % (p[0], p[2][-800:]))

    # A vertex given twice 1e-13 apart (not merged: not exactly equal),
    # the bottom face on one copy, the rest on the other, closed by two
    # zero-area needles: info and mesh weld the copies and drop the needles.
    needle = os.path.join(TMP, "e2e_info_needles.obj")
    with open(needle, "w") as f:
        f.write("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\nv 0 0 1e-13\n"
                "f 9 3 2\nf 9 4 3\nf 5 6 7\nf 5 7 8\nf 1 2 6\nf 1 6 5\nf 2 3 7\nf 2 7 6\nf 3 4 8\n"
                "f 3 8 7\nf 4 1 5\nf 4 5 8\nf 2 1 9\nf 9 1 4\n")
    rc, out, err = run(needle, "--require-closed")
    check(rc == 0 and (field(out, "zero-area needles") or "").startswith("2 of 2 zero-area triangles")
          and field(out, "degenerate triangles") == "0" and field(out, "solid") == "yes",
          "cube with two needles: exit %d, stdout %r, stderr %r" % (rc, out[:800], err))
    p = e2eutil.run([BIN, "mesh", needle, "-o", os.path.join(TMP, "e2e_info_needles.vtu")], timeout=120)
    check(p[0] == 0 and "2 zero-area needles" in p[2] and
          "volume 1 (reconstructed surface 1, input 1)" in p[2],
          "mesh of the cube with two needles: exit %d, stderr %r" % (p[0], p[2][-800:]))

    # An assembly with one part inside out (two unit cubes apart, the second
    # one's triangles reversed): its signed volume sums to 0, which read as
    # "a flat surface encloses no volume"; each part's volume counts now, and
    # mesh reverses a shell with nothing around it whose normals point in.
    cube_v = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0), (0, 0, 1), (1, 0, 1), (1, 1, 1), (0, 1, 1)]
    cube_f = [(1, 3, 2), (1, 4, 3), (5, 6, 7), (5, 7, 8), (1, 2, 6), (1, 6, 5), (2, 3, 7), (2, 7, 6),
              (3, 4, 8), (3, 8, 7), (4, 1, 5), (4, 5, 8)]
    two = os.path.join(TMP, "e2e_info_inside_out.obj")
    with open(two, "w") as f:
        f.writelines("v %g %g %g\n" % (x + dx, y, z) for dx in (0, 2) for x, y, z in cube_v)
        f.writelines("f %d %d %d\n" % t for t in cube_f)
        f.writelines("f %d %d %d\n" % (a + 8, c + 8, b + 8) for a, b, c in cube_f)
    rc, out, err = run(two, "--require-closed")
    check(rc == 0 and field(out, "solid") == "yes" and
          (field(out, "inside out") or "").startswith("1 of 2 components"),
          "cubes, one inside out: exit %d, stdout %r, stderr %r" % (rc, out[-600:], err))
    p = e2eutil.run([BIN, "mesh", two, "-o", os.path.join(TMP, "e2e_info_inside_out.vtu")], timeout=120)
    check(p[0] == 0 and "1 of its 2 surface components were inside out" in p[2] and
          "volume 2 (reconstructed surface 2, input 2)" in p[2],
          "mesh of the cubes, one inside out: exit %d, stderr %r" % (p[0], p[2][-800:]))

    # A repeated option is refused with one line, exit 2, as in the other
    # commands (a second --sharp-angle must not silently win).
    tet = os.path.join(TMP, "e2e_info_tet.obj")
    with open(tet, "w") as f:
        f.write("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n")
    for args, opt in (([tet, "--require-closed", "--require-closed"], "--require-closed"),
                      ([tet, "--features", "--features"], "--features"),
                      ([tet, "--sharp-angle", "30", "--sharp-angle", "40"], "--sharp-angle"),
                      (["--require-closed", tet, "--features", "--require-closed"], "--require-closed")):
        rc, out, err = run(*args)
        lines = err.strip().splitlines()
        check(rc == 2 and len(lines) == 1 and lines[0] ==
              "vorocrust: %s given twice (see 'vorocrust info --help')" % opt and out == "",
              "info %s: exit %d, stdout %r, stderr %r (expected exit 2, one line '%s given twice')"
              % (" ".join(args[1:]), rc, out[:200], err, opt))
    rc, out, err = run(tet, "--features", "--sharp-angle", "30", "--require-closed")
    check(rc == 0 and field(out, "sharp angle") == "30 degrees",
          "--features --sharp-angle 30 --require-closed: exit %d, stderr %r" % (rc, err))

    # a reversed triangle: info says what vorocrust mesh does with it
    with open(tet) as f:
        text = f.read().splitlines()
    first = [i for i, l in enumerate(text) if l.startswith("f ")][0]
    w = text[first].split()
    text[first] = " ".join([w[0], w[1], w[3], w[2]])
    flipped = os.path.join(TMP, "info_flipped_tet.obj")
    with open(flipped, "w") as f:
        f.write("\n".join(text) + "\n")
    rc, out, err = run(flipped)
    check(rc == 0 and field(out, "inconsistently oriented edges") == "3" and
          (field(out, "orientation repair") or "").startswith("1 triangles reversed, as vorocrust mesh") and
          field(out, "solid") == "yes" and field(out, "enclosed volume") == "0.166666667",
          "flipped tetrahedron: exit %d, stdout %r" % (rc, out[:900]))

if failures:
    print("e2e_info: %d failures" % len(failures), file=sys.stderr)
    sys.exit(1)
print("e2e_info %s: all passed" % PART)
