"""End-to-end test of the regions of a surface's arrangement
(include/vorocrust/regions.h): `vorocrust info` lists them (count,
volumes, kinds, nesting), and `vorocrust mesh --surface-only` meshes one
solid (with cavities, several disjoint parts, inward orientation) to its
volume, and every region of the others (interfaces between materials,
nested shells of the same orientation) to the input region's volume
(e2e_materials checks their volume meshes in depth).

The surfaces are generated here from voxel labellings of a small grid:
every unit face between two cells of different labels becomes two
triangles (once, its normal towards the lower label, label 0 being empty
space; or, with `twice`, once per labelled side facing out of it), so
the exact region volumes are the cell counts. Environment: VC_BIN, VC_TMP,
VC_SOURCE."""
import os
import re
import sys

sys.path.insert(0, os.path.join(os.environ["VC_SOURCE"], "tests"))
import e2eutil  # noqa: E402
from e2eutil import check, failures  # noqa: E402

BIN = os.environ["VC_BIN"]
TMP = os.path.join(os.environ.get("VC_TMP", "/tmp"), "e2e_regions")
os.makedirs(TMP, exist_ok=True)


def info_regions(path):
    rc, out, err = e2eutil.run([BIN, "info", path], timeout=60)
    regions = []
    for m in re.finditer(r"^region (\d+): volume ([-0-9.e+]+), (\w+), (outermost|inside region (\d+)), "
                         r"(\d+) holes", out, re.M):
        regions.append((float(m.group(2)), m.group(3), int(m.group(5)) if m.group(5) else 0,
                        int(m.group(6))))
    m = re.search(r"^one solid by orientation: (.*)$", out, re.M)
    return rc, regions, m.group(1) if m else None, out, err




# name: dims, label, twice, flip; expected regions (volume, kind, parent, holes)
# in input order, whether one solid, and the solid volume vorocrust mesh
# must reproduce (None: refused)
CASES = {
    "cube": ((2, 2, 2), lambda i, j, k: 1, False, False,
             [(8, "solid", 0, 0)], "yes", 8),
    "cube_inward": ((2, 2, 2), lambda i, j, k: 1, False, True,
                    [(8, "void", 0, 0)], "yes (oriented inward)", 8),
    "two_cubes": ((5, 2, 2), lambda i, j, k: 0 if i == 2 else 1, False, False,
                  [(8, "solid", 0, 0), (8, "solid", 0, 0)], "yes", 16),
    "cavity": ((4, 4, 4), lambda i, j, k: 0 if 1 <= i <= 2 and 1 <= j <= 2 and 1 <= k <= 2 else 1,
               False, False, [(56, "solid", 0, 1), (8, "void", 1, 0)], "yes", 56),
    "inclusion": ((4, 4, 4), lambda i, j, k: 2 if 1 <= i <= 2 and 1 <= j <= 2 and 1 <= k <= 2 else 1,
                  False, False, [(56, "mixed", 0, 1), (8, "solid", 1, 0)], "no", None),
    "shared_face": ((4, 2, 2), lambda i, j, k: 1 if i < 2 else 2, False, False,
                    [(8, "solid", 0, 0), (8, "mixed", 0, 0)], "no", None),
    "three_layers": ((2, 2, 3), lambda i, j, k: k + 1, False, False,
                     [(4, "solid", 0, 0), (4, "mixed", 0, 0), (4, "mixed", 0, 0)], "no", None),
    "t_wall": ((4, 2, 2), lambda i, j, k: 3 if i >= 2 else (1 if j == 0 else 2), False, False,
               [(4, "mixed", 0, 0), (4, "mixed", 0, 0), (8, "solid", 0, 0)], "no", None),
    "shared_face_twice": ((4, 2, 2), lambda i, j, k: 1 if i < 2 else 2, True, False,
                          [(8, "solid", 0, 0), (8, "solid", 0, 0)], "no", None),
}

def nested(i, j, k):
    # a 6-cube holding a 4-cube holding a 2-cube, every shell outward
    d = min(i, j, k, 5 - i, 5 - j, 5 - k)
    return 1 if d == 0 else 2 if d == 1 else 3


