#!/usr/bin/python3
"""Benchmark over all shared models: runs `vorocrust mesh` on every model,
once per thread count, and prints Markdown tables (to paste into README.md
or docs/benchmark-history.md).

usage: bench_models.py [--bin build/release/vorocrust] [--models ../shared/models]
                       [--threads-list 1,2] [--timeout 300] [--repeat R]
                       [--surface-only] [--args "..."] [--fail-on-mismatch] [MODEL ...]

Every MODEL (default: every .obj/.off/.stl/.ply file of --models, sorted; a
name is looked up in --models first, then as a path) is run as

    BIN mesh MODEL -o TMP/out.vtu --threads N [ARGS]
    BIN mesh MODEL --surface-only --surface TMP/s.obj --threads N [ARGS]   (--surface-only)

for each N of --threads-list, one process per run, R times (--repeat; the
fastest wall time is kept, with that run's phase times). The summary the
mesher prints on stderr gives the balls, cells, the phase times and whether
the surface was sampled again (another sharp angle, folds promoted to
creases or smoothing after the first sampling diverged).

Tables printed on stdout:
  1. per model: triangles, status (ok / exit code and the first error line /
     timeout), balls, cells, resampled (and the final sharp angle), the
     surface phase (the sampling: features and smoothing + sizing + corner
     protection + edge protection + surface coverage + Lipschitz fixes +
     sliver elimination; the time line's "surface" is the reconstructed
     surface, not part of it) and its balls per second, both at the largest
     thread count, the wall time for each thread count, the wall and
     surface-phase speed-ups against the smallest thread count, and the peak
     memory (VmHWM of /proc/PID/status, polled every 5 ms while the child
     runs: its own pages, unlike ru_maxrss which starts from the parent's;
     the binary's process only, so a wrapper script given as --bin shows the
     shell's);
  2. every phase's time at the largest thread count.
The mesher is deterministic for any thread count: a ball count (or cell
count) that differs between thread counts or repeats is flagged in the table
and in a "DETERMINISM" block after it.

Exit status: 0 when the benchmark ran, whatever the models did (a failing or
timed-out model is a row of the table); 3 with --fail-on-mismatch when the
counts differ between thread counts; 2 on a usage error (argparse), 1 on a
script error (a Python traceback), 130 on Ctrl-C."""
import argparse
import datetime
import os
import re
import shlex
import signal
import subprocess
import sys
import tempfile
import time

EXTENSIONS = (".obj", ".off", ".stl", ".ply")
# The sampling phases of the "time (s):" line, summed into the surface phase.
SURFACE_PHASES = ["features and smoothing", "sizing", "corner protection", "edge protection",
                  "surface coverage", "Lipschitz fixes", "sliver elimination"]
POLL_S = 0.005


def log(msg):
    print("[bench_models] " + msg, file=sys.stderr, flush=True)


def read_hwm_kib(pid):
    """VmHWM of a running process in KiB, None once it has exited (a zombie
    has no memory map) or when /proc cannot be read."""
    try:
        with open("/proc/%d/status" % pid) as f:
            for line in f:
                if line.startswith("VmHWM:"):
                    return int(line.split()[1])
    except (OSError, ValueError, IndexError):
        pass
    return None


