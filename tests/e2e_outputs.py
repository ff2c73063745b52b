"""End-to-end test of what the commands do to their output paths (issue 17):

 - an output that exists and is not a regular file is refused with one line
   before any work, exit 1, and left as it was: a FIFO made here (every
   output option of mesh, voronoi, compare, vc-tetgen), /dev/null (checked
   to still be a character device after each run: the command must refuse
   it before writing anything), a socket, a directory, a symbolic link to a
   FIFO; --foam on a FIFO is refused as "Not a directory";
 - a repeated option (-o a -o b, --output a -o b, --seeds twice, ...) is
   refused with one line, exit 2, in every command;
 - a run interrupted by SIGINT, SIGTERM or SIGHUP while it writes (a large
   `vorocrust voronoi` mesh of random seeds: the signal is sent once the
   .tmp file or the case's .tmp directory appears) leaves no file at all
   in the output directory, not even the outputs it had already committed,
   and dies by that signal; the same for SIGXFSZ (`ulimit -f`), in
   `vorocrust voronoi` and in `vorocrust mesh` (whose surface, balls and
   seeds fit under the limit and are committed before the .vtu exceeds it);
 - a signal at a given moment of an OpenFOAM write into an existing case
   (the VC_TEST_SIGNAL_AT hook: when constant/ or system/ is made, when the
   old polyMesh is set aside, between that and the new one renamed in,
   after it): the case is left as it was (the old polyMesh byte for byte,
   no directory of the run's); uninterrupted, the polyMesh is replaced and
   no .old directory stays.
Environment: VC_BIN, VC_TMP, VC_SOURCE, VC_SANITIZED (fewer seeds), VC_TETGEN
(optional: vc-tetgen's checks)."""
import os
import random
import shutil
import signal
import socket
import stat
import subprocess
import sys
import time

sys.path.insert(0, os.path.join(os.environ["VC_SOURCE"], "tests"))
from e2eutil import check, failures  # noqa: E402

BIN = os.environ["VC_BIN"]
TETGEN = os.environ.get("VC_TETGEN", "")
SANITIZED = os.environ.get("VC_SANITIZED", "0") not in ("", "0", "OFF", "FALSE")
TMP = os.path.join(os.environ.get("VC_TMP", "/tmp"), "e2e_outputs")
ICOSPHERE = os.path.join(os.environ["VC_SOURCE"], "models", "icosphere.obj")
T0 = time.time()

shutil.rmtree(TMP, ignore_errors=True)
os.makedirs(TMP)
SPECIAL = os.path.join(TMP, "special")  # the FIFO, socket, ... live here
os.makedirs(SPECIAL)
OUT = os.path.join(TMP, "out")  # must stay empty after every refused or interrupted run
os.makedirs(OUT)


def run(argv, timeout=120):
    p = subprocess.run(argv, capture_output=True, text=True, timeout=timeout)
    return p.returncode, p.stderr


def out_empty(what):
    left = sorted(os.listdir(OUT))
    check(not left, "%s: left %s in the output directory" % (what, left))
    for f in left:
        path = os.path.join(OUT, f)
        if os.path.isdir(path) and not os.path.islink(path):
            shutil.rmtree(path)
        else:
            os.remove(path)


def devnull_intact(what):
    st = os.stat("/dev/null")
    check(stat.S_ISCHR(st.st_mode), "%s: /dev/null is no longer a character device" % what)


def write_seeds(path, n, seed):
    rng = random.Random(seed)
    with open(path, "w") as f:
        f.write("x,y,z\n")
        f.write("".join("%.17g,%.17g,%.17g\n" % (rng.random(), rng.random(), rng.random())
                        for _ in range(n)))


SEEDS_SMALL = os.path.join(TMP, "small.csv")
write_seeds(SEEDS_SMALL, 200, 1)

FIFO = os.path.join(SPECIAL, "fifo")
os.mkfifo(FIFO)
SOCK = os.path.join(SPECIAL, "sock")
sock = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
sock.bind(SOCK)
LINK = os.path.join(SPECIAL, "link-to-fifo")
os.symlink(FIFO, LINK)
DIR = os.path.join(SPECIAL, "dir")
os.makedirs(DIR)


def o(name):
    return os.path.join(OUT, name)


# ---- refusals of non-regular outputs ---------------------------------------

# (what, argv builder taking the bad target, expected words, the program's prefix)
CASES = []
for opt in ("-o", "--surface", "--seeds", "--balls", "--connections"):
    def mesh_argv(bad, opt=opt):
        outs = {"-o": o("m.vtu"), "--surface": o("s.obj"), "--seeds": o("s.csv"),
                "--balls": o("b.csv"), "--connections": o("c.csv")}
        outs[opt] = bad
        argv = [BIN, "mesh", ICOSPHERE, "--quiet"]
        for k, v in outs.items():
            argv += [k, v]
        return argv
    CASES.append(("mesh " + opt, mesh_argv, "vorocrust: "))
