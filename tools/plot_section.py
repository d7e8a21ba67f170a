#!/usr/bin/env python3
"""Contour plots of a cfrd results file (HDF5): settlement and horizontal displacement of
the dam section at one stage, like Figure 7 of the paper, and the gauge histories against
time, like its Figures 9 and 10.

    python3 tools/plot_section.py RESULTS.h5 --out outputs/tianshengqiao-settlement.png
    python3 tools/plot_section.py RESULTS.h5 --what ux --out ux.png
    python3 tools/plot_section.py RESULTS.h5 --histories outputs/tianshengqiao-gauges.png

Displacements are those since each node's placement (dataset displacement_total), in cm
as in the paper; only the elements active at the stage are drawn.
"""

import argparse

import h5py
import matplotlib
import numpy as np

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import matplotlib.tri as mtri  # noqa: E402


def text(value):
    return value.decode() if isinstance(value, bytes) else value


def read(path, stage=None):
    with h5py.File(path, "r") as h5:
        xy = h5["mesh/coordinates"][...]
        conn = h5["mesh/connectivity"][...] - 1
        names = sorted(h5["stages"])
        name = names[-1] if stage is None else f"stage_{stage:04d}"
        g = h5["stages"][name]
        u = g["displacement_total"][...]
        active = g["active"][...].astype(bool)
        attrs = {k: text(g.attrs[k]) for k in g.attrs}
        title = text(h5.attrs["title"])
    return xy, conn, u, active, attrs, title, name


def section_plot(path, what, out, stage=None):
    xy, conn, u, active, attrs, title, name = read(path, stage)
    quads = conn[active]
    tris = np.vstack([quads[:, [0, 1, 2]], quads[:, [0, 2, 3]]])
    used = np.unique(quads)
    tri = mtri.Triangulation(xy[:, 0], xy[:, 1], tris)
    if what == "settlement":
        value, label = -u[:, 1] * 100.0, "settlement (cm)"
    else:
        value, label = u[:, 0] * 100.0, "horizontal displacement (cm, + downstream)"
    fig, ax = plt.subplots(figsize=(12, 4.8))
    levels = np.linspace(value[used].min(), value[used].max(), 15)
    filled = ax.tricontourf(tri, value, levels=levels, cmap="viridis_r" if what ==
                            "settlement" else "coolwarm")
    lines = ax.tricontour(tri, value, levels=levels[::2], colors="k", linewidths=0.5)
    ax.clabel(lines, fmt="%.0f", fontsize=7)
    edges = set()
    for q in quads:
        for k in range(4):
            e = tuple(sorted((q[k], q[(k + 1) % 4])))
            edges.symmetric_difference_update({e})
    for a, b in edges:
        ax.plot(xy[[a, b], 0], xy[[a, b], 1], "k-", lw=0.8)
    k = used[np.argmax(value[used])] if what == "settlement" else used[np.argmax(np.abs(value[used]))]
    ax.plot(*xy[k], "r*", ms=10)
    ax.annotate(f"{value[k]:.0f} cm at El. {xy[k, 1]:.0f} m", xy[k], xytext=(10, 10),
                textcoords="offset points", color="r")
    level = attrs.get("water_level")
    if level is not None:
        ax.axhline(float(np.ravel(level)[0]), xmax=0.4, color="tab:blue", lw=1)
    ax.set_aspect("equal")
    ax.set_xlabel("x (m)")
    ax.set_ylabel("elevation (m)")
    date = attrs.get("date", "")
    ax.set_title(f"{title}\n{label}, {name} {attrs.get('name', '')} {date}", fontsize=9)
    fig.colorbar(filled, ax=ax, shrink=0.8, label=label)
    fig.tight_layout()
    fig.savefig(out, dpi=110)


def month_number(date):
    """'1997.05' (or '1997-05') -> 1997.33 (years, start of the month)."""
    text = date.replace("-", ".")
    return int(text[:4]) + (int(text[5:7]) - 1) / 12.0


def histories_plot(path, out):
    with h5py.File(path, "r") as h5:
        names = [n.decode() if isinstance(n, bytes) else str(n)
                 for n in h5["gauges/names"][...]]
        nodes = h5["gauges/nodes"][...] - 1
        stages = sorted(h5["stages"])
        t, ux, sett = [], [], []
        for s in stages:
            g = h5["stages"][s]
            date = g.attrs.get("date", "")
            date = date.decode() if isinstance(date, bytes) else str(date)
            if not date:
                continue
            u = g["displacement_total"][...]
            t.append(month_number(date))
            ux.append(u[nodes, 0] * 100)
            sett.append(-u[nodes, 1] * 100)
    t, ux, sett = np.array(t), np.array(ux), np.array(sett)
    fig, axes = plt.subplots(1, 2, figsize=(12, 4.2))
    for k, name in enumerate(names):
        name = name.strip()
        if "-V" in name:
            axes[0].plot(t, sett[:, k], "o-", ms=3, label=name)
        else:
            axes[1].plot(t, ux[:, k], "o-", ms=3, label=name)
    axes[0].set_title("settlement along the interface (cm)")
    axes[1].set_title("horizontal displacement along the interface (cm, + downstream)")
    for ax in axes:
        ax.set_xlabel("year")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(out, dpi=110)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("results")
    parser.add_argument("--what", choices=["settlement", "ux"], default="settlement")
    parser.add_argument("--stage", type=int, help="stage number (default: the last)")
    parser.add_argument("--out", help="contour PNG")
    parser.add_argument("--histories", help="gauge histories PNG")
    args = parser.parse_args()
    if args.out:
        section_plot(args.results, args.what, args.out, args.stage)
    if args.histories:
        histories_plot(args.results, args.histories)


if __name__ == "__main__":
    main()
