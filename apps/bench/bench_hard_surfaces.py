#!/usr/bin/python3
"""Sweep of `vorocrust mesh` over hard test surfaces (issue 16): the
surfaces of models/make_hard_surfaces.py and the shared models.

usage: /usr/bin/python3 apps/bench/bench_hard_surfaces.py --bin build/gen/vorocrust
           [--surfaces DIR] [--models DIR ...] [--timeout 120] [--threads N]
           [--max-memory-gb 8] [--only NAME ...] [--keep DIR]
(--keep DIR: the outputs and each run's stderr, NAME.log, stay in DIR)

Generates the hard surfaces into a temporary directory (or takes them from
--surfaces DIR), then runs, with default options, one process per input,
    vorocrust mesh F -o F.vtu --surface F.obj --threads N
on each generated surface and on every model of the --models directories
(default ../shared/models when present), killed after --timeout seconds or
when its resident memory exceeds --max-memory-gb. One table row per input
(Markdown):
  triangles   of the input
  exit        the exit code, "timeout" or "memory"
  wall        seconds
  peak MiB    the high-water mark of the run's resident memory (VmHWM in
              /proc, read every 50 ms)
  balls       from the summary ("balls: N")
  resampled   yes when the summary says "after sampling at A diverged" or
              the kept sampling ran after N > 0 smoothing rounds
  sharp       the sharp angle of the kept sampling
  euler       the reconstructed surface's Euler characteristic against the
              input's, "ok" when equal and the surface is a closed,
              consistently oriented 2-manifold
  hausdorff   two-sided Hausdorff distance between the reconstructed
              surface and the INPUT, % of the input's bounding-box diagonal:
              points sampled densely on both surfaces (vertices, edges and
              triangle interiors, vtkPolyDataPointSampler, about 150k per
              surface), closest points on the other surface (vtkStaticCellLocator)
  volume      enclosed volume of the reconstructed surface against the
              input's (vtkMassProperties), %
  Q min       surface quality from the summary
  note        what failed and how: the last progress line before a
              timeout (the phase it hung in), the error line, "resampled"
The last line counts the inputs meshed with defaults (exit 0) without
resampling, within 0.5 % Hausdorff and 0.5 % volume.
Needs Debian's VTK 9 for /usr/bin/python3 (python3-vtk9)."""
import argparse
import math
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time

try:
    import vtk
except ImportError:  # e.g. a pyenv python3 first on PATH: use Debian's
    if os.path.realpath(sys.executable) != os.path.realpath("/usr/bin/python3") and \
            os.path.exists("/usr/bin/python3"):
        os.execv("/usr/bin/python3", ["/usr/bin/python3"] + sys.argv)
    raise

vtk.vtkObject.GlobalWarningDisplayOff()

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, os.path.join(ROOT, "tests"))
from surfacecheck import hausdorff_sampled  # noqa: E402  (the tests' measure, the same here)
SUFFIXES = (".obj", ".off", ".stl", ".ply")


# ---------------------------------------------------------------- surfaces

def read_surface(path):
    """A triangle vtkPolyData of an OBJ/OFF/STL/PLY file (polygons fanned)."""
    ext = os.path.splitext(path)[1].lower()
    if ext in (".stl", ".ply"):
        r = vtk.vtkSTLReader() if ext == ".stl" else vtk.vtkPLYReader()
        r.SetFileName(path)
        r.Update()
        pd = r.GetOutput()
    else:
        pts, faces = [], []
        with open(path) as f:
            if ext == ".obj":
                for line in f:
                    w = line.split()
                    if not w:
                        continue
                    if w[0] == "v":
                        pts.append(tuple(float(x) for x in w[1:4]))
                    elif w[0] == "f":
                        ids = [int(x.split("/")[0]) for x in w[1:]]
                        faces.append([i - 1 if i > 0 else len(pts) + i for i in ids])
            else:  # OFF
                words = []
                for line in f:
                    line = line.split("#")[0]
                    words += line.split()
                if words[0].upper().endswith("OFF"):
                    words = words[1:]
                nv, nf = int(words[0]), int(words[1])
                k = 3
                for _ in range(nv):
                    pts.append(tuple(float(x) for x in words[k:k + 3]))
                    k += 3
                for _ in range(nf):
                    n = int(words[k])
                    faces.append([int(x) for x in words[k + 1:k + 1 + n]])
                    k += 1 + n
        p = vtk.vtkPoints()
        p.SetDataTypeToDouble()
        for x in pts:
            p.InsertNextPoint(*x)
        cells = vtk.vtkCellArray()
        for fc in faces:
            for i in range(1, len(fc) - 1):
                cells.InsertNextCell(3)
                cells.InsertCellPoint(fc[0])
                cells.InsertCellPoint(fc[i])
                cells.InsertCellPoint(fc[i + 1])
        pd = vtk.vtkPolyData()
        pd.SetPoints(p)
        pd.SetPolys(cells)
    tf = vtk.vtkTriangleFilter()
    tf.SetInputData(pd)
    tf.Update()
    return tf.GetOutput()


