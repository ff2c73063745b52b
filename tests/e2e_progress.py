"""End-to-end test of issue 16's visible work: `vorocrust mesh` says
something on stderr within 2 s of its start and then at least every 2 s
until it exits, whatever the phase (the library's progress lines, and the
CLI's keep-alive, vc_log_keepalive_start, repeating the last one while a
phase is silent: "... (still at it: N s)"). Run on the generated slot_block
(models/make_hard_surfaces.py) on one thread, about 10 s on a quiet
2-core machine; each line's arrival is timed here. A repeat must repeat
the line before it. Not under the sanitizers (their slowdown is not the
CLI's silence; test_log_keepalive checks the mechanism there).
Environment: VC_BIN, VC_SOURCE, VC_SANITIZED."""
import os
import subprocess
import sys
import threading
import time

sys.path.insert(0, os.path.join(os.environ["VC_SOURCE"], "tests"))
import e2eutil  # noqa: E402
from e2eutil import check, failures  # noqa: E402

BIN = os.environ["VC_BIN"]
GEN = os.path.join(os.environ["VC_SOURCE"], "models", "make_hard_surfaces.py")
if os.environ.get("VC_SANITIZED", "0") in ("1", "ON", "TRUE", "true"):
    print("SKIP: timings under the sanitizers", flush=True)
    sys.exit(e2eutil.SKIP)
TMP = e2eutil.fresh_tmp("e2e_progress")
LIMIT = 2.0

g = subprocess.run([sys.executable, GEN, TMP, "slot_block"], capture_output=True, text=True)
check(g.returncode == 0, "generator: %s" % g.stderr[-300:])
src = os.path.join(TMP, "slot_block.obj")

t0 = time.monotonic()
p = subprocess.Popen([BIN, "mesh", src, "-o", os.path.join(TMP, "slot_block.vtu"), "--threads", "1"],
                     stderr=subprocess.PIPE, stdout=subprocess.DEVNULL, text=True, bufsize=1)
lines = []


def read():
    for line in p.stderr:
        lines.append((time.monotonic() - t0, line.rstrip("\n")))


reader = threading.Thread(target=read)
reader.start()
rc = p.wait(timeout=600)
t_end = time.monotonic() - t0
reader.join()
check(rc == 0, "exit %d: %s" % (rc, lines[-3:]))
check(len(lines) > 0 and lines[0][0] <= LIMIT,
      "first line after %.2f s: %r" % (lines[0][0] if lines else t_end, lines[:1]))
worst, where = 0.0, None
for (ta, la), (tb, lb) in zip(lines, lines[1:]):
    if tb - ta > worst:
        worst, where = tb - ta, (la, lb)
check(worst <= LIMIT, "%.2f s without a line, between %r" % (worst, where))
repeats = 0
for (_, la), (_, lb) in zip(lines, lines[1:]):
    if "(still at it: " in lb:
        repeats += 1
        base = lb[:lb.rindex(" (still at it: ")]
        check(base == la or la.startswith(base + " (still at it: "),
              "a repeat of another line: %r after %r" % (lb, la))
print("e2e_progress: %d lines in %.1f s, longest silence %.2f s, %d repeats"
      % (len(lines), t_end, worst, repeats))
sys.exit(1 if failures else 0)
