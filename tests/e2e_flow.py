"""End-to-end flow test (issue 20): laminar flow through a generated duct,
solved by OpenFOAM's simpleFoam on the mesher's cases.

The duct is 4 x 1 x 1 with its inlet (x = 0), outlet (x = 4) and walls
named as OBJ groups, as a user would give them (the patches feature). It is
meshed with `--max-size 0.12` (about 9,000 cells) twice: the exact Voronoi
cells (`--foam-max-skew 0`) and the default case (skew faces collapsed).
On each, simpleFoam with the settings of OpenFOAM's tutorials (SIMPLEC,
linearUpwind for U, GAMG for p, relaxation 0.9), U = (1, 0, 0) at the
inlet, p = 0 at the outlet, no-slip walls, nu = 0.01 (Reynolds number 100
on the duct's width), residual control 1e-6 on p and U. Checked:
 - simpleFoam ends normally with "SIMPLE solution converged" well before
   the iteration limit;
 - inflow equals outflow: the flux phi summed over the outlet against the
   inlet's (-1), within 1e-6 relative; no flux through the walls;
 - the flow is the duct's: the largest axial velocity between 1.3 and 2.5
   (2.1 for the fully developed square-duct profile; the entrance length
   at Re 100 is about the duct's length), no reverse axial flow below
   -0.05, and the pressure falls from inlet to outlet (its largest value
   positive).
Needs OpenFOAM (checkMesh's environment, e2eutil.find_checkmesh).
Environment: VC_BIN, VC_TMP, VC_SOURCE."""
import os
import re
import shutil
import subprocess
import sys

sys.path.insert(0, os.path.join(os.environ["VC_SOURCE"], "tests"))
import e2eutil  # noqa: E402
from e2eutil import FOAM_HEADER as H, check, failures  # noqa: E402

BIN = os.environ["VC_BIN"]
TMP = os.path.join(os.environ.get("VC_TMP", "/tmp"), "e2e_flow")
shutil.rmtree(TMP, ignore_errors=True)
os.makedirs(TMP)
CHECKMESH, FOAM_ENV = e2eutil.find_checkmesh()
SIMPLEFOAM = os.path.join(os.path.dirname(CHECKMESH), "simpleFoam")
MAX_ITER = 2000

CASE_FILES = {
    "0/U": H % ("volVectorField", "U") + "dimensions [0 1 -1 0 0 0 0];\n"
    "internalField uniform (0 0 0);\nboundaryField\n{\n"
    "    inlet { type fixedValue; value uniform (1 0 0); }\n"
    "    outlet { type zeroGradient; }\n    walls { type noSlip; }\n}\n",
    "0/p": H % ("volScalarField", "p") + "dimensions [0 2 -2 0 0 0 0];\n"
    "internalField uniform 0;\nboundaryField\n{\n    inlet { type zeroGradient; }\n"
    "    outlet { type fixedValue; value uniform 0; }\n    walls { type zeroGradient; }\n}\n",
    "constant/transportProperties": H % ("dictionary", "transportProperties")
    + "transportModel Newtonian;\nnu 0.01;\n",
    "constant/turbulenceProperties": H % ("dictionary", "turbulenceProperties")
    + "simulationType laminar;\n",
    "system/controlDict": H % ("dictionary", "controlDict")
    + "application simpleFoam;\nstartFrom startTime;\nstartTime 0;\nstopAt endTime;\n"
    "endTime %d;\ndeltaT 1;\nwriteControl timeStep;\nwriteInterval %d;\nwriteFormat ascii;\n"
    "writePrecision 16;\ntimeFormat general;\n" % (MAX_ITER, MAX_ITER),
    "system/fvSchemes": H % ("dictionary", "fvSchemes")
    + "ddtSchemes { default steadyState; }\ngradSchemes { default Gauss linear; }\n"
    "divSchemes { default none; div(phi,U) bounded Gauss linearUpwind grad(U);\n"
    "             div((nuEff*dev2(T(grad(U))))) Gauss linear; }\n"
    "laplacianSchemes { default Gauss linear corrected; }\n"
    "interpolationSchemes { default linear; }\nsnGradSchemes { default corrected; }\n",
    "system/fvSolution": H % ("dictionary", "fvSolution")
    + "solvers\n{\n    p { solver GAMG; tolerance 1e-08; relTol 0.1; smoother GaussSeidel; }\n"
    "    U { solver smoothSolver; smoother symGaussSeidel; tolerance 1e-08; relTol 0.1; }\n}\n"
    "SIMPLE\n{\n    nNonOrthogonalCorrectors 0;\n    consistent yes;\n"
    "    residualControl { p 1e-6; U 1e-6; }\n}\n"
    "relaxationFactors\n{\n    equations { U 0.9; \".*\" 0.9; }\n}\n",
}


