#!/usr/bin/env python3
"""Peer check of the thin-layer interface against CalculiX (issue 6, section 4).

  python3 tools/ccx_thin.py --cfrd CFRD --workdir DIR

Two elastic blocks (8 x 2 quads each, 8 m wide, 2 m high, E 50 MPa, nu 0.25, 20 kN/m3) with a
0.1 m thin layer between them (E 1 MPa, nu 0.3, weightless: the paper's soft layer), under
their own weight and a 100 kPa surface load on the right half of the top, bottom fixed. cfrd
reads the layer from INTERFACE cards (TYPE THIN, built from node pairs); CalculiX gets the same
quads as CPE4. Asserted: max |u_cfrd - u_ccx| / max |u_ccx| <= 1e-6 (ccx prints 7 digits).
"""
import os
import sys

import numpy as np

from cfrdtools import ccx, results, runner
from cfrdtools.checks import Checks, parser
from cfrdtools.decks import fmt_alpha as a, fmt_int as f, fmt_real as r

NX, NY, W, H, D = 8, 2, 8.0, 2.0, 0.1
BLOCK = (5.0e4, 0.25, 20.0)
LAYER = (1.0e3, 0.3, 0.0)
P = 100.0


def mesh():
    xy = [(W * i / NX, y0 + H * j / NY) for y0 in (0.0, H + D) for j in range(NY + 1)
          for i in range(NX + 1)]
    nb = (NX + 1) * (NY + 1)
    conn = [(a_, a_ + 1, a_ + NX + 2, a_ + NX + 1) for block in (0, 1) for j in range(NY)
            for i in range(NX) for a_ in [block * nb + j * (NX + 1) + i + 1]]
    pairs = [(NY * (NX + 1) + i + 1, nb + i + 1) for i in range(NX + 1)]
    layer = [(b0, b1, t1, t0) for (b0, t0), (b1, t1) in zip(pairs, pairs[1:])]
    loaded = [e for e in range(2 * NX * NY - NX, 2 * NX * NY) if e % NX >= NX // 2]  # 0-based
    return np.array(xy), conn, pairs, layer, loaded


def write_cfrd(path, xy, conn, pairs, loaded):
    out = ["TITLE     thin-layer peer: two blocks and a soft layer", "NODES"]
    out += [f(k) + " " * 10 + r(x) + r(y) for k, (x, y) in enumerate(xy, 1)]
    out += ["ELEMENTS"] + [f(e) + "".join(f(n) for n in c) + f(1) for e, c in enumerate(conn, 1)]
    out += ["MATERIALS", f(1) + a("ELASTIC") + "block", r(BLOCK[0]) + r(BLOCK[1]) + r(BLOCK[2]),
            f(2) + a("ELASTIC") + "thin layer", r(LAYER[0]) + r(LAYER[1]) + r(LAYER[2]),
            "INTERFACE", f(1) + f(pairs[0][0]) + f(pairs[0][1]) + f(NX) + f(1) + f(1) + f(2)
            + a("THIN"), "BOUNDARY", f(1) + f(NX + 1) + f(1) + f(1) + f(1), "LOADS", "GRAVITY"]
    runner.write_deck(path, out + [a("PRESSURE") + f(e + 1) + f(3) + r(P) for e in loaded]
                      + ["END"])


def write_ccx(path, xy, conn, layer, loaded):
    out = ccx.node_cards(xy) + ccx.element_cards("EBLOCK", conn, range(1, len(conn) + 1))
    out += ccx.element_cards("ELAYER", layer, range(len(conn) + 1, len(conn) + len(layer) + 1))
    out += ["*NSET, NSET=NALL, GENERATE", f"1, {len(xy)}, 1",
            "*NSET, NSET=NBASE, GENERATE", f"1, {NX + 1}, 1"]
    out += ccx.material_cards("MBLOCK", *BLOCK, elset="EBLOCK")
    out += ccx.material_cards("MLAYER", *LAYER, elset="ELAYER", density="1e-30")
    out += ["*BOUNDARY", "NBASE, 1, 2", "*STEP", "*STATIC", "*DLOAD",
            "EBLOCK, GRAV, 9.81, 0., -1., 0."] + [f"{e + 1}, P3, {P!r}" for e in loaded]
    runner.write_deck(path, out + ["*NODE PRINT, NSET=NALL", "U", "*END STEP"])


def main(argv=None):
    args = parser(__doc__, cfrd=True, workdir="build/ccx-thin").parse_args(argv)
    os.makedirs(args.workdir, exist_ok=True)
    check = Checks("peer")
    xy, conn, pairs, layer, loaded = mesh()
    deck = os.path.join(args.workdir, "thin.dat")
    write_cfrd(deck, xy, conn, pairs, loaded)
    write_ccx(os.path.join(args.workdir, "thin_ccx.inp"), xy, conn, layer, loaded)
    run = runner.run(args.cfrd, deck, check=False)
    if run.returncode != 0:
        check("ccx-thin-layer", False, f"cfrd exit {run.returncode}: {run.stderr[:300]}")
        return 1
    ccx.run_ccx(args.workdir, "thin_ccx")
    u_ccx = ccx.displacement_array(os.path.join(args.workdir, "thin_ccx.dat"), len(xy))
    with results.open_results(runner.h5_of(deck)) as h5:
        u = results.read(h5, "displacement")
    u = u if u.shape == u_ccx.shape else u.T
    diff = float(np.abs(u - u_ccx).max() / np.abs(u_ccx).max())
    check("ccx-thin-layer", diff <= 1e-6, f"{len(layer)} thin-layer quads from INTERFACE pairs"
          f" vs CalculiX CPE4: max |u_cfrd - u_ccx| / max |u_ccx| = {diff:.2e} (tol 1e-6; max"
          f" |u| {np.abs(u_ccx).max():.4e} m)")
    return check.status


if __name__ == "__main__":
    sys.exit(main())