for opt in ("-o", "--connections"):
    def voronoi_argv(bad, opt=opt):
        outs = {"-o": o("v.vtu"), "--connections": o("c.csv")}
        outs[opt] = bad
        argv = [BIN, "voronoi", SEEDS_SMALL, "--quiet"]
        for k, v in outs.items():
            argv += [k, v]
        return argv
    CASES.append(("voronoi " + opt, voronoi_argv, "vorocrust: "))
CASES.append(("compare -o", lambda bad: [BIN, "compare", ICOSPHERE, "-o", bad, "--quiet"],
              "vorocrust: "))
if TETGEN:
    CASES.append(("vc-tetgen -o", lambda bad: [TETGEN, ICOSPHERE, "-o", bad, "--quiet"],
                  "vc-tetgen: "))
else:
    print("note: VC_TETGEN not set: vc-tetgen's refusals not checked")

TARGETS = [(FIFO, "is a FIFO, not a regular file"),
           ("/dev/null", "is a character device, not a regular file")]
for what, argv_of, prefix in CASES:
    for target, words in TARGETS:
        t = time.time()
        rc, err = run(argv_of(target))
        dt = time.time() - t
        label = "%s %s" % (what, target)
        check(rc == 1, "%s: exit %d, expected 1 (%s)" % (label, rc, err.strip()[-300:]))
        lines = err.strip().splitlines()
        check(len(lines) == 1 and lines[0].startswith(prefix + target + ": ") and words in lines[0],
              "%s: expected one line '%s%s: ... %s', got %r" % (label, prefix, target, words, err))
        check(dt < 5, "%s: the refusal took %.1f s (it must come before any work)" % (label, dt))
        devnull_intact(label)
        check(stat.S_ISFIFO(os.lstat(FIFO).st_mode), "%s: the FIFO was replaced" % label)
        out_empty(label)

# other kinds, on voronoi -o
for target, words in ((SOCK, "is a socket, not a regular file"),
                      (DIR, "cannot write: Is a directory"),
                      (LINK, "is a FIFO, not a regular file")):
    rc, err = run([BIN, "voronoi", SEEDS_SMALL, "-o", target, "--quiet"])
    label = "voronoi -o %s" % target
    check(rc == 1 and len(err.strip().splitlines()) == 1 and words in err,
          "%s: exit %d, %r (expected exit 1, one line '%s')" % (label, rc, err, words))
    out_empty(label)
check(stat.S_ISSOCK(os.lstat(SOCK).st_mode) and os.path.islink(LINK) and os.path.isdir(DIR),
      "the socket, the symbolic link or the directory was replaced")

# --foam on something that is not a directory
for argv in ([BIN, "voronoi", SEEDS_SMALL, "-o", o("v.vtu"), "--foam", FIFO, "--quiet"],
             [BIN, "mesh", ICOSPHERE, "-o", o("m.vtu"), "--foam", FIFO, "--quiet"],
             [BIN, "voronoi", SEEDS_SMALL, "-o", o("v.vtu"), "--foam", "/dev/null", "--quiet"]):
    rc, err = run(argv)
    label = " ".join(argv[1:2] + argv[-3:-1])
    check(rc == 1 and len(err.strip().splitlines()) == 1 and "Not a directory" in err,
          "%s: exit %d, %r (expected exit 1, one line 'Not a directory')" % (label, rc, err))
    devnull_intact(label)
    check(stat.S_ISFIFO(os.lstat(FIFO).st_mode), "%s: the FIFO was replaced" % label)
    out_empty(label)

# ---- repeated options --------------------------------------------------------

