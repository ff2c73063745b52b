"""End-to-end tests of `vorocrust compare` (vorocrust mesh against vc-tetgen).

  (a) models/icosphere.obj with -o report.html and --mesh-dir: the table's
      vertex and cell counts and total volumes agree with VTK 9.1 reading
      the two kept meshes (vtkCellSizeFilter volumes; vtkMassProperties for
      the polyhedra it under-measures); TetGen's target is vorocrust's cell
      count and its count lands near it; the volume error, fatness,
      shortest edge, triangle quality and angle rows are what `vorocrust
      quality --input` prints for the same meshes; TetGen's boundary is the
      input (Hausdorff ~ 0), vorocrust's within 1% of the diagonal; time and
      memory are positive; the HTML report parses (html.parser) and holds
      the same table and two SVG histograms whose bar counts add up to the
      measured cells and boundary triangles of each mesher; no script and no
      external resource;
  (b) a surface vorocrust refuses (one triangle flipped): exit 1, one
      stderr line naming the failure, the vorocrust column marked failed,
      TetGen still measured (quality bound only: no target), the report
      still written and saying so;
  (c) the reference sphere.obj (VC_MODELS), when present: counts and volumes
      against VTK;
  (d) SIGTERM or SIGINT sent to compare alone while vc-tetgen runs: the
      child is stopped with it, the work directory (TMPDIR) and the report
      are removed, compare dies by the signal;
  and bad input: exit 1 (2 for usage), one stderr line naming the problem.

Environment: VC_BIN, VC_TETGEN (vc-tetgen must sit next to VC_BIN), VC_SOURCE,
VC_MODELS, VC_TMP.
"""
import html.parser
import math
import os
import re
import shutil
import signal
import subprocess
import sys
import time

sys.path.insert(0, os.path.join(os.environ["VC_SOURCE"], "tests"))
import vtk  # noqa: E402
import e2eutil  # noqa: E402
import vtkcheck  # noqa: E402
from e2eutil import check, failures  # noqa: E402

BIN = os.environ["VC_BIN"]
SOURCE = os.environ["VC_SOURCE"]
MODELS = os.environ.get("VC_MODELS", "")
TMP = os.path.join(os.environ.get("VC_TMP", "/tmp"), "e2e_compare")
shutil.rmtree(TMP, ignore_errors=True)
os.makedirs(TMP)

if os.path.dirname(os.environ.get("VC_TETGEN", "")) != os.path.dirname(BIN):
    print("FAIL: vc-tetgen (VC_TETGEN=%r) is not built next to %s" % (os.environ.get("VC_TETGEN"), BIN),
          file=sys.stderr)
    sys.exit(1)


def close(a, b, rel):
    return abs(a - b) <= rel * max(abs(a), abs(b), 1e-300)


def path(*names):
    return os.path.join(TMP, *names)


def run(*args):
    return e2eutil.run([BIN, *args], timeout=900)


def parse_table(out):
    """The table rows as {name: [vorocrust, tetgen]} (strings), and the
    other 'key: value' lines."""
    rows, other = {}, {}
    for line in out.splitlines():
        m = re.match(r"^(\S.*?)\s{2,}(\S+)\s{2,}(\S+)$", line)
        if m and not line.startswith(("compare:", "command ", "tetgen target", "failed ", "metric ")):
            rows[m.group(1)] = [m.group(2), m.group(3)]
        else:
            key, _, val = line.partition(": ")
            other[key] = val
    return rows, other


def quality(mesh, surface):
    rc, so, se = run("quality", mesh, "--input", surface)
    check(rc == 0, "quality %s: exit %d %r" % (mesh, rc, se))
    rep = {}
    for line in so.splitlines():
        key, _, val = line.partition(": ")
        rep[key] = val
    return rep


def stat(rep, key, which):
    m = re.search(r"\b%s (\S+?)(,|$)" % which, rep.get(key, ""))
    return m.group(1) if m else None


