"""End-to-end regression test of hostile inputs (issue 17): the reproducers
of the reader audit (tests/data/repro/, copied from the audit's shared
folder) and a few malformed files written here. Each must give exit 1 and
exactly one line "vorocrust: FILE: ..." naming the real problem, with no
sanitizer report, within 1 s (10 s when VC_SANITIZED=1).

Environment: VC_BIN (the vorocrust executable), VC_TMP (a writable
directory), VC_SOURCE (the source tree), VC_SANITIZED (1 under ASan/UBSan).
"""
import os
import re
import struct
import sys
import time

sys.path.insert(0, os.path.join(os.environ["VC_SOURCE"], "tests"))
import e2eutil  # noqa: E402
from e2eutil import check, failures  # noqa: E402

BIN = os.environ["VC_BIN"]
REPRO = os.path.join(os.environ["VC_SOURCE"], "tests", "data", "repro")
LIMIT = 10.0 if os.environ.get("VC_SANITIZED", "0") in ("1", "ON", "TRUE", "true") else 1.0
TMP = e2eutil.fresh_tmp("e2e_repro")

# (file, command, a substring the one line must hold)
REPRODUCERS = [
    ("off_index_int64max.off", "info", "refers to vertex 9223372036854775807"),
    ("off_openmesh_huge_reserve.off", "info", "missing OFF header"),
    ("off_openmesh_timeout.off", "info", "binary OFF: the header announces"),
    ("ply_nan_list_length.ply", "info", "list length nan is not an integer"),
    ("vtu_heap_overflow_min48.vtu", "quality", "no Piece"),
    ("vtu_appended_marker_at_eof.vtu", "quality", "no polyhedron or tetrahedron"),
    ("vtu_real_mesh_cut_after_marker.vtu", "quality", "past the end of the appended data"),
    ("vtu_zlib_zero_size_block.vtu", "quality", "corrupt zlib block"),
    ("vtu_faces_len_int64max_ascii.vtu", "quality", "'faces' is malformed"),
    ("vtu_faces_len_int64max_raw.vtu", "quality", "'faces' is malformed"),
    ("vtu_npoints_overflow.vtu", "quality", "beyond what a file can hold"),
    # OpenMesh's .om reader added an edge per announced edge (2.7 GB, 15 s)
    # and aborts on malformed chunks: .om is not read.
    ("om_edge_count_huge.om", "info", "unsupported file extension '.om'"),
]


def expect_one_line(argv, path, needle, what):
    t0 = time.monotonic()
    rc, out, err = e2eutil.run(argv, timeout=60)
    dt = time.monotonic() - t0
    lines = err.strip().splitlines()
    check(rc == 1, "%s: exit %d (expected 1), stderr %r" % (what, rc, err[:400]))
    check(len(lines) == 1, "%s: %d stderr lines (expected 1): %r" % (what, len(lines), err[:400]))
    if lines:
        head = "vorocrust: %s" % path
        check(lines[0].startswith(head + ": ") or re.match(re.escape(head) + r":\d+: ", lines[0]),
              "%s: the line does not start with '%s: ': %r" % (what, head, lines[0]))
        check(needle in lines[0], "%s: %r not in %r" % (what, needle, lines[0]))
        check(all(c >= " " and c != "\x7f" for c in lines[0]),
              "%s: control characters in %r" % (what, lines[0]))
    check("runtime error" not in err and "Sanitizer" not in err, "%s: sanitizer report %r" % (what, err[:400]))
    check(dt < LIMIT, "%s: %.2f s (limit %.0f s)" % (what, dt, LIMIT))


for name, cmd, needle in REPRODUCERS:
    path = os.path.join(REPRO, name)
    expect_one_line([BIN, cmd, path], path, needle, name)


def write(name, data):
    path = os.path.join(TMP, name)
    with open(path, "wb") as f:
        f.write(data if isinstance(data, bytes) else data.encode())
    return path


TET_OBJ = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\n"
TET_OFF_BODY = "0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n"

# Strict parsing: the real problem, the real value.
CASES = [
    ("frac.obj", TET_OBJ + "f 2.7 3 4\n", "line 5: malformed face index"),
    ("relative.obj", TET_OBJ + "f -5 1 2\n", "relative face index -5 refers before the first vertex"),
    ("zero.obj", TET_OBJ + "f 0 1 2\n", "face index 0"),
    ("surplus.off", "OFF\n4 3 0\n" + TET_OFF_BODY, "data after the 3 faces the header announces"),
    ("fracidx.off", "OFF\n4 4 0\n" + TET_OFF_BODY.replace("3 1 2 3", "3 1 2.5 3"), "fewer than the 3 integer"),
    ("bigcounts.off", "OFF\n4000000000 4 0\n" + TET_OFF_BODY, "file ends after 8 of 4000000000 vertices"),
    ("surplus.ply", "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
     "property float z\nelement face 3\nproperty list uchar int vertex_indices\nend_header\n"
     + TET_OFF_BODY, "data after the last element"),
    ("ctrl.ply", "ply\nformat ascii\x01\x1b[31m 1.0\n", "unknown PLY format 'ascii\\x01\\x1b[31m'"),
    ("noprops.ply", "ply\nformat binary_little_endian 1.0\nelement junk 1000000000000\nend_header\n",
     "has 1000000000000 rows but no properties"),
    ("solidbad.stl", b"solid binary header" + b"\0" * 61 + struct.pack("<I", 5) + b"\0" * 100,
     "malformed binary STL: the header announces 5 triangles (334 bytes) but the file has 184 bytes"),
    ("binbad.off", b"OFF BINARY\n" + struct.pack("<III", 100000000, 1, 0) + b"\0" * 40,
     "binary OFF: the header announces 100000000 vertices"),
]
for name, data, needle in CASES:
    path = write(name, data)
    expect_one_line([BIN, "info", path], path, needle, name)

