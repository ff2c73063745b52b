#!/usr/bin/python3
"""Surface-sampling benchmark: runs `vorocrust mesh --surface-only` on the
reference models, one process each, and prints per model the ball counts,
the time of each phase (the thesis' Table 6.1 phases), the wall time and
peak memory of the run, and the ratio to the public VoroCrust
implementation's published wall time on this machine class where known.

usage: bench_surface.py [--bin build/release/vorocrust] [--models ../shared/models]
                        [--timeout 120] [--threads N] [MODEL ...]
(default models: bracket.obj torus.obj fandisk.off)"""
import argparse
import os
import re
import resource
import subprocess
import sys
import tempfile
import time

# Public VoroCrust implementation, 2 threads, this machine class (issue #3).
PEER_SECONDS = {"bracket.obj": 47.6, "torus.obj": 11.1}
PEER_BALLS = {"bracket.obj": 10438}
PHASES = ["features and smoothing", "sizing", "corner protection", "edge protection",
          "surface coverage", "Lipschitz fixes", "sliver elimination", "seeds", "surface"]


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    root = os.path.dirname(os.path.dirname(here))
    ap = argparse.ArgumentParser()
    ap.add_argument("--bin", default=os.path.join(root, "build", "release", "vorocrust"))
    ap.add_argument("--models", default=os.path.join(root, "..", "shared", "models"))
    ap.add_argument("--timeout", type=float, default=120)
    ap.add_argument("--threads", default=None)
    ap.add_argument("model", nargs="*", default=["bracket.obj", "torus.obj", "fandisk.off"])
    a = ap.parse_args()
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for m in a.model:
            cmd = [a.bin, "mesh", os.path.join(a.models, m), "--surface-only", "--surface",
                   os.path.join(tmp, "s.obj")]
            if a.threads:
                cmd += ["--threads", a.threads]
            t0 = time.monotonic()
            before = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss
            try:
                p = subprocess.run(cmd, capture_output=True, text=True, timeout=a.timeout)
                wall = time.monotonic() - t0
                err, rc = p.stderr, p.returncode
            except subprocess.TimeoutExpired:
                rows.append((m, None, "did not finish in %g s" % a.timeout))
                print("[bench_surface] %s: did not finish in %g s" % (m, a.timeout), file=sys.stderr)
                continue
            peak = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss
            if rc != 0:
                rows.append((m, None, "failed: " + err.strip().splitlines()[-1]))
                continue
            b = re.search(r"balls: (\d+) \(corner (\d+), edge (\d+), surface (\d+)\)", err)
            t = re.search(r"time \(s\): (.*)", err)
            times = dict((k.strip(), float(v)) for k, v in
                         (x.rsplit(" ", 1) for x in t.group(1).split(", "))) if t else {}
            surf = re.search(r"surface: .*", err)
            rows.append((m, dict(balls=b.groups() if b else None, times=times, wall=wall,
                                 peak=max(peak, before) / 1024.0,
                                 surface=surf.group(0) if surf else ""), None))
            print("[bench_surface] %s: %.2f s" % (m, wall), file=sys.stderr)
    print("# vorocrust mesh --surface-only, one process per model; wall seconds of the whole run")
    print("# (reading, sampling, seeds, reconstruction, writing); peak MiB: max RSS of the runs so far")
    print()
    print("| model | balls (corner/edge/surface) | " + " | ".join(PHASES) + " | wall s | peak MiB | public VoroCrust s | speed-up |")
    print("|---|---|" + "--:|" * (len(PHASES) + 4))
    for m, r, note in rows:
        if r is None:
            print("| %s | %s |" % (m, note) + " |" * (len(PHASES) + 4))
            continue
        balls = "%s (%s/%s/%s)" % tuple(r["balls"]) if r["balls"] else "?"
        ph = " | ".join("%.3f" % r["times"].get(k, float("nan")) for k in PHASES)
        peer = PEER_SECONDS.get(m)
        print("| %s | %s | %s | %.2f | %.0f | %s | %s |" % (
            m, balls, ph, r["wall"], r["peak"], "%.1f" % peer if peer else "-",
            "%.1f" % (peer / r["wall"]) if peer else "-"))
    print()
    for m, r, note in rows:
        if r is not None:
            extra = " (public implementation: %d surface balls)" % PEER_BALLS[m] if m in PEER_BALLS else ""
            print("%s: %s%s" % (m, r["surface"].strip(), extra))


if __name__ == "__main__":
    main()