def reference_volumes(grid):
    """vtkCellSizeFilter's volumes, vtkMassProperties where it loses volume on
    a polyhedron (see e2e_quality)."""
    vols = [abs(v) for v in vtkcheck.vtk_volumes(grid)]
    for c in range(len(vols)):
        if grid.GetCellType(c) == 42:
            mp = vtkcheck.cell_mass_volume(grid, c)
            if abs(vols[c] - mp) > 1e-6 * mp:
                vols[c] = mp
    return vols


def enclosed_volume_obj(fname):
    verts, vol = [], []
    with open(fname) as fh:
        for line in fh:
            w = line.split()
            if w and w[0] == "v":
                verts.append([float(x) for x in w[1:4]])
            elif w and w[0] == "f":
                a, b, c = (verts[int(x.split("/")[0]) - 1] for x in w[1:4])
                vol.append(a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0])
                           + a[2] * (b[0] * c[1] - b[1] * c[0]))
    return math.fsum(vol) / 6.0


def check_against_vtk(name, rows, mesh_dir, input_volume):
    """Counts and volumes of the table against VTK reading the kept meshes."""
    for col, mesher in enumerate(("vorocrust", "tetgen")):
        try:
            grid = vtkcheck.read_vtu(os.path.join(mesh_dir, mesher + ".vtu"))
        except vtkcheck.CheckError as e:
            check(False, "%s: %s" % (name, e))
            continue
        check(int(rows["cells"][col]) == grid.GetNumberOfCells(),
              "%s %s: %s cells in the table, VTK reads %d" % (name, mesher, rows["cells"][col], grid.GetNumberOfCells()))
        check(int(rows["vertices"][col]) == grid.GetNumberOfPoints(),
              "%s %s: %s vertices in the table, VTK reads %d" % (name, mesher, rows["vertices"][col], grid.GetNumberOfPoints()))
        vols = reference_volumes(grid)
        total = math.fsum(vols)
        check(close(float(rows["total volume"][col]), total, 1e-8),
              "%s %s: total volume %s in the table, VTK %.12g" % (name, mesher, rows["total volume"][col], total))
        err = 100.0 * (total - input_volume) / input_volume
        # printed with 3 significant digits
        check(abs(float(rows["volume error (%)"][col]) - err) <= 5e-3 * abs(err) + 1e-9,
              "%s %s: volume error %s%% in the table, %.6g%% from VTK" % (name, mesher, rows["volume error (%)"][col], err))
        if mesher == "tetgen":
            check(grid.GetCellType(0) == vtk.VTK_TETRA, "%s: tetgen cells are not tetrahedra" % name)
            check(close(total, input_volume, 1e-8), "%s: tetgen volume %.15g, input %.15g" % (name, total, input_volume))


class ReportParser(html.parser.HTMLParser):
    """Collects the table cells, the SVG elements and every bar."""

    def __init__(self):
        super().__init__()
        self.svgs, self.bars, self.table, self.tags = [], [], [], set()
        self.lines = {}  # svg id -> its <line> elements
        self.current_svg = None
        self.in_td = False
        self.row = None
        self.text = ""

    def handle_starttag(self, tag, attrs):
        a = dict(attrs)
        self.tags.add(tag)
        if tag == "svg":
            self.current_svg = a.get("id")
            self.svgs.append(self.current_svg)
        elif tag == "line" and self.current_svg:
            self.lines[self.current_svg] = self.lines.get(self.current_svg, 0) + 1
        elif tag == "rect" and a.get("class") == "bar":
            self.bars.append((self.current_svg, a["data-mesher"], int(a["data-count"])))
        elif tag == "tr":
            self.row = []
        elif tag == "td":
            self.in_td, self.text = True, ""
        for k, v in attrs:
            if k in ("src", "href") or (v and re.match(r"(https?:)?//", v) and k != "xmlns"):
                self.tags.add("external:" + k)

    def handle_endtag(self, tag):
        if tag == "svg":
            self.current_svg = None
        elif tag == "td":
            self.in_td = False
            self.row.append(self.text.strip())
        elif tag == "tr" and self.row:
            self.table.append(self.row)
            self.row = None

    def handle_data(self, data):
        if self.in_td:
            self.text += data