def diagonal(pd):
    b = pd.GetBounds()
    return math.sqrt(sum((b[2 * i + 1] - b[2 * i]) ** 2 for i in range(3)))


def volume(pd):
    """Signed enclosed volume (sum over triangles of p0 . (p1 x p2) / 6,
    about the bounding-box centre)."""
    mp = vtk.vtkMassProperties()
    mp.SetInputData(pd)
    mp.Update()
    return mp.GetVolume()


def hausdorff(a, b, n_target=150000):
    return hausdorff_sampled(a, b, n_target)


# ---------------------------------------------------------------- runs

def rss_mib(pid):
    """(resident, high-water mark) MiB of a running process. Not wait4's
    ru_maxrss: that counts the pages of this (large) Python process the
    child shared between fork and exec."""
    rss = hwm = 0.0
    try:
        with open("/proc/%d/status" % pid) as f:
            for line in f:
                if line.startswith("VmRSS:"):
                    rss = int(line.split()[1]) / 1024.0
                elif line.startswith("VmHWM:"):
                    hwm = int(line.split()[1]) / 1024.0
    except OSError:
        pass
    return rss, hwm


def run(cmd, timeout, max_mib):
    """(exit code | 'timeout' | 'memory', stderr text, wall s, peak MiB: the
    last VmHWM seen, every 50 ms; the summary's "peak memory" is getrusage's
    ru_maxrss, which keeps the pages of this Python process across exec)."""
    with tempfile.TemporaryFile(mode="w+") as err:
        t0 = time.monotonic()
        p = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=err)
        peak, why = 0.0, None
        while True:
            pid, status, ru = os.wait4(p.pid, os.WNOHANG)
            if pid == p.pid:
                break
            rss, hwm = rss_mib(p.pid)
            peak = max(peak, hwm)
            if time.monotonic() - t0 > timeout:
                why = "timeout"
            elif rss > max_mib:
                why = "memory"
            if why:
                p.kill()
                _, status, ru = os.wait4(p.pid, 0)
                break
            time.sleep(0.05)
        wall = time.monotonic() - t0
        p.returncode = os.waitstatus_to_exitcode(status)
        err.seek(0)
        return (why or p.returncode), err.read(), wall, peak


def summary(err):
    f = {}
    m = re.search(r"vorocrust mesh: .* \((\d+) triangles, (\d+) after (\d+) smoothing rounds; "
                  r"sharp angle ([0-9.eE+-]+)(, after sampling at ([0-9.eE+-]+) diverged)?\)", err)
    if m:
        f["smooth"] = int(m.group(3))
        f["sharp"] = float(m.group(4))
        f["first_sharp"] = float(m.group(6)) if m.group(6) else None
        f["resampled"] = bool(m.group(5)) or f["smooth"] > 0
    m = re.search(r"balls: (\d+)", err)
    f["balls"] = int(m.group(1)) if m else None
    m = re.search(r"euler (-?\d+) \(input (-?\d+)\), ([^,]*),", err)
    if m:
        f["euler"] = (int(m.group(1)), int(m.group(2)), m.group(3))
    m = re.search(r"Q min ([0-9.]+)", err)
    f["qmin"] = float(m.group(1)) if m else None
    # several materials: the worst region's volume error (%), and whether
    # every region's boundary is the input region's closed manifold
    errs = [float(x) for x in re.findall(r"^  region \d+: \d+ cells, volume [^(]*\(input [^,]*, "
                                         r"([-+0-9.]+)%\)", err, re.M)]
    f["region_volume"] = max(errs, key=abs) if errs else None
    f["regions_closed"] = "the regions' boundaries closed 2-manifolds" in err
    m = re.search(r"failed sampling at [0-9.]+ ([0-9.]+)", err)
    f["failed_time"] = float(m.group(1)) if m else None
    m = re.search(r"sliver elimination ([0-9.]+), seeds", err)
    f["t_slivers"] = float(m.group(1)) if m else None
    return f


def last_progress(err):
    lines = [l for l in err.splitlines() if l.strip()]
    return lines[-1].strip() if lines else "(no output on stderr)"


