#!/usr/bin/env python3
"""The measuring aid of issue 21 (docs/performance.md, "(k)"): CFRD_WRITE_MATRIX and
tools/factor_floor.c, on the x1 Tianshengqiao-I bonded deck.

    python3 tools/check_matrix_market.py --cfrd build/debug-bin/cfrd --workdir DIR

Checks, each printing PASS or FAIL:
  - results unchanged: the run with CFRD_WRITE_MATRIX set writes the same HDF5 datasets, bit
    for bit, as the run without it (reference: that run);
  - the file is the matrix of the stage asked for: scipy.io.mmread (an independent reader)
    reads a square matrix with the stage's equations and nonzeros (its solver attributes
    neq and nnz in the HDF5 file), symmetric to 1e-12 (the E-B tangent of the bonded deck
    is);
  - tools/factor_floor.c, built here, solves A x = A 1 with UMFPACK (AMD, METIS) and with
    CHOLMOD (AMD, METIS, NESDIS) to max |x - 1| <= 1e-6 (reference: the closed form x = 1).
"""

import os
import re
import subprocess
import sys

import h5py
import scipy.io

from cfrdtools.checks import Checks, fresh, parser
from check_stop import compare_stages

STAGE = 3
DECK = "inputs/tianshengqiao-x1.dat"


def main():
    args = parser(__doc__, cfrd="build/debug-bin/cfrd",
                  workdir="build/check-matrix-market").parse_args()
    check = Checks("matrix-market")
    cfrd, work = os.path.abspath(args.cfrd), fresh(args.workdir)
    mtx = os.path.join(work, "stage.mtx")
    stem = os.path.splitext(os.path.basename(DECK))[0]
    env = {k: v for k, v in os.environ.items() if not k.startswith("CFRD_WRITE_MATRIX")}
    for folder, extra in (("plain", {}), ("written", {"CFRD_WRITE_MATRIX": mtx,
                                                      "CFRD_WRITE_MATRIX_STAGE": str(STAGE)})):
        subprocess.run([cfrd, "--quiet", "--out", os.path.join(work, folder), DECK],
                       env=dict(env, **extra), check=True)
    names, _, differences = compare_stages(os.path.join(work, "written", stem + ".h5"),
                                           os.path.join(work, "plain", stem + ".h5"))
    check("results-unchanged", not differences,
          f"{len(names)} stages, every dataset and attribute (timings aside) equal to the run "
          "without CFRD_WRITE_MATRIX" if not differences else "; ".join(differences[:4]))
    if not check("file-written", os.path.exists(mtx), mtx):
        return check.status
    with open(mtx) as f:
        f.readline()
        stage = re.search(r"stage (\d+) ", f.readline())
    check("stage", stage is not None and int(stage.group(1)) == STAGE,
          f"the file's comment names stage {stage.group(1) if stage else '?'}")
    a = scipy.io.mmread(mtx)              # an independent reader
    with h5py.File(os.path.join(work, "written", stem + ".h5"), "r") as f:
        solver = f["stages"][f"stage_{STAGE:04d}"]["solver"].attrs
        neq, nnz = int(solver["neq"]), int(solver["nnz"])
    check("order", a.shape == (neq, neq) and a.nnz == nnz,
          f"n = {a.shape[0]}, {a.nnz} entries; the stage's solver attributes: neq = {neq}, "
          f"nnz = {nnz}")
    a = a.tocsc()
    asym = abs(a - a.T).max() / abs(a).max()
    check("symmetric", asym <= 1e-12, f"max|a - a^T| / max|a| = {asym:.1e}")
    tool = os.path.join(work, "factor_floor")
    subprocess.run(["gcc", "-O2", "-o", tool, "tools/factor_floor.c", "-lcholmod", "-lumfpack",
                    "-lsuitesparseconfig", "-lm"], check=True)
    out = subprocess.run([tool, "--repeat", "1", mtx], capture_output=True, text=True,
                         env=dict(env, OPENBLAS_NUM_THREADS="1"))
    errors = [float(x) for x in re.findall(r"max\|x - 1\| ([0-9.e+-]+)", out.stdout)]
    check("factor-floor-solves", out.returncode == 0 and len(errors) == 5 and
          max(errors) <= 1e-6, "UMFPACK AMD / METIS, CHOLMOD AMD / METIS / NESDIS: "
          f"max|x - 1| {errors} (closed form x = 1)")
    return check.status


if __name__ == "__main__":
    sys.exit(main())