def check_report(name, report, rows, measured_cells, triangles, failed=()):
    if not check(os.path.isfile(report), "%s: no report %s" % (name, report)):
        return None
    with open(report, encoding="utf-8") as fh:
        text = fh.read()
    p = ReportParser()
    p.feed(text)
    p.close()
    check(p.svgs == ["cut-vorocrust", "cut-tetgen", "fatness-histogram", "quality-histogram"],
          "%s: SVG elements %r" % (name, p.svgs))
    # the cut through each mesh: segments for a mesher that succeeded, none otherwise
    for mesher in ("vorocrust", "tetgen"):
        n = p.lines.get("cut-" + mesher, 0)
        check(n == 0 if mesher in failed else n > 100, "%s: %d segments in %s's cut" % (name, n, mesher))
    # the run: date, version, threads; no path of the removed temporary directory
    check(re.search(r"<p>Run \d{4}-\d\d-\d\d \d\d:\d\d UTC: vorocrust \d+\.\d+\.\d+ with \d+ threads?", text),
          "%s: the report does not say when, which version and how many threads" % name)
    check("vc-compare." not in text, "%s: the report names the removed temporary directory" % name)
    check("script" not in p.tags and "link" not in p.tags and not any(t.startswith("external:") for t in p.tags),
          "%s: the report is not self-contained: %r" % (name, sorted(p.tags)))
    table = {r[0]: r[1:] for r in p.table}
    check(table == rows, "%s: the HTML table differs from the printed one:\n%r\n%r" % (name, table, rows))
    for svg, expected in (("fatness-histogram", measured_cells), ("quality-histogram", triangles)):
        for col, mesher in enumerate(("vorocrust", "tetgen")):
            total = sum(n for s, m, n in p.bars if s == svg and m == mesher)
            if mesher in failed:
                check(total == 0 and not [b for b in p.bars if b[0] == svg and b[1] == mesher],
                      "%s: %s failed but has bars in %s" % (name, mesher, svg))
            else:
                check(total == expected[col], "%s: %s bars in %s count %d, expected %d"
                      % (name, mesher, svg, total, expected[col]))
    check(not [f for f in os.listdir(os.path.dirname(report)) if ".tmp." in f], "%s: temporary file left" % name)
    return text