REPEATS = [
    [BIN, "voronoi", SEEDS_SMALL, "-o", o("a.vtu"), "-o", o("b.vtu")],
    [BIN, "voronoi", SEEDS_SMALL, "--output", o("a.vtu"), "-o", o("b.vtu")],
    [BIN, "voronoi", SEEDS_SMALL, "-o", o("a.vtu"), "--connections", o("a.csv"),
     "--connections", o("b.csv")],
    [BIN, "voronoi", SEEDS_SMALL, "-o", o("a.vtu"), "--threads", "1", "--threads", "2"],
    [BIN, "voronoi", SEEDS_SMALL, "-o", o("a.vtu"), "--foam", o("c1"), "--foam", o("c2")],
    [BIN, "mesh", ICOSPHERE, "-o", o("a.vtu"), "-o", o("b.vtu")],
    [BIN, "mesh", ICOSPHERE, "-o", o("a.vtu"), "--seeds", o("a.csv"), "--seeds", o("b.csv")],
    [BIN, "mesh", ICOSPHERE, "-o", o("a.vtu"), "--surface", o("a.obj"), "--surface", o("b.obj")],
    [BIN, "mesh", ICOSPHERE, "-o", o("a.vtu"), "--balls", o("a.csv"), "--balls", o("b.csv")],
    [BIN, "mesh", ICOSPHERE, "-o", o("a.vtu"), "--connections", o("a.csv"), "--connections",
     o("b.csv")],
    [BIN, "mesh", ICOSPHERE, "-o", o("a.vtu"), "--seed", "1", "--seed", "2"],
    [BIN, "compare", ICOSPHERE, "-o", o("a.html"), "--output", o("b.html")],
    [BIN, "quality", o("a.vtu"), "--input", ICOSPHERE, "--input", ICOSPHERE],
]
if TETGEN:
    REPEATS.append([TETGEN, ICOSPHERE, "-o", o("a.vtu"), "-o", o("b.vtu")])
for argv in REPEATS:
    rc, err = run(argv)
    label = " ".join(os.path.basename(a) for a in argv)
    check(rc == 2 and len(err.strip().splitlines()) == 1 and "given twice" in err,
          "%s: exit %d, %r (expected exit 2, one line 'given twice')" % (label, rc, err))
    out_empty(label)

# ---- interrupted runs --------------------------------------------------------

N_SEEDS = 30000 if SANITIZED else 100000
SEEDS_BIG = os.path.join(TMP, "big.csv")
write_seeds(SEEDS_BIG, N_SEEDS, 2)