def fmt(x, spec):
    return "-" if x is None else format(x, spec)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--bin", default=os.path.join(ROOT, "build", "gen", "vorocrust"))
    ap.add_argument("--surfaces", help="take the generated surfaces from DIR (*.obj)")
    ap.add_argument("--models", nargs="*", default=None,
                    help="directories of further models (default ../shared/models when present)")
    ap.add_argument("--timeout", type=float, default=120)
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--max-memory-gb", type=float, default=8)
    ap.add_argument("--only", nargs="*", help="only the inputs of these names (file stems)")
    ap.add_argument("--keep", help="write the outputs into DIR instead of a temporary one")
    a = ap.parse_args()
    if not os.access(a.bin, os.X_OK):
        sys.exit("no executable %s" % a.bin)

    tmp = tempfile.mkdtemp(prefix="vc_hard_")
    out = a.keep or tmp
    os.makedirs(out, exist_ok=True)
    try:
        if a.surfaces:
            gen = a.surfaces
        else:
            gen = os.path.join(tmp, "surfaces")
            subprocess.check_call(["/usr/bin/python3", os.path.join(ROOT, "models", "make_hard_surfaces.py"),
                                   gen], stdout=subprocess.DEVNULL)
        inputs = sorted(os.path.join(gen, f) for f in os.listdir(gen) if f.endswith(SUFFIXES))
        manifest = os.path.join(gen, "manifest.csv")
        if os.path.exists(manifest):  # the generator's order
            order = [l.split(",")[0] for l in open(manifest).read().splitlines()[1:]]
            inputs.sort(key=lambda p: order.index(os.path.splitext(os.path.basename(p))[0])
                        if os.path.splitext(os.path.basename(p))[0] in order else len(order))
        dirs = a.models
        if dirs is None:
            shared = os.path.normpath(os.path.join(ROOT, "..", "shared", "models"))
            dirs = [shared] if os.path.isdir(shared) else []
        for d in dirs:
            inputs += sorted(os.path.join(d, f) for f in os.listdir(d) if f.endswith(SUFFIXES))
        if a.only:
            inputs = [p for p in inputs if os.path.splitext(os.path.basename(p))[0] in a.only]

        print("| input | triangles | exit | wall s | peak MiB | balls | resampled | sharp | euler "
              "| Hausdorff % | volume % | Q min | note |")
        print("|---|---:|---|---:|---:|---:|---|---:|---|---:|---:|---:|---|")
        sys.stdout.flush()
        n_good = n_good_euler = 0
        for path in inputs:
            name = os.path.basename(path)
            stem = os.path.splitext(name)[0]
            src = read_surface(path)
            n_tri = src.GetNumberOfPolys()
            vtu = os.path.join(out, stem + ".vtu")
            surf = os.path.join(out, stem + ".out.obj")
            for f in (vtu, surf):
                if os.path.exists(f):
                    os.remove(f)
            cmd = [a.bin, "mesh", path, "-o", vtu, "--surface", surf, "--threads", str(a.threads)]
            code, err, wall, peak = run(cmd, a.timeout, a.max_memory_gb * 1024)
            s = summary(err)
            if a.keep:
                with open(os.path.join(out, stem + ".log"), "w") as f:
                    f.write(err)
            notes = []
            haus = dvol = None
            eul = "-"
            if code == 0:
                if s.get("resampled"):
                    notes.append("first sampling at %g diverged after %.1f s; resampled at %g after "
                                 "%d smoothing rounds" % (s["first_sharp"] or s["sharp"], s["failed_time"] or 0,
                                                          s["sharp"], s["smooth"]))
                if "euler" in s:
                    e, ei, status = s["euler"]
                    ok = e == ei and (status.startswith("closed 2-manifold") or s["regions_closed"])
                    eul = ("ok %d" % e) if ok else ("%d vs %d%s" % (e, ei, "" if status.startswith("closed")
                                                                  else ", " + status))
                if os.path.exists(surf):
                    rec = read_surface(surf)
                    diag = diagonal(src)
                    haus = 100.0 * hausdorff(rec, src) / diag
                    v0 = volume(src)
                    dvol = 100.0 * (volume(rec) - v0) / v0 if v0 else None
                    if s["region_volume"] is not None:
                        dvol = s["region_volume"]  # the surface is the union of the regions'
                        notes.append("several regions: volume % is the worst region's")
                    if haus > 0.5:
                        notes.append("Hausdorff > 0.5%")
                    if dvol is not None and abs(dvol) > 0.5:
                        notes.append("volume off by > 0.5%")
                good = (not s.get("resampled") and haus is not None and haus <= 0.5
                        and dvol is not None and abs(dvol) <= 0.5)
                n_good += good
                n_good_euler += good and eul.startswith("ok")
                exit_s = "0"
            elif code in ("timeout", "memory"):
                exit_s = code
                notes.append("killed (%s) in: %s" % ("no finish in %g s" % a.timeout if code == "timeout"
                                                     else "RSS > %g GB" % a.max_memory_gb,
                                                     last_progress(err)))
            else:
                exit_s = str(code)
                notes.append(last_progress(err))
            note = "; ".join(notes).replace("|", "/")
            print("| %s | %d | %s | %.1f | %.0f | %s | %s | %s | %s | %s | %s | %s | %s |"
                  % (name, n_tri, exit_s, wall, peak, fmt(s.get("balls"), "d"),
                     "-" if code != 0 else ("yes" if s.get("resampled") else "no"),
                     fmt(s.get("sharp"), "g"), eul, fmt(haus, ".3f"), fmt(dvol, "+.3f"),
                     fmt(s.get("qmin"), ".3f"), note))
            sys.stdout.flush()
            if not a.keep:
                for f in (vtu, surf):
                    if os.path.exists(f):
                        os.remove(f)
        print()
        print("%d of %d inputs meshed with defaults without resampling, within 0.5%% Hausdorff and "
              "0.5%% volume (%d of them also with the input's Euler characteristic, closed and oriented)"
              % (n_good, len(inputs), n_good_euler))
    finally:
        shutil.rmtree(tmp, ignore_errors=True)


if __name__ == "__main__":
    main()