# (a) the bundled icosphere
ico = os.path.join(SOURCE, "models", "icosphere.obj")
ico_volume = enclosed_volume_obj(ico)
mesh_dir = path("ico")
os.makedirs(mesh_dir)
report = path("ico.html")
rc, so, se = run("compare", ico, "-o", report, "--mesh-dir", mesh_dir, "--threads", "2", "--seed", "3")
if check(rc == 0, "icosphere: exit %d, stderr %r" % (rc, se)):
    rows, other = parse_table(so)
    names = ["time (s)", "cpu time (s)", "peak memory (MiB)", "vertices", "cells", "faces", "boundary faces",
             "total volume", "volume error (%)", "fatness max", "fatness mean", "fatness p99",
             "shortest relative edge min", "non-orthogonality max (deg)", "non-orthogonality average (deg)",
             "skewness max", "faces with skewness > 4", "surface triangles", "surface Q min", "surface Q mean",
             "angles < 30 deg (%)", "angles > 90 deg (%)", "hausdorff / diagonal"]
    check(list(rows) == names, "icosphere: table rows %r" % list(rows))
    check(close(float(other["compare"].split("enclosed volume ")[1].split(",")[0]), ico_volume, 1e-9),
          "icosphere: header %r" % other.get("compare"))
    check_against_vtk("icosphere", rows, mesh_dir, ico_volume)
    for r in ("time (s)", "cpu time (s)", "peak memory (MiB)"):
        check(all(float(v) > 0 for v in rows[r]), "icosphere: %s %r" % (r, rows[r]))
    vc_cells, tet_cells = int(rows["cells"][0]), int(rows["cells"][1])
    check(other.get("tetgen target cells", "").startswith("%d (" % vc_cells),
          "icosphere: tetgen target %r, vorocrust made %d cells" % (other.get("tetgen target cells"), vc_cells))
    check(0.75 * vc_cells <= tet_cells <= 1.33 * vc_cells,
          "icosphere: tetgen %d cells for vorocrust's %d" % (tet_cells, vc_cells))
    check("--seed 3" in other.get("command vorocrust", "") and "--threads 2" in other.get("command vorocrust", ""),
          "icosphere: vorocrust command %r" % other.get("command vorocrust"))
    check("--max-volume" in other.get("command tetgen", ""), "icosphere: tetgen command %r" % other.get("command tetgen"))
    # the same figures as `vorocrust quality --input` on the kept meshes
    measured, triangles = [], []
    for col, mesher in enumerate(("vorocrust", "tetgen")):
        rep = quality(os.path.join(mesh_dir, mesher + ".vtu"), ico)
        for row, key, which in (("fatness max", "fatness", "max"), ("fatness mean", "fatness", "mean"),
                                ("fatness p99", "fatness", "p99"),
                                ("shortest relative edge min", "shortest relative edge", "min"),
                                ("surface Q min", "triangle quality", "min"),
                                ("surface Q mean", "triangle quality", "mean")):
            check(stat(rep, key, which) is not None and float(stat(rep, key, which)) == float(rows[row][col]),
                  "icosphere %s: %s %s in the table, quality says %r" % (mesher, row, rows[row][col], stat(rep, key, which)))
        check(rows["faces"][col] == rep["faces"].split()[0] and rows["boundary faces"][col] == rep["faces"].split("(")[1].split()[0],
              "icosphere %s: faces %r / %r, quality: %r" % (mesher, rows["faces"][col], rows["boundary faces"][col], rep["faces"]))
        check(rows["surface triangles"][col] == rep["boundary triangles"],
              "icosphere %s: triangles %r, quality %r" % (mesher, rows["surface triangles"][col], rep["boundary triangles"]))
        for row, key in (("angles < 30 deg (%)", "angles below 30 degrees"), ("angles > 90 deg (%)", "angles above 90 degrees")):
            check(abs(float(rows[row][col]) - float(rep[key].rstrip("%"))) <= 0.006,
                  "icosphere %s: %s %s, quality %r" % (mesher, row, rows[row][col], rep[key]))
        # checkMesh's measures, as vorocrust quality prints them
        cm = re.match(r"non-orthogonality max ([\d.e+-]+) average ([\d.e+-]+) degrees, skewness max "
                      r"([\d.e+-]+) \((\d+) faces above 4\)", rep.get("checkMesh measures", ""))
        if check(cm, "icosphere %s: quality prints no checkMesh measures: %r" % (mesher, rep.get("checkMesh measures"))):
            for k, row in enumerate(("non-orthogonality max (deg)", "non-orthogonality average (deg)",
                                     "skewness max", "faces with skewness > 4")):
                check(close(float(rows[row][col]), float(cm.group(k + 1)), 1e-3),
                      "icosphere %s: %s %s, quality %s" % (mesher, row, rows[row][col], cm.group(k + 1)))
        hd = float(rep["hausdorff distance"].split(": ")[1].rstrip(")"))
        check(close(float(rows["hausdorff / diagonal"][col]), hd, 1e-3) or hd < 1e-12,
              "icosphere %s: hausdorff %s, quality %r" % (mesher, rows["hausdorff / diagonal"][col], hd))
        unmeasured = int(rep["unmeasured cells"].split()[0]) if "unmeasured cells" in rep else 0
        measured.append(int(rows["cells"][col]) - unmeasured)
        triangles.append(int(rows["surface triangles"][col]))
    check(float(rows["hausdorff / diagonal"][1]) < 1e-12, "icosphere: tetgen boundary off the input: %r" % rows["hausdorff / diagonal"])
    check(0 < float(rows["hausdorff / diagonal"][0]) < 0.01, "icosphere: vorocrust hausdorff %r" % rows["hausdorff / diagonal"])
    check(float(rows["fatness max"][1]) >= 3 - 1e-9 and float(rows["fatness mean"][0]) >= math.sqrt(3) - 1e-9,
          "icosphere: fatness below its bounds %r %r" % (rows["fatness max"], rows["fatness mean"]))
    text = check_report("icosphere", report, rows, measured, triangles)
    check(text is not None and "its phases (s): read " in text, "icosphere: the report lacks vorocrust's phase times")
    check(sorted(os.listdir(mesh_dir)) == ["tetgen-bound.log", "tetgen.log", "tetgen.vtu", "vorocrust.log",
                                           "vorocrust.vtu", "vorocrust_boundary.vtu"],
          "icosphere: mesh dir holds %r" % sorted(os.listdir(mesh_dir)))