# A binary STL whose header starts with "solid" and whose size matches is binary.
tri = struct.pack("<3f", 0, 0, 0)
facets = [((0, 0, 0), (0, 1, 0), (1, 0, 0)), ((0, 0, 0), (1, 0, 0), (0, 0, 1)),
          ((0, 0, 0), (0, 0, 1), (0, 1, 0)), ((1, 0, 0), (0, 1, 0), (0, 0, 1))]
body = b"".join(tri + b"".join(struct.pack("<3f", *v) for v in f) + b"\0\0" for f in facets)
path = write("solid_binary.stl", b"solid but binary".ljust(80, b" ") + struct.pack("<I", 4) + body)
rc, out, err = e2eutil.run([BIN, "info", path], timeout=60)
check(rc == 0 and "triangles: 4" in out, "solid_binary.stl: exit %d, %r %r" % (rc, out[:300], err[:300]))

# A binary OFF that is right (the layout OpenMesh writes) is read.
verts = [(0, 0, 0), (1, 0, 0), (0, 1, 0), (0, 0, 1)]
faces = [(0, 2, 1), (0, 1, 3), (0, 3, 2), (1, 2, 3)]
data = b"OFF BINARY\n" + struct.pack("<III", 4, 4, 0) + b"".join(struct.pack("<3f", *v) for v in verts) \
    + b"".join(struct.pack("<4I", 3, *f) for f in faces)
path = write("good_binary.off", data)
rc, out, err = e2eutil.run([BIN, "info", path], timeout=60)
check(rc == 0 and "triangles: 4" in out, "good_binary.off: exit %d, %r %r" % (rc, out[:300], err[:300]))

# .om is not read (OpenMesh's reader trusts the header's counts and aborts on
# a malformed chunk; no reader of ours validates it first): a good .om
# tetrahedron as OpenMesh 9.0 writes it, and its header alone, are refused.
TET_OM = bytes.fromhex(
    "4f4d544204000000040000000600000000160000000000000000000000000000803f0000000000000000"
    "000000000000803f0000000000000000000000000000803ff8160202000900020401000b020300000006"
    "01010803010301030500010a0302010202070303e00609030b07e806040801071c00")
for name, data in (("tet.om", TET_OM), ("short.om", b"OMTB\x04\0\0\0")):
    path = write(name, data)
    expect_one_line([BIN, "info", path], path, "unsupported file extension '.om' (expected .obj, "
                    ".off, .stl or .ply)", name)

# A directory given as input.
d = os.path.join(TMP, "adir.obj")
os.makedirs(d, exist_ok=True)
expect_one_line([BIN, "info", d], d, "is a directory", "directory .obj")
d2 = os.path.join(TMP, "adir.vtu")
os.makedirs(d2, exist_ok=True)
expect_one_line([BIN, "quality", d2], d2, "is a directory", "directory .vtu")

# Seeds CSV: control characters escaped, a directory named.
path = write("ctrl.csv", "x,y,z\n0,0,0\n1,\x1b[2J,0\n")
out_vtu = os.path.join(TMP, "ctrl.vtu")
expect_one_line([BIN, "voronoi", path, "-o", out_vtu], path, "field 2 \"\\x1b[2J\" is not a number",
                "ctrl.csv")
# .vtu: bytes of the file quoted in a message are escaped as \xNN like in the
# other readers (control characters, DEL and bytes >= 0x80), not shown as '?';
# a control character in the file name too (its UTF-8 kept).
VTU_HEAD = '<?xml version="1.0"?>\n<VTKFile type="UnstructuredGrid" version="1.0" byte_order="%s">\n'
for name, order, needle in (
        ("ctrl.vtu", "Big\x1b[2J\x7fEndian", "byte_order 'Big\\x1b[2J\\x7fEndian' is not supported"),
        ("high.vtu", "Big\xe9Endian", "byte_order 'Big\\xc3\\xa9Endian' is not supported")):
    path = write(name, (VTU_HEAD % order).encode())
    expect_one_line([BIN, "quality", path], path, needle, name)
path = write("ctrl\x01name\u00e9.vtu", (VTU_HEAD % "BigEndian").encode())
shown = path.replace("\x01", "\\x01")
rc, out, err = e2eutil.run([BIN, "quality", path], timeout=60)
check(rc == 1 and err.strip().splitlines() == ["vorocrust: %s: byte_order 'BigEndian' is not supported "
                                               "(LittleEndian only)" % shown],
      "vtu name with a control byte: exit %d, %r (expected the name shown as %r)" % (rc, err, shown))
d3 = os.path.join(TMP, "adir.csv")
os.makedirs(d3, exist_ok=True)
expect_one_line([BIN, "voronoi", d3, "-o", out_vtu], d3, "is a directory", "directory .csv")

if failures:
    print("%d failure(s)" % len(failures), file=sys.stderr)
    sys.exit(1)
print("e2e_repro: %d reproducers, %d malformed files: OK" % (len(REPRODUCERS), len(CASES)))