CASES["nested3"] = ((6, 6, 6), nested, False, False,
                    [(152, "mixed", 0, 1), (56, "mixed", 1, 1), (8, "solid", 2, 0)], "no", None)

for name, (dims, label, twice, flip, want, one, mesh_volume) in CASES.items():
    path = os.path.join(TMP, name + ".obj")
    e2eutil.voxel_surface(path, dims, label, twice, flip)
    rc, regions, single, out, err = info_regions(path)
    check(rc == 0, "%s: info exit %d: %s" % (name, rc, err))
    got = sorted(regions, key=lambda r: (r[0], r[1]))
    exp = sorted([(float(v), k, p, h) for v, k, p, h in want], key=lambda r: (r[0], r[1]))
    ok = len(got) == len(exp) and all(abs(g[0] - e[0]) <= 1e-9 * max(1, e[0]) and g[1:] == e[1:]
                                      for g, e in zip(got, exp))
    check(ok, "%s: regions %r, expected %r" % (name, regions, want))
    check(single == one, "%s: one solid %r, expected %r" % (name, single, one))
    print("%s: %d regions %s, one solid: %s" % (name, len(regions), regions, single), flush=True)

    surf = os.path.join(TMP, name + "_surface.obj")
    if os.path.exists(surf):
        os.remove(surf)
    rc, out, err = e2eutil.run([BIN, "mesh", path, "--surface-only", "--surface", surf,
                                "--threads", "2"], timeout=110)
    if mesh_volume is None:
        # several materials: every region meshed, its volume the input's
        check(rc == 0, "%s: mesh exit %d: %s" % (name, rc, err[-800:]))
        got = [(float(m.group(2)), float(m.group(3))) for m in re.finditer(
            r"^  region (\d+): \d+ cells, volume ([-0-9.e+]+) \(input ([-0-9.e+]+)", err, re.M)]
        check(len(got) == len(want) and all(abs(v - w) <= 0.005 * w for v, w in got),
              "%s: region volumes (mesh, input) %r, expected %d regions within 0.5%%" % (name, got, len(want)))
        print("%s: meshed, %d regions, volumes (mesh, input) %r" % (name, len(got), got), flush=True)
    else:
        check(rc == 0, "%s: mesh exit %d: %s" % (name, rc, err[-800:]))
        if rc == 0:
            v = abs(e2eutil.obj_volume(surf))
            check(abs(v - mesh_volume) <= 0.005 * mesh_volume,
                  "%s: reconstructed volume %.6g, the solid's %g" % (name, v, mesh_volume))
            print("%s: meshed, reconstructed volume %.6g of %g" % (name, v, mesh_volume), flush=True)

# --cavities: nested closed shells alternate solid and cavity (the
# outermost solid) whatever their orientation; an interface is refused.
for name, volume in (("inclusion", 56), ("nested3", 152 + 8), ("cavity", 56), ("cube_inward", 8),
                     ("shared_face", None)):
    path = os.path.join(TMP, name + ".obj")
    surf = os.path.join(TMP, name + "_cavities.obj")
    if os.path.exists(surf):
        os.remove(surf)
    rc, out, err = e2eutil.run([BIN, "mesh", path, "--cavities", "--surface-only", "--surface", surf,
                                "--threads", "2"], timeout=110)
    if volume is None:
        check(rc == 1 and len(err.strip().splitlines()) == 1 and "--cavities needs closed shells" in err
              and not os.path.exists(surf), "%s --cavities: exit %d, %r" % (name, rc, err))
        continue
    check(rc == 0, "%s --cavities: exit %d: %s" % (name, rc, err[-800:]))
    if rc == 0:
        v = abs(e2eutil.obj_volume(surf))
        check(abs(v - volume) <= 0.005 * volume, "%s --cavities: reconstructed volume %.6g, the "
              "solid's %g" % (name, v, volume))
        print("%s --cavities: meshed, reconstructed volume %.6g of %g" % (name, v, volume), flush=True)

sys.exit(1 if failures else 0)
