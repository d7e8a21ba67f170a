#!/usr/bin/env python3
"""The slab's stresses of one deck meshed at several refinements, side by side (issue 22;
docs/tianshengqiao.md section 11): whether the largest slab tension comes from a
mesh-converged place.

  python3 tools/slab_convergence.py X2.h5 X4.h5 X8.h5 [--stage N] [--base] [--fixed]
                                    [--out FIG.png]

For each file, at stage N (default: the last): the largest centroid sigma_1 of the slab
elements, the largest fibre stress N/h +- 6M/h^2 and the largest membrane stress N/h of the
slab sections, within bands of distance from the slab's toe (its lowest node; --base: the
nearest slab node on the base, the summary's singular points of a clamped toe); then, per
band, the spread of the files' values, max / min - 1, in %. --fixed adds N/h and the larger
fibre stress at fixed distances (linear between sections) with their spread (max - min) / max
(docs/tianshengqiao.md section 11.1). --out draws the two fibre stresses along the slope, one
curve per file. Reads only the HDF5 files (/mesh, /stages/*/principal, /stages/*/slab).
"""
import argparse
import sys

import h5py
import numpy as np

from cfrdtools.plots import plt, save
from cfrdtools.results import field, text

BANDS = (0.0, 2.0, 5.0, 10.0, 20.0, 30.0, 50.0, 100.0, 200.0, 400.0)   # m from the toe
FIXED = (5.0, 10.0, 15.0, 20.0, 30.0, 50.0, 100.0)                      # m from the toe


def slab_stresses(path, stage=None, base=False):
    """(name, stage label, toe distance and sigma_1 of the slab centroids, toe distance,
    elevation and the larger fibre stress of the sections, water and cushion fibres);
    base: distances from the nearest slab node on the base, not from the lowest node."""
    with h5py.File(path, "r") as h5:
        xy = h5["mesh/coordinates"][...][:, :2]
        conn = h5["mesh/connectivity"][...] - 1
        names = sorted(h5["stages"])
        g = h5["stages"][names[-1 if stage is None else stage - 1]]
        r = g["slab"]
        element = r["element"][...] - 1
        nodes = np.unique(conn[element])
        toe = xy[nodes[np.argmin(xy[nodes, 1] + 1e-6 * xy[nodes, 0])]]
        ends = xy[nodes[np.abs(xy[nodes, 1] - xy[nodes, 1].min()) < 1e-6]] if base else toe[None]
        active = g["active"][...].astype(bool)[element]
        centre = xy[conn[element[active]]].mean(axis=1)
        sigma1 = field(g, "principal")[element[active], 0]
        placed = (r["axial"][...] != 0.0) | (r["moment"][...] != 0.0)
        sx, sy = r["section_x"][...][placed], r["section_y"][...][placed]
        water, cushion = r["sigma_water"][...][placed], r["sigma_cushion"][...][placed]
        number = names.index(g.name.rsplit("/", 1)[-1]) + 1
        label = f"stage {number}: {text(g.attrs.get('name', ''))}"
        return (path.rsplit("/", 1)[-1].replace(".h5", ""), label,
                distance(centre, ends), sigma1,
                distance(np.column_stack([sx, sy]), ends), sy, water, cushion)


def distance(points, ends):
    """Distance of each point (n, 2) from the nearest of the points ends (m, 2)."""
    return np.min(np.hypot(points[:, None, 0] - ends[None, :, 0],
                           points[:, None, 1] - ends[None, :, 1]), axis=1)


def band_maxima(distance, value):
    """The largest value in each band of BANDS (None where the band holds none)."""
    return [float(value[(distance >= a) & (distance < b)].max())
            if np.any((distance >= a) & (distance < b)) else None
            for a, b in zip(BANDS[:-1], BANDS[1:])]


def spread(values):
    """max / min - 1 of positive values, in %, or None."""
    v = [x for x in values if x is not None]
    return 100.0 * (max(v) / min(v) - 1.0) if len(v) == len(values) and min(v) > 0 else None


def print_fixed(runs):
    """N/h and the larger fibre stress (MPa) at the distances FIXED, one column per file,
    linear between sections, with their spread (max - min) / max in %."""
    print("section N/h | larger fibre stress (MPa) at fixed distances from the toe (m), "
          "per file, (max - min) / max:")
    for x in FIXED:
        row = []
        for values in ((lambda r: 0.5 * (r[6] + r[7])), (lambda r: np.maximum(r[6], r[7]))):
            at = [float(np.interp(x, *sorted_by(r[4], values(r)))) / 1000.0 for r in runs]
            gap = 100.0 * (max(at) - min(at)) / max(abs(a) for a in at)
            row.append(" / ".join(f"{a:.1f}" for a in at) + f" ({gap:.0f} %)")
        print(f"{x:6g}  " + "  |  ".join(row))


def sorted_by(distance, value):
    """(distance, value) sorted by distance, for np.interp."""
    order = np.argsort(distance)
    return distance[order], value[order]


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("results", nargs="+", help="cfrd HDF5 results files, coarse to fine")
    ap.add_argument("--stage", type=int, help="stage number (default: the last)")
    ap.add_argument("--base", action="store_true",
                    help="distances from the nearest slab node on the base")
    ap.add_argument("--fixed", action="store_true",
                    help="N/h and fibre stress at fixed distances from the toe")
    ap.add_argument("--out", help="PNG of the fibre stresses along the slope")
    args = ap.parse_args(argv)
    runs = [slab_stresses(p, args.stage, args.base) for p in args.results]
    heads = [f"{a:g}-{b:g}" for a, b in zip(BANDS[:-1], BANDS[1:])]
    for what, d, v in (("centroid sigma_1", 2, 3), ("section fibre stress", 4, 6),
                       ("section membrane stress N/h", 4, 8)):
        print(f"largest slab {what} (kPa) by distance from the toe (m), {runs[0][1]}:")
        print(f"{'':24}" + "".join(f"{h:>10}" for h in heads))
        table = []
        for run in runs:
            value = {3: run[3], 6: np.maximum(run[6], run[7]), 8: 0.5 * (run[6] + run[7])}[v]
            table.append(band_maxima(run[d], value))
            print(f"{run[0]:24}" + "".join(f"{x:10.0f}" if x is not None else f"{'-':>10}"
                                          for x in table[-1]))
        print(f"{'spread %':24}" + "".join(
            f"{s:10.1f}" if s is not None else f"{'-':>10}"
            for s in (spread([row[k] for row in table]) for k in range(len(heads)))))
    if args.fixed:
        print_fixed(runs)
    if args.out:
        fig, axes = plt.subplots(1, 2, figsize=(10, 5), sharey=True)
        for run in runs:
            order = np.argsort(run[5])
            for ax, k, side in ((axes[0], 6, "water side"), (axes[1], 7, "cushion side")):
                ax.plot(run[k][order] / 1000.0, run[5][order], ".-", ms=3, label=run[0])
                ax.set_xlabel(f"fibre stress, {side} (MPa, tension +)")
                ax.grid(alpha=0.3)
        axes[0].set_ylabel("elevation (m)")
        axes[1].legend(fontsize=8)
        fig.suptitle(f"slab fibre stresses N/h +- 6M/h^2 along the slope, {runs[0][1]}")
        save(fig, args.out)
    return 0


if __name__ == "__main__":
    sys.exit(main())