# (b) an inconsistently oriented surface: vorocrust reverses the flipped
# triangle (a warning in its log) and both mesh it
def with_first_face(dst_path, first_face_lines):
    """The icosphere with its first face replaced by first_face_lines(w)."""
    with open(ico) as src, open(dst_path, "w") as dst:
        done = False
        for line in src:
            w = line.split()
            if w and w[0] == "f" and not done:
                line = first_face_lines(w)
                done = True
            dst.write(line)


flipped = path("flipped.obj")
with_first_face(flipped, lambda w: "f %s %s %s\n" % (w[1], w[3], w[2]))
flipped_dir = path("flipped")
os.makedirs(flipped_dir)
rc, so, se = run("compare", flipped, "--mesh-dir", flipped_dir, "--quiet")
check(rc == 0, "flipped: exit %d, expected 0 (stderr %r)" % (rc, se))
with open(os.path.join(flipped_dir, "vorocrust.log")) as f:
    log = f.read()
check("1 triangles reversed" in log, "flipped: vorocrust's log does not say it reversed the triangle: %r" % log[:500])

# (b2) a triangle given twice: both meshers refuse it; the table and the
# report say so for each
dup = path("repeated.obj")
with_first_face(dup, lambda w: (" ".join(w) + "\n") * 2)
report = path("repeated.html")
rc, so, se = run("compare", dup, "-o", report, "--quiet")
check(rc == 1, "repeated: exit %d, expected 1 (stderr %r)" % (rc, se))
lines = se.strip().splitlines()
check(len(lines) == 2 and re.match(r"vorocrust: compare: .*repeated\.obj: vorocrust failed: exit 1: vorocrust: .*repeated\.obj: .*repeat",
                                   lines[0] if lines else "") and "tetgen failed" in lines[-1], "repeated: stderr %r" % se)
rows, other = parse_table(so)
if check("cells" in rows, "repeated: no table in %r" % so):
    check(rows["cells"] == ["failed", "failed"] and rows["fatness max"][0] == "failed", "repeated: cells %r" % rows["cells"])
    check(float(rows["time (s)"][0]) > 0, "repeated: the failed run's time %r" % rows["time (s)"])
    check("--max-volume" not in other.get("command tetgen", "x") and "tetgen target cells" not in other,
          "repeated: tetgen should run with its quality bound only: %r" % other.get("command tetgen"))
    text = check_report("repeated", report, rows, [0, 0], [0, 0], failed=("vorocrust", "tetgen"))
    check(text is not None and "vorocrust failed:" in text and "tetgen failed:" in text,
          "repeated: the report does not name the failures")

# (c) the reference sphere
sphere = os.path.join(MODELS, "sphere.obj")
if not os.path.isfile(sphere):
    print("(c) skipped: %s not found (the shared reference models directory is missing)" % sphere)
else:
    mesh_dir = path("sphere")
    os.makedirs(mesh_dir)
    rc, so, se = run("compare", sphere, "--mesh-dir", mesh_dir, "--quiet")
    if check(rc == 0, "sphere.obj: exit %d, stderr %r" % (rc, se)):
        rows, other = parse_table(so)
        check_against_vtk("sphere.obj", rows, mesh_dir, enclosed_volume_obj(sphere))


# bad input
def bad(name, args, code, pattern):
    rc, so, se = run("compare", *args)
    lines = se.strip().splitlines()
    check(rc == code, "%s: exit %d, expected %d (stderr %r)" % (name, rc, code, se))
    check(len(lines) == 1 and lines[0].startswith("vorocrust: ") and re.search(pattern, lines[0]),
          "%s: stderr %r does not match %r in one line" % (name, se, pattern))
    check(not os.path.exists(path("bad.html")), "%s: a report was written" % name)