def run_once(cmd, timeout):
    """dict(rc: exit code (negative: signal) or None on timeout, err: stderr
    text, wall: seconds, peak: MiB or None). The child is polled every
    POLL_S for VmHWM; the last reading before it exits is kept (growth in
    the last POLL_S is missed)."""
    with tempfile.TemporaryFile(mode="w+b") as err:
        t0 = time.monotonic()
        p = subprocess.Popen(cmd, stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL,
                             stderr=err, start_new_session=True)
        hwm = None
        timed_out = False
        try:
            while True:
                h = read_hwm_kib(p.pid)
                if h is not None and (hwm is None or h > hwm):
                    hwm = h
                pid, status = os.waitpid(p.pid, os.WNOHANG)
                if pid == p.pid:
                    break
                if time.monotonic() - t0 > timeout:
                    timed_out = True
                    os.killpg(p.pid, signal.SIGKILL)
                    os.waitpid(p.pid, 0)
                    break
                time.sleep(POLL_S)
        except BaseException:
            # Ctrl-C or a script error: do not leave the child running (it is
            # in its own session, so the terminal's SIGINT did not reach it).
            try:
                os.killpg(p.pid, signal.SIGKILL)
                os.waitpid(p.pid, 0)
            except OSError:
                pass
            raise
        wall = time.monotonic() - t0
        p.returncode = 0  # reaped by hand: keep Popen's destructor quiet
        err.seek(0)
        text = err.read().decode("utf-8", "replace")
    rc = None if timed_out else os.waitstatus_to_exitcode(status)
    return dict(rc=rc, err=text, wall=wall, peak=hwm / 1024.0 if hwm is not None else None)


def parse_summary(err):
    """The figures of `vorocrust mesh`'s summary (missing ones absent)."""
    f = {}
    m = re.search(r"^vorocrust mesh: .* \((\d+) triangles, (\d+) after (\d+) smoothing rounds; "
                  r"sharp angle ([0-9.eE+-]+)(, after sampling at ([0-9.eE+-]+) diverged)?\)\s*$",
                  err, re.M)
    if m:
        f["triangles"] = int(m.group(1))
        f["sampled_triangles"] = int(m.group(2))
        f["smooth"] = int(m.group(3))
        f["sharp"] = m.group(4)
        f["first_sharp"] = m.group(6)
    else:
        m = re.search(r"^mesh: sampling (\d+) triangles", err, re.M)
        if m:
            f["triangles"] = int(m.group(1))
    f["resample_lines"] = re.findall(r"^mesh: (sampling again .*)$", err, re.M)
    m = re.search(r"^  balls: (\d+) \(corner (\d+), edge (\d+), surface (\d+)\)", err, re.M)
    if m:
        f["balls"] = int(m.group(1))
        f["balls_kinds"] = tuple(int(x) for x in m.groups()[1:])
    f["safe_mode"] = bool(re.search(r"^  balls: .*\(safe mode\)", err, re.M))
    m = re.search(r"^  time \(s\): (.*)$", err, re.M)
    phases = []
    if m:
        for item in m.group(1).split(", "):
            mm = re.match(r"^(.*?) ([0-9.eE+-]+)$", item.strip())
            if not mm:
                continue
            name = mm.group(1)
            if name.startswith("failed sampling"):
                name = "failed sampling"
            phases.append((name, float(mm.group(2))))
    m = re.search(r"^  interior: .*, ([0-9.]+) s$", err, re.M)
    if m:
        phases.append(("interior", float(m.group(1))))
    m = re.search(r"^  Lloyd: .*, ([0-9.]+) s$", err, re.M)
    if m:
        phases.append(("Lloyd", float(m.group(1))))
    m = re.search(r"^  volume mesh: (\d+) cells \((\d+) interior seeds\).*?, ([0-9.]+) s[ ;]", err, re.M)
    if m:
        f["cells"] = int(m.group(1))
        f["interior"] = int(m.group(2))
        phases.append(("volume mesh", float(m.group(3))))
    m = re.search(r"^  total: ([0-9.]+) s, peak memory ([0-9.]+) MiB", err, re.M)
    if m:
        phases.append(("total", float(m.group(1))))
        f["self_peak"] = float(m.group(2))
    f["phases"] = phases
    times = dict(phases)
    if "surface coverage" in times:
        f["surface_phase"] = sum(times.get(k, 0.0) for k in SURFACE_PHASES)
    return f


def shorten(text, n=90):
    return text if len(text) <= n else text[:n - 3] + "..."


