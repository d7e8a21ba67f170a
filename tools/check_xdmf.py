#!/usr/bin/env python3
"""Read cfrd's DECK.xmf with an independent XDMF reader (meshio's TimeSeriesReader, the reader
ParaView-style time series are checked with) and compare what it returns with the HDF5
datasets, exactly:

  steps   one time step per stage: as many as the deck's STAGES cards (counted here from the
          deck text), at times 1, 2, ..., N;
  mesh    the points are /mesh/coordinates, one block of quads whose connectivity is
          /mesh/connectivity - 1 (XDMF numbers from 0), as many cells as the mesh;
  fields  at every step, the node vectors displacement and displacement_total are the stage's
          (nnode, 2) datasets padded with z = 0, and the cell fields stress_centroid,
          principal, stress_level, active, material equal theirs.

    python3 tools/check_xdmf.py RESULTS.xmf DECK          (an existing run)
    python3 tools/check_xdmf.py --run CFRD --workdir DIR  (what make test runs: the
                                                           Goodman-joint Tianshengqiao-I deck)
"""

import pathlib
import subprocess
import sys

import h5py
import meshio
import numpy as np

from cfrdtools.checks import Checks, parser
from cfrdtools.decks import groups

DECK = "inputs/tianshengqiao-x1-joint.dat"
check = Checks("xdmf")


def check_files(xmf, deck):
    cards = dict(groups(pathlib.Path(deck).read_text())).get("STAGES", [])
    # (1 without STAGES: the LOADS stage)
    nstage = sum(ln[:10].strip().upper() in ("FILL", "LOAD", "RESET", "WATER")
                 for ln in cards) or 1
    with h5py.File(pathlib.Path(xmf).with_suffix(".h5"), "r") as h5, \
            meshio.xdmf.TimeSeriesReader(xmf) as reader:
        points, cells = reader.read_points_cells()
        xy, conn = h5["mesh/coordinates"][...], h5["mesh/connectivity"][...]
        check("steps", reader.num_steps == nstage == len(h5["stages"]), f"{reader.num_steps} "
              f"time steps read, {nstage} stage cards in {deck}, {len(h5['stages'])} stage "
              f"groups in the HDF5 file (equal)")
        quads = [c for c in cells if c.type == "quad"]
        check("mesh", len(cells) == 1 and len(quads) == 1 and np.array_equal(
            quads[0].data, conn - 1) and np.array_equal(points, xy), f"{points.shape[0]} "
              f"points, {quads[0].data.shape[0] if quads else 0} quads read; HDF5 mesh "
              f"{xy.shape[0]} nodes, {conn.shape[0]} elements (connectivity - 1, exact)")
        bad, times = [], []
        node_fields = ("displacement", "displacement_total")
        cell_fields = ("stress_centroid", "principal", "stress_level", "active")
        for k in range(reader.num_steps):
            t, point_data, cell_data = reader.read_data(k)
            times.append(t)
            g = h5["stages"][f"stage_{k + 1:04d}"]
            bad += [f"{name} at step {k}" for name in node_fields if not (
                point_data[name].shape == (xy.shape[0], 3) and np.array_equal(
                    point_data[name][:, :2], g[name][...]) and not point_data[name][:, 2].any())]
            bad += [f"{name} at step {k}" for name in cell_fields
                    if not np.array_equal(cell_data[name][0], g[name][...])]
            if not np.array_equal(cell_data["material"][0], h5["mesh/material"][...]):
                bad.append(f"material at step {k}")
        check("times", times == [float(s) for s in range(1, nstage + 1)],
              f"times {times[0]:g} .. {times[-1]:g} (the stage numbers)")
        fields = ", ".join(node_fields + cell_fields)
        check("fields", not bad, f"{reader.num_steps} steps x ({fields}, material) equal to "
              f"the HDF5 datasets bit for bit"
              + (f"; differ: {', '.join(bad[:5])}" if bad else ""))


def main(argv=None):
    ap = parser(__doc__, workdir="build/xdmf-check")
    ap.add_argument("xmf", nargs="?")
    ap.add_argument("deck", nargs="?")
    ap.add_argument("--run", metavar="CFRD")
    args = ap.parse_args(argv)
    if args.run:
        work = pathlib.Path(args.workdir)
        work.mkdir(parents=True, exist_ok=True)
        run = subprocess.run([args.run, "--quiet", "--out", str(work), DECK],
                             capture_output=True, text=True)
        if run.returncode != 0:
            check("run", False, f"{args.run} {DECK}: exit {run.returncode}: {run.stderr[-300:]}")
            return 1
        xmf, deck = work / (pathlib.Path(DECK).stem + ".xmf"), DECK
    elif args.xmf and args.deck:
        xmf, deck = args.xmf, args.deck
    else:
        ap.error("give RESULTS.xmf DECK, or --run CFRD")
    check_files(str(xmf), deck)
    return check.status


if __name__ == "__main__":
    sys.exit(main())
