#!/usr/bin/python3
"""Volume-mesh benchmark: runs `vorocrust mesh MODEL -o OUT.vtu` (the whole
pipeline: reading, sampling, seeds, reconstructed surface, interior seeds,
Voronoi cells, validation, quality, writing) on the reference models, one
process each, and prints per model the wall time, the peak memory of that
process (its own rusage, from wait4), the cell count and cells per second,
the summary's figures (balls, interior seeds, octree leaves, fatness) and
the ratio to the public VoroCrust implementation where known. A model that
fails (non-zero exit, or no finish within --timeout) is reported as a
failed row with the reason; the benchmark goes on.

usage: bench_mesh.py [--bin build/release/vorocrust] [--models ../shared/models]
                     [--timeout 300] [--threads N] [--repeat R] [--args "..."] [MODEL ...]
(default models: bracket.obj torus.obj fertility.off; --repeat: the fastest
of R runs; --args: extra options for vorocrust mesh, e.g. "--lloyd 2")"""
import argparse
import os
import re
import shlex
import subprocess
import sys
import tempfile
import time

# Public VoroCrust implementation on this machine class (issue #4).
PEER = {"bracket.obj": (47.6, 29327)}


def run_once(cmd, timeout):
    """(exit code or None on timeout, stderr text, wall s, peak MiB)."""
    with tempfile.TemporaryFile(mode="w+") as err:
        t0 = time.monotonic()
        p = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=err)
        while True:
            pid, status, ru = os.wait4(p.pid, os.WNOHANG)
            if pid == p.pid:
                break
            if time.monotonic() - t0 > timeout:
                p.kill()
                os.wait4(p.pid, 0)
                p.returncode = -9
                return None, "", time.monotonic() - t0, 0.0
            time.sleep(0.01)
        wall = time.monotonic() - t0
        p.returncode = os.waitstatus_to_exitcode(status)
        err.seek(0)
        return p.returncode, err.read(), wall, ru.ru_maxrss / 1024.0


def figures(err):
    f = {}
    m = re.search(r"volume mesh: (\d+) cells \((\d+) interior seeds\)", err)
    if m:
        f["cells"], f["interior"] = int(m.group(1)), int(m.group(2))
    m = re.search(r"balls: (\d+)", err)
    f["balls"] = int(m.group(1)) if m else None
    m = re.search(r"surface seeds: (\d+)", err)
    f["surface_seeds"] = int(m.group(1)) if m else None
    m = re.search(r"octree of (\d+) leaves", err)
    f["leaves"] = int(m.group(1)) if m else None
    m = re.search(r"fatness max ([0-9.]+) mean ([0-9.]+) \(interior cells: max ([0-9.]+) mean ([0-9.]+)\)", err)
    f["fatness"] = tuple(float(x) for x in m.groups()) if m else None
    m = re.search(r"volume ([0-9.e+-]+) \(reconstructed surface ([0-9.e+-]+), input ([0-9.e+-]+)\)", err)
    f["volume"] = tuple(float(x) for x in m.groups()) if m else None
    return f


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    root = os.path.dirname(os.path.dirname(here))
    ap = argparse.ArgumentParser()
    ap.add_argument("--bin", default=os.path.join(root, "build", "release", "vorocrust"))
    ap.add_argument("--models", default=os.path.join(root, "..", "shared", "models"))
    ap.add_argument("--timeout", type=float, default=300)
    ap.add_argument("--threads", default=None)
    ap.add_argument("--repeat", type=int, default=1)
    ap.add_argument("--args", default="")
    ap.add_argument("model", nargs="*", default=["bracket.obj", "torus.obj", "fertility.off"])
    a = ap.parse_args()
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for m in a.model:
            cmd = [a.bin, "mesh", os.path.join(a.models, m), "-o", os.path.join(tmp, "mesh.vtu")]
            if a.threads:
                cmd += ["--threads", a.threads]
            cmd += shlex.split(a.args)
            best = None
            for _ in range(max(1, a.repeat)):
                rc, err, wall, peak = run_once(cmd, a.timeout)
                if rc is None:
                    best = ("did not finish in %g s" % a.timeout, None)
                    break
                if rc != 0:
                    lines = [l for l in err.strip().splitlines() if l.startswith("vorocrust:")]
                    reason = lines[-1] if lines else (err.strip().splitlines() or ["exit %d" % rc])[-1]
                    best = ("failed (exit %d): %s" % (rc, reason), None)
                    break
                if best is None or wall < best[1]["wall"]:
                    best = (None, dict(wall=wall, peak=peak, **figures(err)))
            rows.append((m, best[1], best[0]))
            print("[bench_mesh] %s: %s" % (m, best[0] or "%.2f s" % best[1]["wall"]), file=sys.stderr)
    print("# vorocrust mesh MODEL -o OUT.vtu%s%s, one process per run%s; wall seconds of the whole"
          % (" --threads " + a.threads if a.threads else "", " " + a.args if a.args else "",
             ", fastest of %d" % a.repeat if a.repeat > 1 else ""))
    print("# run; peak MiB: the process's max RSS")
    print()
    print("| model | balls | cells (interior) | octree leaves | wall s | peak MiB | cells/s "
          "| fatness max / mean | interior fatness max / mean | volume vs input | public VoroCrust |")
    print("|---|--:|--:|--:|--:|--:|--:|--:|--:|--:|---|")
    for m, r, note in rows:
        if r is None:
            print("| %s | %s |  |  |  |  |  |  |  |  |  |" % (m, note))
            continue
        fat = r.get("fatness") or (float("nan"),) * 4
        vol = r.get("volume")
        dv = "%+.2f%%" % (100 * (vol[0] - vol[2]) / vol[2]) if vol else "?"
        peer = PEER.get(m)
        peer_text = "%.1f s, %d cells (%.0fx)" % (peer[0], peer[1], peer[0] / r["wall"]) if peer else "-"
        print("| %s | %s | %s (%s) | %s | %.2f | %.0f | %.0f | %.2f / %.2f | %.2f / %.2f | %s | %s |" % (
            m, r.get("balls"), r.get("cells"), r.get("interior"), r.get("leaves") or "-", r["wall"],
            r["peak"], r.get("cells", 0) / r["wall"], fat[0], fat[1], fat[2], fat[3], dv, peer_text))


if __name__ == "__main__":
    main()