def first_error(err, path):
    """The first error line of a failed run without the "vorocrust: PATH: "
    prefix, shortened, Markdown-safe."""
    lines = [l.strip() for l in err.splitlines() if l.strip()]
    pick = [l for l in lines if l.startswith("vorocrust:") or "error" in l.lower()]
    text = pick[0] if pick else (lines[-1] if lines else "")
    for prefix in ("vorocrust: ", path + ": "):
        if text.startswith(prefix):
            text = text[len(prefix):]
    return md(shorten(text))


def last_progress(err):
    """The last "mesh: ..." progress line (the phase a killed run was in)."""
    lines = [l.strip() for l in err.splitlines() if l.startswith("mesh: ")]
    return md(shorten(lines[-1][len("mesh: "):], 60)) if lines else ""


def md(text):
    return text.replace("|", "\\|").replace("\n", " ")


def status_text(rc, err, timeout, path):
    if rc is None:
        where = last_progress(err)
        return "timeout (%g s)%s" % (timeout, ", in: " + where if where else "")
    if rc < 0:
        try:
            name = signal.Signals(-rc).name
        except ValueError:
            name = "signal %d" % -rc
        where = last_progress(err)
        return "killed by %s%s" % (name, ", in: " + where if where else "")
    msg = first_error(err, path)
    return "exit %d%s" % (rc, ": " + msg if msg else "")


def fmt_s(x):
    if x is None:
        return "-"
    return "%.3f" % x if x < 10 else "%.2f" % x if x < 100 else "%.1f" % x


def fmt_int(x):
    return "-" if x is None else "{:,}".format(x)


def git_head(root):
    try:
        out = subprocess.run(["git", "-C", root, "log", "-1", "--format=%h %cd", "--date=short"],
                             capture_output=True, text=True, timeout=10)
        if out.returncode == 0:
            dirty = subprocess.run(["git", "-C", root, "status", "--porcelain", "--untracked-files=no"],
                                   capture_output=True, text=True, timeout=10).stdout.strip()
            return out.stdout.strip() + (" (plus uncommitted changes)" if dirty else "")
    except (OSError, subprocess.SubprocessError):
        pass
    return "?"


