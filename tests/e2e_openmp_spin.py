"""The CLI's short OpenMP spin (apps/cli/openmp_spin.c): unless the user set
OMP_WAIT_POLICY or GOMP_SPINCOUNT, `vorocrust` runs with GOMP_SPINCOUNT=10000
(libgomp reads it when it loads, so the program starts itself again with it);
a user's setting is left as it is. Checked on the environment of the running
process (/proc/PID/environ: the environment its image started with), on a
mesh of models/icosphere.obj that runs about a second.

Environment: VC_SOURCE, VC_BIN, VC_TMP.
"""
import os
import subprocess
import sys
import time

sys.path.insert(0, os.path.join(os.environ["VC_SOURCE"], "tests"))
from e2eutil import check, failures, fresh_tmp  # noqa: E402

BIN = os.environ["VC_BIN"]
ICOSPHERE = os.path.join(os.environ["VC_SOURCE"], "models", "icosphere.obj")
TMP = fresh_tmp("openmp_spin")


def spin_seen(extra_env):
    """GOMP_SPINCOUNT's value in the running mesher's environment (None when
    absent), and its exit code."""
    env = {k: v for k, v in os.environ.items() if k not in ("OMP_WAIT_POLICY", "GOMP_SPINCOUNT")}
    env.update(extra_env)
    p = subprocess.Popen([BIN, "mesh", ICOSPHERE, "-o", os.path.join(TMP, "i.vtu"), "--threads", "2",
                          "--quiet", "--max-error", "0.001"], env=env)
    seen = None
    deadline = time.monotonic() + 5.0  # the restart comes first thing; a slow start under a sanitizer
    while p.poll() is None and time.monotonic() < deadline:
        try:
            with open("/proc/%d/environ" % p.pid, "rb") as f:
                entries = f.read().split(b"\0")
        except OSError:
            break
        values = [e.split(b"=", 1)[1].decode() for e in entries if e.startswith(b"GOMP_SPINCOUNT=")]
        if values:
            seen = values[0]
            break
        time.sleep(0.01)
    return seen, p.wait(timeout=120)


seen, rc = spin_seen({})
check(rc == 0 and seen == "10000", "no setting: GOMP_SPINCOUNT %r in the mesher, exit %d (want '10000', 0)" % (seen, rc))
seen, rc = spin_seen({"OMP_WAIT_POLICY": "ACTIVE"})
check(rc == 0 and seen is None, "OMP_WAIT_POLICY=ACTIVE: GOMP_SPINCOUNT %r set, exit %d" % (seen, rc))
seen, rc = spin_seen({"GOMP_SPINCOUNT": "500"})
check(rc == 0 and seen == "500", "GOMP_SPINCOUNT=500: %r in the mesher, exit %d" % (seen, rc))
if failures:
    print("e2e_openmp_spin: %d failures" % len(failures), file=sys.stderr)
    sys.exit(1)
print("e2e_openmp_spin: all passed")