def interrupt(sig, wait_for, label):
    """vorocrust voronoi on the big seeds, all three outputs; sig sent once
    a name containing wait_for appears in the output directory."""
    argv = [BIN, "voronoi", SEEDS_BIG, "-o", o("m.vtu"), "--connections", o("c.csv"),
            "--foam", o("case"), "--no-validate", "--quiet", "--threads", "2"]
    t = time.time()
    p = subprocess.Popen(argv, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    seen = None
    while p.poll() is None and time.time() - t < 300:
        names = os.listdir(OUT)
        hit = [n for n in names if wait_for in n]
        if hit:
            seen = sorted(names)
            time.sleep(0.02)  # well inside the write
            p.send_signal(sig)
            break
        time.sleep(0.002)
    try:
        p.wait(timeout=120)
    except subprocess.TimeoutExpired:
        p.kill()
        p.wait()
    err = p.stderr.read().decode(errors="replace")
    p.stderr.close()
    check(seen is not None, "%s: %r never appeared (exit %s: %s)" % (label, wait_for, p.returncode,
                                                                  err[-300:]))
    check(p.returncode == -sig, "%s: exit %s, expected death by signal %d (%s)"
          % (label, p.returncode, sig, err[-300:]))
    print("%s: signal %d with %s in the directory, %.2f s" % (label, sig, seen, time.time() - t))
    out_empty(label)


interrupt(signal.SIGINT, "m.vtu.tmp.", "SIGINT while writing the .vtu")
interrupt(signal.SIGTERM, "c.csv.tmp.", "SIGTERM while writing the connections (the .vtu committed)")
interrupt(signal.SIGHUP, "case.tmp.", "SIGHUP while writing the OpenFOAM case (.vtu and .csv committed)")


def xfsz(limit_kb, argv, label):
    t = time.time()
    cmd = "ulimit -c 0; ulimit -f %d; exec \"$@\"" % limit_kb
    p = subprocess.run(["/bin/bash", "-c", cmd, "bash"] + argv, capture_output=True, text=True,
                       timeout=300, cwd=TMP)
    check(p.returncode == -signal.SIGXFSZ, "%s: exit %s, expected death by SIGXFSZ (%s)"
          % (label, p.returncode, p.stderr[-300:]))
    print("%s: exit %s, %.2f s" % (label, p.returncode, time.time() - t))
    out_empty(label)


xfsz(2000, [BIN, "voronoi", SEEDS_BIG, "-o", o("m.vtu"), "--connections", o("c.csv"),
            "--no-validate", "--quiet", "--threads", "2"], "ulimit -f 2000: voronoi")
# icosphere: surface 71 kB, balls 120 kB, seeds 261 kB, then the .vtu 481 kB
xfsz(400, [BIN, "mesh", ICOSPHERE, "--surface", o("s.obj"), "--balls", o("b.csv"), "--seeds",
           o("s.csv"), "-o", o("m.vtu"), "--quiet", "--threads", "2"],
     "ulimit -f 400: mesh (surface, balls, seeds committed before the .vtu)")

# ---- a signal at a given moment of an OpenFOAM write into an existing case ----
# VC_TEST_SIGNAL_AT="EVENT:SUFFIX:SIGNAL" (apps/cli/cli_util.h) makes the
# program raise SIGNAL in itself when the library reports EVENT for an output
# path ending in SUFFIX. The case must be left as it was: its old polyMesh in
# place, byte for byte (even when the signal comes between the old one set
# aside and the new one renamed in), and no constant/ or system/ made by the
# run, no .old/.tmp directory, no other output.
CASES_DIR = os.path.join(TMP, "cases")
os.makedirs(CASES_DIR)
CASE = os.path.join(CASES_DIR, "case")
SEEDS_OTHER = os.path.join(TMP, "other.csv")
write_seeds(SEEDS_OTHER, 300, 3)


def snapshot(top):
    """{relative path: file bytes, or None for a directory} under top."""
    snap = {}
    for root, dirs, files in os.walk(top):
        for d in dirs:
            snap[os.path.relpath(os.path.join(root, d), top)] = None
        for f in files:
            with open(os.path.join(root, f), "rb") as fh:
                snap[os.path.relpath(os.path.join(root, f), top)] = fh.read()
    return snap


def foam_at(spec, sig, label):
    before = snapshot(CASES_DIR)
    env = dict(os.environ, VC_TEST_SIGNAL_AT="%s:%d" % (spec, sig))
    p = subprocess.run([BIN, "voronoi", SEEDS_OTHER, "-o", o("v.vtu"), "--connections", o("c.csv"),
                        "--foam", CASE, "--quiet"], capture_output=True, text=True, timeout=120, env=env)
    check(p.returncode == -sig, "%s: exit %s, expected death by signal %d (%s)"
          % (label, p.returncode, sig, p.stderr[-300:]))
    after = snapshot(CASES_DIR)
    changed = sorted(k for k in set(before) | set(after) if before.get(k, 0) != after.get(k, 0))
    check(not changed, "%s: the case changed: %s" % (label, changed[:12]))
    out_empty(label)


os.makedirs(CASE)  # an existing, empty case: constant/ and system/ are the run's
for spec, sig in (("mkdir:/case/constant", signal.SIGTERM), ("mkdir:/case/system", signal.SIGINT),
                  ("renaming:/case/constant/polyMesh", signal.SIGHUP),
                  ("committed:/case/constant/polyMesh", signal.SIGTERM),
                  ("committed:/case/system/controlDict", signal.SIGXFSZ)):
    foam_at(spec, sig, "signal %d at %s, into an empty case" % (sig, spec))
rc, err = run([BIN, "voronoi", SEEDS_SMALL, "-o", o("v.vtu"), "--foam", CASE, "--quiet"])
check(rc == 0, "a case with a polyMesh: exit %d (%s)" % (rc, err[-300:]))
os.remove(o("v.vtu"))
for spec, sig in (("add:/case/constant/polyMesh", signal.SIGTERM),
                  ("backup:/case/constant/polyMesh", signal.SIGINT),
                  ("renaming:/case/constant/polyMesh", signal.SIGTERM),
                  ("committed:/case/constant/polyMesh", signal.SIGHUP),
                  ("renaming:/c.csv", signal.SIGXFSZ)):
    foam_at(spec, sig, "signal %d at %s, into a case with a polyMesh" % (sig, spec))
# Not interrupted: the new polyMesh replaces the old one, nothing else left.
old_points = snapshot(CASES_DIR)[os.path.join("case", "constant", "polyMesh", "points")]
rc, err = run([BIN, "voronoi", SEEDS_OTHER, "-o", o("v.vtu"), "--foam", CASE, "--quiet"])
snap = snapshot(CASES_DIR)
check(rc == 0 and snap[os.path.join("case", "constant", "polyMesh", "points")] != old_points
      and sorted(k for k in snap if snap[k] is None) == ["case", "case/constant", "case/constant/polyMesh",
                                                           "case/system"],
      "a case replaced: exit %d, %s (%s)" % (rc, sorted(k for k in snap if snap[k] is None), err[-300:]))
os.remove(o("v.vtu"))
shutil.rmtree(CASE)

# A run that is not interrupted keeps its outputs (the tracking does not
# remove them at exit).
rc, err = run([BIN, "voronoi", SEEDS_SMALL, "-o", o("v.vtu"), "--connections", o("c.csv"),
               "--foam", o("case"), "--quiet"])
check(rc == 0 and sorted(os.listdir(OUT)) == ["c.csv", "case", "v.vtu"],
      "uninterrupted voronoi: exit %d, %s (%s)" % (rc, sorted(os.listdir(OUT)), err[-300:]))

sock.close()
shutil.rmtree(TMP, ignore_errors=True)
print("e2e_outputs: %d failures, %.1f s" % (len(failures), time.time() - T0))
sys.exit(1 if failures else 0)