open_obj = path("open.obj")
with open(open_obj, "w") as fh:
    fh.write("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\n")
bad("missing input", [path("nope.obj"), "-o", path("bad.html")], 1, r"nope\.obj: cannot open")
bad("open surface", [open_obj, "-o", path("bad.html")], 1, r"open\.obj: 3 open boundary edges")
bad("report directory missing", [ico, "-o", path("nodir", "bad.html")], 1, r"nodir/bad\.html: cannot write")
bad("mesh dir missing", [ico, "--mesh-dir", path("nodir")], 1, r"--mesh-dir .*nodir: not a writable directory")
bad("no input", [], 2, r"missing the INPUT")
bad("unknown option", [ico, "--frobnicate"], 2, r"unknown option '--frobnicate'")
bad("threads 0", [ico, "--threads", "0"], 2, r"--threads: '0'")
bad("target 0", [ico, "--target-cells", "0"], 2, r"--target-cells: '0'")
bad("seed without value", [ico, "--seed"], 2, r"--seed needs a value")
bad("two inputs", [ico, ico], 2, r"unexpected argument")


# (d) a signal sent to compare alone (kill PID, not the process group) while
# a mesher runs: compare sends it on to the child and waits for it, then
# removes its work directory and the report, and dies by that signal. The
# child is vc-tetgen searching the volume bound of a large target (tens of
# seconds): it must be gone when compare is, and TMPDIR left empty.
def children(pid):
    try:
        with open("/proc/%d/task/%d/children" % (pid, pid)) as fh:
            return [int(c) for c in fh.read().split()]
    except OSError:
        return []


def cmdline(pid):
    try:
        with open("/proc/%d/cmdline" % pid, "rb") as fh:
            return fh.read().replace(b"\0", b" ").decode(errors="replace")
    except OSError:
        return ""


def alive(pid):
    try:
        with open("/proc/%d/stat" % pid) as fh:
            return fh.read().rsplit(")", 1)[1].split()[0] != "Z"
    except OSError:
        return False


for sig in (signal.SIGTERM, signal.SIGINT):
    name = "compare killed by %s" % sig.name
    tmpdir = path("tmpdir-%s" % sig.name)
    os.makedirs(tmpdir)
    report = path("killed-%s.html" % sig.name)
    env = dict(os.environ, TMPDIR=tmpdir)
    p = subprocess.Popen([BIN, "compare", ico, "-o", report, "--target-cells", "1000000", "--threads", "1",
                          "--quiet"], stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, env=env,
                         start_new_session=True)  # a terminal's Ctrl-C would reach the child itself
    child = None
    t0 = time.time()
    while p.poll() is None and time.time() - t0 < 120 and child is None:
        for c in children(p.pid):
            if "vc-tetgen" in cmdline(c):
                child = c
        time.sleep(0.01)
    if check(child is not None, "%s: vc-tetgen never ran (exit %s)" % (name, p.returncode)):
        time.sleep(0.3)  # well inside its run
        p.send_signal(sig)
        try:
            p.wait(timeout=30)
        except subprocess.TimeoutExpired:
            p.kill()
            p.wait()
        err = p.stderr.read().decode(errors="replace")
        check(p.returncode == -sig, "%s: exit %s, expected death by the signal (%s)" % (name, p.returncode, err[-300:]))
        left_running = alive(child)
        check(not left_running, "%s: its child %d (%s) still runs" % (name, child, cmdline(child)[:200]))
        if left_running:
            os.kill(child, signal.SIGKILL)
        check(os.listdir(tmpdir) == [], "%s: TMPDIR holds %r" % (name, os.listdir(tmpdir)))
        check(not os.path.exists(report), "%s: the report was written" % name)
        if not left_running:
            print("%s: child %d stopped with it, %.1f s" % (name, child, time.time() - t0))
    else:
        p.kill()
        p.wait()
    p.stderr.close()

if failures:
    print("%d failure(s)" % len(failures), file=sys.stderr)
    sys.exit(1)
print("e2e_compare: all checks passed")
