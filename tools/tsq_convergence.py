#!/usr/bin/env python3
"""Mesh convergence of the Tianshengqiao-I results (issue 5, docs/tianshengqiao.md).

Reads the results of the x1, x2, x4 (and x8) runs of the midpoint deck (written by
`python3 tools/bench.py --only-tianshengqiao`, or by --run here) and prints a markdown table
of the August 1999 state: the maximum settlement since placement and where it is, the largest
settlement on the mid-height row line (El. 709.33 m, a line of every mesh), the gauges, and
the largest horizontal displacements up- and downstream. The change between successive
meshes, and a Richardson estimate from the last three, say how far each figure is from the
converged one.

    python3 tools/tsq_convergence.py [--dir build/bench-tsq] [--run bin/cfrd] [--refine 1,2,4]
"""

import argparse
import os
import subprocess
import sys

import h5py
import numpy as np
from cfrdtools import results

HERE = os.path.dirname(os.path.abspath(__file__))
MID_ROW = 709.3333333


def figures(path):
    with h5py.File(path) as f:
        x = f["mesh/coordinates"][...]
        stage = results.last_stage(f)
        u = stage["displacement_total"][...]
        names = [n.decode().strip() if isinstance(n, bytes) else str(n).strip()
                 for n in f["gauges/names"][...]]
        nodes = f["gauges/nodes"][...] - 1
        nelem = f["mesh/connectivity"].shape[0]
    k = int(np.argmin(u[:, 1]))
    row = np.abs(x[:, 1] - MID_ROW) < 1e-3
    out = {"elements": nelem, "max settlement m": -u[k, 1],
           "at x, El. m": f"{x[k, 0]:.1f}, {x[k, 1]:.1f}",
           "max settl. El. 709.3 m": float(np.max(-u[row, 1]))}
    for name, node in zip(names, nodes):
        if "-V" in name:
            out[f"{name} settl. m"] = -u[node, 1]
        else:
            out[f"{name} ux m"] = u[node, 0]
    out["max ux downstream m"] = float(u[:, 0].max())
    out["max ux upstream m"] = float(-u[:, 0].min())
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--dir", default="build/bench-tsq")
    ap.add_argument("--run", help="cfrd program: generate and run the decks first")
    ap.add_argument("--refine", default="1,2,4,8")
    args = ap.parse_args()
    refine = [int(r) for r in args.refine.split(",")]
    rows = []
    for r in refine:
        deck = os.path.join(args.dir, f"tianshengqiao-x{r}-midpoint.dat")
        if args.run:
            os.makedirs(args.dir, exist_ok=True)
            subprocess.run([sys.executable, os.path.join(HERE, "tianshengqiao.py"), "--refine",
                            str(r), "--deck", deck], check=True)
            subprocess.run([args.run, "--quiet", deck], check=True)
        h5 = deck[:-4] + ".h5"
        if os.path.exists(h5):
            rows.append((r, figures(h5)))
    keys = list(rows[0][1])
    print("| quantity | " + " | ".join(f"x{r}" for r, _ in rows) + " | Richardson |")
    print("|:---|" + "---:|" * (len(rows) + 1))
    for key in keys:
        vals = [f[key] for _, f in rows]
        cells = [v if isinstance(v, str) else (f"{v:.4f}" if isinstance(v, float) else str(v))
                 for v in vals]
        rich = "-"
        if len(vals) >= 3 and all(isinstance(v, float) for v in vals[-3:]):
            a, b, c = vals[-3:]
            d1, d2 = b - a, c - b
            if abs(d1) > 1e-12 and 0.0 < d2 / d1 < 1.0:
                ratio = d2 / d1
                rich = f"{c + d2 * ratio / (1 - ratio):.4f}"
        print(f"| {key} | " + " | ".join(cells) + f" | {rich} |")


if __name__ == "__main__":
    main()
