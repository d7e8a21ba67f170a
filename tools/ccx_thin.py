#!/usr/bin/env python3
"""Peer check of the thin-layer interface against CalculiX (issue 6, section 4).

  python3 tools/ccx_thin.py --cfrd CFRD --workdir DIR

Two elastic blocks (8 x 2 quads each, 8 m wide, 2 m high, E 50 MPa, nu 0.25, 20 kN/m3) with a
0.1 m thin layer between them (E 1 MPa, nu 0.3, weightless: the paper's soft layer), under
their own weight and a 100 kPa surface load on the right half of the top, bottom fixed. cfrd
reads the layer from INTERFACE cards (TYPE THIN, built from node pairs); CalculiX gets the same
quads as CPE4. Asserted: max |u_cfrd - u_ccx| / max |u_ccx| <= 1e-6 (ccx prints 7 digits).
"""
import argparse
import os
import sys

import numpy as np

import embankment as emb
from cfrdtools import results, runner
from cfrdtools.ccx import run_ccx

NX, NY, W, H, D = 8, 2, 8.0, 2.0, 0.1
BLOCK = (5.0e4, 0.25, 20.0)
LAYER = (1.0e3, 0.3, 0.0)
P = 100.0


def mesh():
    xy, conn, mat = [], [], []
    for block, y0 in ((0, 0.0), (1, H + D)):
        for j in range(NY + 1):
            for i in range(NX + 1):
                xy.append((W * i / NX, y0 + H * j / NY))
    nb = (NX + 1) * (NY + 1)
    for block in (0, 1):
        for j in range(NY):
            for i in range(NX):
                a = block * nb + j * (NX + 1) + i + 1
                conn.append((a, a + 1, a + NX + 2, a + NX + 1))
                mat.append(1)
    pairs = [(NY * (NX + 1) + i + 1, nb + i + 1) for i in range(NX + 1)]
    layer = [(b0, b1, t1, t0) for (b0, t0), (b1, t1) in zip(pairs, pairs[1:])]
    top = [2 * NX * NY - NX + i for i in range(NX)]          # 0-based elements, top row
    return np.array(xy), conn, mat, pairs, layer, top


def write_cfrd(path, xy, conn, mat, pairs, top):
    f, r, a = emb.fmt_int, emb.fmt_real, emb.fmt_alpha
    out = ["TITLE     thin-layer peer: two blocks and a soft layer", "NODES"]
    out += [f(k) + " " * 10 + r(x) + r(y) for k, (x, y) in enumerate(xy, 1)]
    out.append("ELEMENTS")
    out += [f(e) + "".join(f(n) for n in c) + f(m) for e, (c, m) in enumerate(zip(conn, mat), 1)]
    out += ["MATERIALS", f(1) + a("ELASTIC") + "block", r(BLOCK[0]) + r(BLOCK[1]) + r(BLOCK[2]),
            f(2) + a("ELASTIC") + "thin layer", r(LAYER[0]) + r(LAYER[1]) + r(LAYER[2]),
            "INTERFACE", f(1) + f(pairs[0][0]) + f(pairs[0][1]) + f(NX) + f(1) + f(1) + f(2)
            + a("THIN"), "BOUNDARY", f(1) + f(NX + 1) + f(1) + f(1) + f(1), "LOADS", "GRAVITY"]
    out += [a("PRESSURE") + f(e + 1) + f(3) + r(P) for e in top if e % NX >= NX // 2]
    out.append("END")
    open(path, "w").write("\n".join(out) + "\n")


def write_ccx(path, xy, conn, mat, layer, top):
    out = ["*NODE"] + [f"{k}, {emb.ccx_real(x)}, {emb.ccx_real(y)}, 0.0"
                       for k, (x, y) in enumerate(xy, 1)]
    out.append("*ELEMENT, TYPE=CPE4, ELSET=EBLOCK")
    out += [f"{e}, {a}, {b}, {c}, {d}" for e, (a, b, c, d) in enumerate(conn, 1)]
    out.append("*ELEMENT, TYPE=CPE4, ELSET=ELAYER")
    out += [f"{len(conn) + k}, {a}, {b}, {c}, {d}" for k, (a, b, c, d) in enumerate(layer, 1)]
    out += ["*NSET, NSET=NALL, GENERATE", f"1, {len(xy)}, 1",
            "*NSET, NSET=NBASE, GENERATE", f"1, {NX + 1}, 1",
            "*MATERIAL, NAME=MBLOCK", "*ELASTIC", f"{BLOCK[0]!r}, {BLOCK[1]!r}", "*DENSITY",
            emb.ccx_real(BLOCK[2] / 9.81), "*SOLID SECTION, ELSET=EBLOCK, MATERIAL=MBLOCK", "1.0",
            "*MATERIAL, NAME=MLAYER", "*ELASTIC", f"{LAYER[0]!r}, {LAYER[1]!r}", "*DENSITY",
            "1e-30", "*SOLID SECTION, ELSET=ELAYER, MATERIAL=MLAYER", "1.0",
            "*BOUNDARY", "NBASE, 1, 2", "*STEP", "*STATIC", "*DLOAD",
            "EBLOCK, GRAV, 9.81, 0., -1., 0."]
    out += [f"{e + 1}, P3, {P!r}" for e in top if e % NX >= NX // 2]
    out += ["*NODE PRINT, NSET=NALL", "U", "*END STEP"]
    open(path, "w").write("\n".join(out) + "\n")


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--cfrd", required=True)
    parser.add_argument("--workdir", default="build/ccx-thin")
    args = parser.parse_args(argv)
    os.makedirs(args.workdir, exist_ok=True)
    xy, conn, mat, pairs, layer, top = mesh()
    deck = os.path.join(args.workdir, "thin.dat")
    write_cfrd(deck, xy, conn, mat, pairs, top)
    write_ccx(os.path.join(args.workdir, "thin_ccx.inp"), xy, conn, mat, layer, top)
    run = runner.run(args.cfrd, deck, check=False)
    if run.returncode != 0:
        print(f"FAIL peer/ccx-thin-layer: cfrd exit {run.returncode}: {run.stderr[:300]}")
        return 1
    run_ccx(args.workdir, "thin_ccx")
    u_ccx = emb.ccx_displacement_array(os.path.join(args.workdir, "thin_ccx.dat"), len(xy))
    with results.open_results(runner.h5_of(deck)) as h5:
        u = results.read(h5, "displacement")
    u = u if u.shape == u_ccx.shape else u.T
    diff = float(np.abs(u - u_ccx).max() / np.abs(u_ccx).max())
    good = diff <= 1e-6
    print(("PASS" if good else "FAIL") + f" peer/ccx-thin-layer: {len(layer)} thin-layer quads"
          f" from INTERFACE pairs vs CalculiX CPE4: max |u_cfrd - u_ccx| / max |u_ccx| ="
          f" {diff:.2e} (tol 1e-6; max |u| {np.abs(u_ccx).max():.4e} m)")
    return 0 if good else 1


if __name__ == "__main__":
    sys.exit(main())
