#!/usr/bin/env python3
"""Contour plots of a cfrd results file (HDF5): settlement and horizontal displacement of
the dam section at one stage, like Figure 7 of the paper, and the gauge histories against
time, like its Figures 9 and 10.

    python3 tools/plot_section.py RESULTS.h5 --out settlement.png
    python3 tools/plot_section.py RESULTS.h5 --what ux --out ux.png
    python3 tools/plot_section.py RESULTS.h5 --histories gauges.png

Displacements are those since each node's placement (dataset displacement_total), in cm
as in the paper; only the elements active at the stage are drawn. tools/figures.py draws
these and the interface figures for a deck in one command.
"""

import argparse

import h5py
import matplotlib
import numpy as np
from cfrdtools.results import text

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import matplotlib.tri as mtri  # noqa: E402


def read(path, stage=None):
    with h5py.File(path, "r") as h5:
        xy = h5["mesh/coordinates"][...]
        conn = h5["mesh/connectivity"][...] - 1
        names = sorted(h5["stages"])
        name = names[-1] if stage is None else f"stage_{stage:04d}"
        g = h5["stages"][name]
        u = g["displacement_total"][...]
        active = g["active"][...].astype(bool)
        attrs = {k: text(g.attrs[k]) if isinstance(g.attrs[k], (bytes, str)) else g.attrs[k]
                 for k in g.attrs}
        title = text(h5.attrs["title"])
    return xy, conn, u, active, attrs, title, name


def section_field(path, what="settlement", stage=None):
    """The contoured field of one stage: settlement (cm, + down) or ux (cm, + downstream)
    at the nodes, on the active quads split in triangles; `used` are the nodes drawn."""
    xy, conn, u, active, attrs, title, name = read(path, stage)
    quads = conn[active]
    if what == "settlement":
        value, label = -u[:, 1] * 100.0, "settlement (cm)"
    else:
        value, label = u[:, 0] * 100.0, "horizontal displacement (cm, + downstream)"
    return dict(xy=xy, quads=quads, used=np.unique(quads), value=value, label=label,
                attrs=attrs, title=title, name=name, what=what)


def draw_section(ax, field):
    """Filled contours with labelled lines, the outline of the active part, the extreme
    value starred, the reservoir level; returns the filled contour set."""
    xy, quads, used, value = field["xy"], field["quads"], field["used"], field["value"]
    tris = np.vstack([quads[:, [0, 1, 2]], quads[:, [0, 2, 3]]])
    # Joints and repeated-node triangles are degenerate: drop zero-area triangles.
    p = xy[tris]
    area = (p[:, 1, 0] - p[:, 0, 0]) * (p[:, 2, 1] - p[:, 0, 1]) - \
        (p[:, 2, 0] - p[:, 0, 0]) * (p[:, 1, 1] - p[:, 0, 1])
    tri = mtri.Triangulation(xy[:, 0], xy[:, 1], tris[np.abs(area) > 1e-12])
    levels = np.linspace(value[used].min(), value[used].max(), 15)
    settlement = field["what"] == "settlement"
    filled = ax.tricontourf(tri, value, levels=levels,
                            cmap="viridis_r" if settlement else "coolwarm")
    lines = ax.tricontour(tri, value, levels=levels[::2], colors="k", linewidths=0.5)
    ax.clabel(lines, fmt="%.0f", fontsize=7)
    edges = set()
    for q in quads:
        for k in range(4):
            e = tuple(sorted((q[k], q[(k + 1) % 4])))
            if e[0] != e[1]:
                edges.symmetric_difference_update({e})
    for a, b in edges:
        ax.plot(xy[[a, b], 0], xy[[a, b], 1], "k-", lw=0.8)
    k = used[np.argmax(value[used])] if settlement else used[np.argmax(np.abs(value[used]))]
    ax.plot(*xy[k], "r*", ms=10)
    ax.annotate(f"{value[k]:.0f} cm at El. {xy[k, 1]:.0f} m", xy[k], xytext=(10, 10),
                textcoords="offset points", color="r")
    level = field["attrs"].get("water_level")
    if level is not None:
        ax.axhline(float(np.ravel(level)[0]), xmax=0.4, color="tab:blue", lw=1)
    ax.set_aspect("equal")
    ax.set_xlabel("x (m)")
    ax.set_ylabel("elevation (m)")
    attrs = field["attrs"]
    ax.set_title(f"{field['title']}\n{field['label']}, {field['name']} "
                 f"{attrs.get('name', '')} {attrs.get('date', '')}", fontsize=9)
    return filled


def section_plot(path, what, out, stage=None, note=None):
    field = section_field(path, what, stage)
    fig, ax = plt.subplots(figsize=(12, 4.8))
    filled = draw_section(ax, field)
    fig.colorbar(filled, ax=ax, shrink=0.8, label=field["label"])
    if note:
        fig.text(0.5, 0.01, note, ha="center", fontsize=8, color="0.25")
    fig.tight_layout(rect=(0, 0.04 if note else 0, 1, 1))
    fig.savefig(out, dpi=110)
    return fig, field


def month_number(date):
    """'1997.05' (or '1997-05') -> 1997.33 (years, start of the month); '1997-05-16' -> the
    day's fraction of its year."""
    if len(date) == 10 and date[4] == "-" and date[7] == "-":
        import datetime
        day = datetime.date.fromisoformat(date)
        start = datetime.date(day.year, 1, 1)
        length = (datetime.date(day.year + 1, 1, 1) - start).days
        return day.year + (day - start).days / length
    date = date.replace("-", ".")
    return int(date[:4]) + (int(date[5:7]) - 1) / 12.0


def gauge_histories(path):
    """Per dated stage: time (years), and ux and settlement (cm) at each gauge."""
    with h5py.File(path, "r") as h5:
        names = [text(n).strip() for n in h5["gauges/names"][...]]
        nodes = h5["gauges/nodes"][...] - 1
        t, ux, sett = [], [], []
        for s in sorted(h5["stages"]):
            g = h5["stages"][s]
            date = text(g.attrs.get("date", "")).strip()
            if not date:
                continue
            u = g["displacement_total"][...]
            t.append(month_number(date))
            ux.append(u[nodes, 0] * 100)
            sett.append(-u[nodes, 1] * 100)
    return names, np.array(t), np.array(ux), np.array(sett)


def histories_plot(path, out, note=None):
    """Settlement of the V gauges and horizontal displacement of the others against time."""
    names, t, ux, sett = gauge_histories(path)
    fig, axes = plt.subplots(1, 2, figsize=(12, 4.2))
    for k, name in enumerate(names):
        if "-V" in name:
            axes[0].plot(t, sett[:, k], "o-", ms=3, label=name)
        else:
            axes[1].plot(t, ux[:, k], "o-", ms=3, label=name)
    axes[0].set_title("settlement along the interface (cf. paper Fig. 9)")
    axes[0].set_ylabel("settlement (cm, + down)")
    axes[1].set_title("horizontal displacement along the interface (cf. paper Fig. 10)")
    axes[1].set_ylabel("horizontal displacement (cm, + downstream)")
    for ax in axes:
        ax.set_xlabel("year")
        ax.grid(alpha=0.3)
        if ax.get_lines():
            ax.legend(fontsize=8)
    if note:
        fig.text(0.5, 0.01, note, ha="center", fontsize=8, color="0.25")
    fig.tight_layout(rect=(0, 0.04 if note else 0, 1, 1))
    fig.savefig(out, dpi=110)
    return fig


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
