#!/usr/bin/env python3
"""Read cfrd's DECK.xmf with an independent XDMF reader (meshio's TimeSeriesReader, the
reader ParaView-style time series are checked with) and compare what it returns with the
HDF5 datasets, exactly:

  steps      one time step per stage: as many as the deck's STAGES cards (counted here from
             the deck text), at times 1, 2, ..., N;
  mesh       the points are /mesh/coordinates, one block of quads whose connectivity is
             /mesh/connectivity - 1 (XDMF numbers from 0), as many cells as the mesh;
  fields     at every step, the node vectors displacement and displacement_total are the
             stage's (nnode, 2) datasets padded with z = 0, and the cell fields
             stress_centroid, principal, stress_level, active, material equal theirs.

    python3 tools/check_xdmf.py RESULTS.xmf DECK          (an existing run)
    python3 tools/check_xdmf.py --run CFRD --workdir DIR  (what make test runs)

--run runs the Goodman-joint Tianshengqiao-I deck (body quads and zero-thickness joints).
Prints one PASS/FAIL line per check; exit status 1 if any failed.
"""

import argparse
import pathlib
import subprocess
import sys

import h5py
import meshio
import numpy as np

DECK = "inputs/tianshengqiao-x1-joint.dat"


def stage_cards(deck):
    """Number of stage cards of the deck's STAGES group (1 without one: the LOADS stage)."""
    count, inside = 0, False
    for line in pathlib.Path(deck).read_text().splitlines():
        if not line.strip() or line.startswith("*"):
            continue
        word = line[:10].strip().upper()
        if not line[0].isspace() and word in ("STAGES", "END", "STOP", "TITLE", "CONTROL",
                                              "NODES", "ELEMENTS", "MATERIALS", "BOUNDARY",
                                              "LOADS", "RESERVOIR", "GAUGES", "INTERFACE",
                                              "SLAB"):
            inside = word == "STAGES"
            continue
        if inside and word in ("FILL", "LOAD", "RESET", "WATER"):
            count += 1
    return count or 1


def check(xmf, deck):
    results = []

    def verdict(name, ok, detail):
        results.append(ok)
        print(f"{'PASS' if ok else 'FAIL'} xdmf/{name}: {detail}")

    h5path = pathlib.Path(xmf).with_suffix(".h5")
    with h5py.File(h5path, "r") as h5, meshio.xdmf.TimeSeriesReader(xmf) as reader:
        points, cells = reader.read_points_cells()
        xy = h5["mesh/coordinates"][...]
        conn = h5["mesh/connectivity"][...]
        nstage = stage_cards(deck)
        verdict("steps", reader.num_steps == nstage == len(h5["stages"]),
                f"{reader.num_steps} time steps read, {nstage} stage cards in {deck}, "
                f"{len(h5['stages'])} stage groups in the HDF5 file (equal)")
        quads = [c for c in cells if c.type == "quad"]
        ok = (len(cells) == 1 and len(quads) == 1 and np.array_equal(quads[0].data, conn - 1)
              and np.array_equal(points, xy))
        verdict("mesh", ok, f"{points.shape[0]} points, {quads[0].data.shape[0] if quads else 0}"
                f" quads read; HDF5 mesh {xy.shape[0]} nodes, {conn.shape[0]} elements "
                "(connectivity - 1, exact)")
        bad, times = [], []
        node_fields = ("displacement", "displacement_total")
        cell_fields = ("stress_centroid", "principal", "stress_level", "active")
        for k in range(reader.num_steps):
            t, point_data, cell_data = reader.read_data(k)
            times.append(t)
            g = h5["stages"][f"stage_{k + 1:04d}"]
            for name in node_fields:
                v = point_data[name]
                if not (v.shape == (xy.shape[0], 3) and np.array_equal(v[:, :2], g[name][...])
                        and not v[:, 2].any()):
                    bad.append(f"{name} at step {k}")
            for name in cell_fields:
                if not np.array_equal(cell_data[name][0], g[name][...]):
                    bad.append(f"{name} at step {k}")
            if not np.array_equal(cell_data["material"][0], h5["mesh/material"][...]):
                bad.append(f"material at step {k}")
        verdict("times", times == [float(s) for s in range(1, nstage + 1)],
                f"times {times[0]:g} .. {times[-1]:g} (the stage numbers)")
        verdict("fields", not bad,
                f"{reader.num_steps} steps x ({', '.join(node_fields + cell_fields)}, material) "
                f"equal to the HDF5 datasets bit for bit"
                + (f"; differ: {', '.join(bad[:5])}" if bad else ""))
    return all(results)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("xmf", nargs="?")
    parser.add_argument("deck", nargs="?")
    parser.add_argument("--run", metavar="CFRD")
    parser.add_argument("--workdir", default="build/xdmf-check")
    args = parser.parse_args(argv)
    if args.run:
        work = pathlib.Path(args.workdir)
        work.mkdir(parents=True, exist_ok=True)
        run = subprocess.run([args.run, "--quiet", "--out", str(work), DECK],
                             capture_output=True, text=True)
        if run.returncode != 0:
            print(f"FAIL xdmf/run: {args.run} {DECK}: exit {run.returncode}: "
                  f"{run.stderr[-300:]}")
            return 1
        xmf, deck = work / (pathlib.Path(DECK).stem + ".xmf"), DECK
    elif args.xmf and args.deck:
        xmf, deck = args.xmf, args.deck
    else:
        parser.error("give RESULTS.xmf DECK, or --run CFRD")
    return 0 if check(str(xmf), deck) else 1


if __name__ == "__main__":
    sys.exit(main())