def parse_threads(text):
    try:
        ns = [int(x) for x in text.split(",") if x.strip()]
    except ValueError:
        raise argparse.ArgumentTypeError("expected thread counts like 1,2: %r" % text)
    if not ns or any(n < 1 for n in ns):
        raise argparse.ArgumentTypeError("thread counts must be positive: %r" % text)
    return sorted(set(ns))


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    root = os.path.dirname(os.path.dirname(here))
    ap = argparse.ArgumentParser(
        description="Run `vorocrust mesh` on every shared model for each thread count and print "
                    "Markdown tables: balls, cells, resampling, surface-phase time and balls/s, "
                    "wall times, speed-up, peak memory, and every phase's time.",
        epilog="Exit status 0 whatever the models did (failures are rows); 3 with "
               "--fail-on-mismatch when ball or cell counts differ between thread counts; "
               "2 on a usage error, 1 on a script error.")
    ap.add_argument("--bin", default=os.path.join(root, "build", "release", "vorocrust"),
                    help="the vorocrust binary (default: %(default)s)")
    ap.add_argument("--models", default=os.path.normpath(os.path.join(root, "..", "shared", "models")),
                    help="models directory (default: %(default)s)")
    ap.add_argument("--threads-list", type=parse_threads, default=[1, 2], metavar="N,N,...",
                    help="thread counts, one run each (default: 1,2)")
    ap.add_argument("--timeout", type=float, default=300, help="seconds per run (default: 300)")
    ap.add_argument("--repeat", type=int, default=1, metavar="R",
                    help="runs per model and thread count; the fastest wall time is kept (default: 1)")
    ap.add_argument("--surface-only", action="store_true",
                    help="--surface-only --surface TMP/s.obj instead of -o TMP/out.vtu")
    ap.add_argument("--args", default="", help='extra options for vorocrust mesh, e.g. "--seed 2"')
    ap.add_argument("--fail-on-mismatch", action="store_true",
                    help="exit 3 when ball or cell counts differ between thread counts or repeats")
    ap.add_argument("model", nargs="*", help="model names (in --models) or paths (default: all of "
                    "--models' %s files)" % "/".join(EXTENSIONS))
    a = ap.parse_args()
    if a.repeat < 1:
        ap.error("--repeat must be at least 1")
    if a.timeout <= 0:
        ap.error("--timeout must be positive")
    if not (os.path.isfile(a.bin) and os.access(a.bin, os.X_OK)):
        ap.error("no executable %s (build it, or give --bin)" % a.bin)
    extra = shlex.split(a.args)

    models = []  # (name shown, path or None when not found)
    if a.model:
        for m in a.model:
            p = os.path.join(a.models, m)
            models.append((m, p if os.path.isfile(p) else m if os.path.isfile(m) else None))
    else:
        if not os.path.isdir(a.models):
            ap.error("no models directory %s" % a.models)
        names = sorted(n for n in os.listdir(a.models)
                       if n.lower().endswith(EXTENSIONS) and os.path.isfile(os.path.join(a.models, n)))
        if not names:
            ap.error("no %s files in %s" % ("/".join(EXTENSIONS), a.models))
        models = [(n, os.path.join(a.models, n)) for n in names]

    threads = a.threads_list
    nmax, nmin = threads[-1], threads[0]
    started = datetime.datetime.now(datetime.timezone.utc)
    load = os.getloadavg()
    results = []  # per model: dict(name, runs={N: best run dict}, all={N: [runs]})
    with tempfile.TemporaryDirectory(prefix="bench_models.") as tmp:
        for name, path in models:
            res = dict(name=name, path=path, best={}, runs={})
            results.append(res)
            if path is None:
                log("%s: not found" % name)
                continue
            for n in threads:
                if a.surface_only:
                    cmd = [a.bin, "mesh", path, "--surface-only", "--surface", os.path.join(tmp, "s.obj")]
                else:
                    cmd = [a.bin, "mesh", path, "-o", os.path.join(tmp, "out.vtu")]
                cmd += ["--threads", str(n)] + extra
                runs = []
                for i in range(a.repeat):
                    r = run_once(cmd, a.timeout)
                    r.update(parse_summary(r["err"]))
                    r["status"] = "ok" if r["rc"] == 0 else status_text(r["rc"], r["err"], a.timeout, path)
                    runs.append(r)
                    if r["rc"] == 0 and ("balls" not in r or "surface_phase" not in r):
                        log("%s: exit 0 but the summary's balls or time line was not recognised "
                            "(did its format change?)" % name)
                    log("%s, %d thread%s, run %d/%d: %s, %.2f s%s" % (
                        name, n, "" if n == 1 else "s", i + 1, a.repeat, r["status"], r["wall"],
                        ", %d balls" % r["balls"] if "balls" in r else ""))
                    if r["rc"] != 0:
                        break
                res["runs"][n] = runs
                ok = [r for r in runs if r["rc"] == 0]
                res["best"][n] = min(ok, key=lambda r: r["wall"]) if ok else runs[-1]
    finished = datetime.datetime.now(datetime.timezone.utc)

    # Determinism: every successful run of a model must give the same counts.
    mismatches = []
    for res in results:
        seen = {}
        for n in threads:
            for r in res["runs"].get(n, []):
                if r["rc"] != 0:
                    continue
                key = (r.get("balls"), r.get("balls_kinds"), r.get("cells"))
                seen.setdefault(key, []).append(n)
        res["mismatch"] = len(seen) > 1
        if res["mismatch"]:
            mismatches.append((res["name"], seen))

    mode = "--surface-only --surface TMP/s.obj" if a.surface_only else "-o TMP/out.vtu"
    print("# vorocrust mesh MODEL %s --threads N%s; N = %s; %s" % (
        mode, " " + a.args if a.args else "", ",".join(map(str, threads)),
        "fastest of %d runs" % a.repeat if a.repeat > 1 else "one run each"))
    print("# binary %s; main at %s; %s to %s UTC; %d cores; load average at start %.2f %.2f %.2f" % (
        a.bin, git_head(root), started.strftime("%Y-%m-%d %H:%M"), finished.strftime("%H:%M"),
        os.cpu_count() or 0, load[0], load[1], load[2]))
    print("# surface phase: features and smoothing + sizing + corner + edge protection + surface "
          "coverage + Lipschitz fixes + sliver elimination, at %d thread%s (balls/s: balls / that;" % (
              nmax, "" if nmax == 1 else "s"))
    print("# a diverged first sampling is not in it: \"failed sampling\" in the phase table);")
    print("# wall s: the whole process; peak MiB: VmHWM of /proc/PID/status polled every %g ms, at "
          "%d thread%s" % (POLL_S * 1000, nmax, "" if nmax == 1 else "s"))
    print()

    others = [n for n in threads if n != nmin]
    head = ["model", "triangles", "status", "balls", "cells", "resampled (sharp angle)",
            "surface phase s", "balls/s"]
    head += ["wall s, %d thr" % n for n in threads]
    head += ["speed-up t%d/t%d" % (nmin, n) for n in others]
    head += ["surface speed-up t%d/t%d" % (nmin, n) for n in others]
    head += ["peak MiB"]
    align = ["---", "--:", "---", "--:", "--:", "---", "--:", "--:"] + ["--:"] * (
        len(threads) + 2 * len(others) + 1)
    print("| " + " | ".join(head) + " |")
    print("|" + "|".join(align) + "|")
    for res in results:
        name = res["name"]
        if res["path"] is None:
            print("| %s | - | not found | " % md(name) + " | ".join(["-"] * (len(head) - 3)) + " |")
            continue
        best = res["best"]
        top = best[nmax]
        any_f = next((best[n] for n in reversed(threads) if "triangles" in best[n]), top)
        tri = any_f.get("triangles")
        if any_f.get("sampled_triangles") is not None and any_f.get("sampled_triangles") != tri:
            tri_text = "%s (%s sampled)" % (fmt_int(tri), fmt_int(any_f["sampled_triangles"]))
        else:
            tri_text = fmt_int(tri)
        statuses = {}
        for n in threads:
            statuses.setdefault(best[n]["status"], []).append(n)
        if list(statuses) == ["ok"]:
            status = "ok"
        else:
            status = "; ".join("%s (%s thr)" % (s, ",".join(map(str, ns))) if len(statuses) > 1 else s
                               for s, ns in statuses.items())
        ball_vals = sorted({best[n]["balls"] for n in threads if best[n]["rc"] == 0 and "balls" in best[n]})
        if res["mismatch"]:
            balls = "**MISMATCH** " + " / ".join(
                "%s (%d thr)" % (fmt_int(best[n].get("balls")), n) for n in threads if best[n]["rc"] == 0)
            cells = " / ".join(fmt_int(best[n].get("cells")) for n in threads if best[n]["rc"] == 0)
        else:
            ok_best = next((best[n] for n in reversed(threads) if best[n]["rc"] == 0), top)
            balls = fmt_int(ball_vals[0]) if ball_vals else fmt_int(top.get("balls"))
            cells = fmt_int(ok_best.get("cells")) if not a.surface_only else "-"
        if "sharp" in any_f:
            lines = any_f.get("resample_lines", [])
            if any_f.get("first_sharp") is not None or lines:
                resampled = "yes (%s -> %s%s%s)" % (
                    any_f.get("first_sharp") or "?", any_f["sharp"],
                    ", %d smoothing rounds" % any_f["smooth"] if any_f.get("smooth") else "",
                    ", %d retries" % len(lines) if len(lines) > 1 else "")
            else:
                resampled = "no (%s%s)" % (any_f["sharp"], ", %d smoothing rounds" % any_f["smooth"]
                                           if any_f.get("smooth") else "")
            if any_f.get("safe_mode"):
                resampled += ", sliver safe mode"
        else:
            resampled = "yes (failed)" if any_f.get("resample_lines") else "-"
        sp = top.get("surface_phase") if top["rc"] == 0 else None
        bps = "{:,.0f}".format(top["balls"] / sp) if sp and top.get("balls") else "-"
        walls = [fmt_s(best[n]["wall"]) if best[n]["rc"] == 0 else "-" for n in threads]
        speed = []
        for n in others:
            b0, b1 = best[nmin], best[n]
            speed.append("%.2f" % (b0["wall"] / b1["wall"]) if b0["rc"] == 0 and b1["rc"] == 0 else "-")
        sspeed = []
        for n in others:
            s0, s1 = best[nmin].get("surface_phase"), best[n].get("surface_phase")
            ok = best[nmin]["rc"] == 0 and best[n]["rc"] == 0 and s0 and s1
            sspeed.append("%.2f" % (s0 / s1) if ok else "-")
        peak = "%.0f" % top["peak"] if top.get("peak") is not None else "-"
        row = [md(name), tri_text, status, balls, cells, resampled, fmt_s(sp), bps] + walls + speed + sspeed + [peak]
        print("| " + " | ".join(row) + " |")
    print()

    # Phases at the largest thread count, in the order the summary gives them.
    order = []
    for res in results:
        r = res["best"].get(nmax)
        if r and r["rc"] == 0:
            for k, _ in r["phases"]:
                if k not in order:
                    order.append(k)
    print("Phase times (s) at %d thread%s (\"surface\": the reconstructed surface; \"volume mesh\": "
          "Voronoi cells, quality and writing; \"total\": the mesher's own):" % (nmax, "" if nmax == 1 else "s"))
    print()
    print("| model | " + " | ".join(order) + " | wall |")
    print("|---|" + "--:|" * (len(order) + 1))
    for res in results:
        r = res["best"].get(nmax)
        if not r or r["rc"] != 0:
            print("| %s | " % md(res["name"]) + " | ".join(["-"] * len(order)) + " | %s |" % (
                "failed" if r else "not found"))
            continue
        t = dict(r["phases"])
        print("| %s | %s | %s |" % (md(res["name"]), " | ".join(
            "%.3f" % t[k] if k in t else "-" for k in order), fmt_s(r["wall"])))
    print()

    if len(threads) > 1 or a.repeat > 1:
        if mismatches:
            print("**DETERMINISM: counts differ between thread counts or repeats** "
                  "(the mesher must give the same balls for any thread count):")
            for name, seen in mismatches:
                print("- %s: " % md(name) + "; ".join(
                    "balls %s (corner/edge/surface %s), cells %s at %s thr" % (
                        fmt_int(k[0]), "/".join(map(str, k[1])) if k[1] else "?", fmt_int(k[2]),
                        ",".join(map(str, ns))) for k, ns in seen.items()))
            log("DETERMINISM FAILURE: ball or cell counts differ between thread counts or repeats: %s"
                % ", ".join(n for n, _ in mismatches))
        else:
            compared = sum(1 for res in results
                           if sum(1 for n in threads for r in res["runs"].get(n, []) if r["rc"] == 0) > 1)
            print("Determinism: ball and cell counts identical between thread counts %s%s "
                  "(%d models compared)." % (",".join(map(str, threads)),
                                             " and repeats" if a.repeat > 1 else "", compared))
    return 3 if (mismatches and a.fail_on_mismatch) else 0


def on_signal(signum, frame):
    # SIGTERM / SIGHUP: unwind like Ctrl-C, so that run_once kills the child
    # (in its own session, it would not get the signal) and the temporary
    # directory is removed.
    raise SystemExit(128 + signum)


if __name__ == "__main__":
    signal.signal(signal.SIGTERM, on_signal)
    signal.signal(signal.SIGHUP, on_signal)
    try:
        sys.exit(main())
    except KeyboardInterrupt:
        log("interrupted")
        sys.exit(130)