def run_case(tag, extra):
    case = os.path.join(TMP, tag)
    vtu = os.path.join(TMP, tag + ".vtu")
    rc, out, err = e2eutil.run([BIN, "mesh", os.path.join(TMP, "duct.obj"), "-o", vtu, "--foam", case,
                                "--patch-type", "walls=wall", "--max-size", "0.12"] + extra, 300)
    if not check(rc == 0, "%s: mesh exit %d: %s" % (tag, rc, err[-1500:])):
        return
    cells = re.search(r"volume mesh: (\d+) cells", err)
    e2eutil.write_foam_files(case, CASE_FILES)
    p = subprocess.run([SIMPLEFOAM, "-case", case], capture_output=True, text=True, env=FOAM_ENV,
                       timeout=600)
    log = p.stdout + p.stderr
    with open(os.path.join(TMP, tag + ".simpleFoam.log"), "w") as f:
        f.write(log)
    m = re.search(r"SIMPLE solution converged in (\d+) iterations", log)
    if not check(p.returncode == 0 and m is not None and int(m.group(1)) < MAX_ITER // 2,
                 "%s: simpleFoam exit %d, %s: %s" % (tag, p.returncode, m and m.group(0), log[-1500:])):
        return
    last = m.group(1)
    phi = os.path.join(case, last, "phi")
    f_in = e2eutil.foam_patch_sum(phi, "inlet")
    f_out = e2eutil.foam_patch_sum(phi, "outlet")
    f_wall = e2eutil.foam_patch_sum(phi, "walls")
    if not check(None not in (f_in, f_out, f_wall), "%s: no flux on the patches in %s" % (tag, phi)):
        return
    imbalance = abs(f_in + f_out) / abs(f_in)
    check(abs(f_in + 1) < 1e-9 and imbalance <= 1e-6 and f_wall == 0,
          "%s: inflow %.12g, outflow %.12g (imbalance %.3g), walls %g" % (tag, f_in, f_out, imbalance,
                                                                           f_wall))
    U = e2eutil.foam_internal_field(os.path.join(case, last, "U"))
    P = e2eutil.foam_internal_field(os.path.join(case, last, "p"))
    if check(U is not None and P is not None, "%s: no U or p field" % tag):
        umax = max(u[0] for u in U)
        umin = min(u[0] for u in U)
        check(1.3 <= umax <= 2.5 and umin >= -0.05 and max(P) > 0,
              "%s: axial velocity %.3g to %.3g, pressure up to %.3g" % (tag, umin, umax, max(P)))
        print("%s: %s cells; simpleFoam converged in %s iterations; inflow %.10g, outflow %.10g "
              "(imbalance %.2g); axial velocity %.3f to %.3f, pressure drop %.4g"
              % (tag, cells.group(1) if cells else "?", last, -f_in, f_out, imbalance, umin, umax,
                 max(P)), flush=True)


e2eutil.duct_obj(os.path.join(TMP, "duct.obj"))
run_case("exact", ["--foam-max-skew", "0"])
run_case("collapsed", [])
if failures:
    print("e2e_flow: %d failure(s)" % len(failures), file=sys.stderr)
sys.exit(1 if failures else 0)
