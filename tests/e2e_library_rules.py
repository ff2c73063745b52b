"""The library's contract with its callers (issue 15), checked on the sources:

 - the library owns no process-wide state a caller owns: no MPI_Init, no
   setenv, no omp_set_num_threads, no abort(), no exit(), no getenv(), no
   atexit, and it writes to no stream (no fprintf(stderr / stdout, printf,
   puts, perror) in vorocrust/ (comments and string literals aside);
 - every public header (include/vorocrust/*.h) compiles on its own, as C11
   and as C++ (extern "C"), with -Wall -Wextra -Werror, and includes no
   internal header;
 - vorocrust.h declares the pipeline call and the version API.

Environment: VC_SOURCE (the repository), VC_BIN (the vorocrust program, whose
directory is the build directory holding include/vorocrust/version.h).
"""
import glob
import os
import re
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.join(os.environ["VC_SOURCE"], "tests"))
from e2eutil import check, failures  # noqa: E402

SOURCE = os.environ["VC_SOURCE"]
BUILD = os.path.dirname(os.environ["VC_BIN"])

FORBIDDEN = [
    (r"\bMPI_Init\s*\(", "MPI_Init"),
    (r"\bMPI_Init_thread\s*\(", "MPI_Init_thread"),
    (r"\bMPI_Finalize\s*\(", "MPI_Finalize"),
    (r"\bsetenv\s*\(", "setenv"),
    (r"\bputenv\s*\(", "putenv"),
    (r"\bomp_set_num_threads\s*\(", "omp_set_num_threads"),
    (r"(?<![\w.>])abort\s*\(", "abort()"),
    (r"(?<![\w.>])exit\s*\(", "exit()"),
    (r"\bgetenv\s*\(", "getenv()"),
    (r"\batexit\s*\(", "atexit"),
    (r"\bfprintf\s*\(\s*std(err|out)\b", "fprintf to stderr/stdout"),
    (r"\bfputs\s*\([^;]*,\s*std(err|out)\s*\)", "fputs to stderr/stdout"),
    (r"(?<![\w.>])printf\s*\(", "printf"),
    (r"(?<![\w.>])puts\s*\(", "puts"),
    (r"\bperror\s*\(", "perror"),
    (r"\bstd::c(out|err)\b", "std::cout/cerr"),
]


def code_only(text):
    """The text with comments and string and character literals blanked."""
    out, i, n = [], 0, len(text)
    while i < n:
        c = text[i]
        if text.startswith("/*", i):
            j = text.find("*/", i + 2)
            j = n if j < 0 else j + 2
            out.append(re.sub(r"[^\n]", " ", text[i:j]))
            i = j
        elif text.startswith("//", i):
            j = text.find("\n", i)
            j = n if j < 0 else j
            out.append(" " * (j - i))
            i = j
        elif c in "\"'":
            j = i + 1
            while j < n and text[j] != c:
                j += 2 if text[j] == "\\" else 1
            out.append(c + " " * (min(j, n) - i - 1) + c)
            i = j + 1
        else:
            out.append(c)
            i += 1
    return "".join(out)


sources = sorted(glob.glob(os.path.join(SOURCE, "vorocrust", "**", "*.[ch]"), recursive=True) +
                 glob.glob(os.path.join(SOURCE, "vorocrust", "**", "*.cpp"), recursive=True))
check(len(sources) > 50, "only %d library sources found under %s/vorocrust" % (len(sources), SOURCE))
hits = []
for path in sources:
    with open(path, encoding="utf-8", errors="replace") as f:
        code = code_only(f.read())
    for pattern, what in FORBIDDEN:
        for m in re.finditer(pattern, code):
            line = code.count("\n", 0, m.start()) + 1
            hits.append("%s:%d: %s" % (os.path.relpath(path, SOURCE), line, what))
for h in hits:
    print("forbidden in the library:", h, file=sys.stderr)
check(not hits, "%d forbidden calls in vorocrust/ (see above)" % len(hits))
print("library sources: %d files, %d forbidden calls" % (len(sources), len(hits)))

headers = sorted(glob.glob(os.path.join(SOURCE, "include", "vorocrust", "*.h")))
check(any(h.endswith("vorocrust.h") for h in headers), "include/vorocrust/vorocrust.h is missing")
incs = ["-I", os.path.join(SOURCE, "include"), "-I", os.path.join(BUILD, "include")]
with tempfile.TemporaryDirectory() as tmp:
    for h in headers:
        name = os.path.basename(h)
        with open(h) as f:
            text = f.read()
        for inc in re.findall(r'#include\s+"([^"]+)"', text):
            check(inc.startswith("vorocrust/"), "%s includes the internal header %s" % (name, inc))
        for lang, compiler, flags in (("c", "cc", ["-std=c11"]), ("c++", "c++", ["-std=c++17"])):
            src = os.path.join(tmp, "one." + ("c" if lang == "c" else "cpp"))
            with open(src, "w") as f:
                f.write('#include "vorocrust/%s"\nint vc_header_check_%s;\n' % (name, lang.replace("+", "p")))
            p = subprocess.run([compiler, "-fsyntax-only", "-Wall", "-Wextra", "-Werror"] + flags + incs +
                               [src], capture_output=True, text=True, timeout=120)
            check(p.returncode == 0, "%s does not compile alone as %s: %s" % (name, lang, p.stderr[-800:]))
    print("public headers: %d, each compiled alone as C11 and C++17" % len(headers))

with open(os.path.join(SOURCE, "include", "vorocrust", "vorocrust.h")) as f:
    api = f.read()
for decl in ("int vc_mesh(const vc_surface *", "void vc_mesh_options_default(vc_mesh_options *",
             "void vc_mesh_result_free(vc_mesh_result *", "const char *vc_version(void)",
             "int vc_version_number(void)"):
    check(decl in api, "vorocrust.h does not declare %s" % decl)
with open(os.path.join(BUILD, "include", "vorocrust", "version.h")) as f:
    version = f.read()
for macro in ("VC_VERSION_MAJOR", "VC_VERSION_MINOR", "VC_VERSION_PATCH", "VC_VERSION_STRING",
              "VC_VERSION_NUMBER"):
    check("#define " + macro in version, "version.h does not define %s" % macro)

if failures:
    print("%d failure(s)" % len(failures), file=sys.stderr)
    sys.exit(1)
print("e2e_library_rules: all checks passed")
