#!/usr/bin/env python3
"""Interface figures like the paper's Figures 11, 13 and 14 from cfrd HDF5 results.

  python3 tools/plot_interface.py RESULTS.h5 [RESULTS2.h5 ...] --out PREFIX

Writes PREFIX-opening.png (relative normal displacement along the interface at the end of
each slab-casting period and at the last stage, Fig. 11), PREFIX-normal-stress.png (normal
stress along the interface just before the phase II slab is cast and at the end of the dam
body's construction, one curve per results file, Fig. 13) and PREFIX-slab.png (normal stress
along the slab axis and shear stress at the end of construction, Fig. 14). "Before phase II"
is the stage before the second RESET, "end of construction" the stage before the third (the
last stage when a deck has fewer RESETs). tools/figures.py draws these with the others.
"""
import argparse

import h5py
import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.ticker import MaxNLocator  # noqa: E402
import numpy as np  # noqa: E402


def text(value):
    return value.decode() if isinstance(value, bytes) else str(value)


def stages(h5):
    """Stage group names in order, and the indices of the RESET stages."""
    names = sorted(h5["stages"])
    kinds = [text(h5["stages"][s].attrs["kind"]).strip() for s in names]
    resets = [i for i, k in enumerate(kinds) if k == "RESET"]
    return names, resets


def label(path):
    return path.rsplit("/", 1)[-1].replace(".h5", "")


def date_of(g):
    return text(g.attrs.get("date", "")).strip()


def opening_stages(h5):
    """Fig. 11's stages: the end of each slab-casting period (the stage before each RESET
    after the first) and the last stage."""
    names, resets = stages(h5)
    return sorted(set([i - 1 for i in resets[1:]] + [len(names) - 1]))


def construction_stages(h5):
    """Fig. 13's two stages: before the phase II slab (the stage before the second RESET)
    and the end of the dam body's construction (before the third); the last stage stands in
    for either when the deck has fewer RESETs."""
    names, resets = stages(h5)
    last = len(names) - 1
    before_2 = resets[1] - 1 if len(resets) > 1 else last
    before_3 = resets[2] - 1 if len(resets) > 2 else last
    return [(before_2, "before phase II slab"), (before_3, "end of dam body construction")]


def interface_profile(h5, i, key):
    """Elevation and `key` of the active stations of stage index i, sorted by elevation;
    None when the stage has no interface results."""
    g = h5["stages"][sorted(h5["stages"])[i]]
    if "interface" not in g:
        return None
    r = g["interface"]
    act = r["active"][...].astype(bool)
    y = r["y"][...][act].ravel()
    v = r[key][...][act].ravel()
    order = np.argsort(y, kind="stable")
    return y[order], v[order]


def slab_profile(h5, i, key):
    """Elevation and `key` at the Gauss points of the active slab elements of stage i."""
    g = h5["stages"][sorted(h5["stages"])[i]]
    if "slab" not in g:
        return None
    r = g["slab"]
    keep = g["active"][...].astype(bool)[r["element"][...] - 1]
    return r["y"][...][keep].ravel(), r[key][...][keep].ravel()


def opening_plot(h5, name, out):
    """Fig. 11: relative normal displacement (cm) along the interface at opening_stages."""
    fig, ax = plt.subplots(figsize=(7, 4))
    names = sorted(h5["stages"])
    for i in opening_stages(h5):
        profile = interface_profile(h5, i, "du_n")
        if profile is None:
            continue
        y, du = profile
        ax.plot(y, 100 * du, marker=".",
                label=f"stage {i + 1} ({date_of(h5['stages'][names[i]])})")
    ax.set_xlabel("elevation (m)")
    ax.set_ylabel("relative normal displacement (cm, opening +)")
    ax.set_title(f"{name}: slab-cushion opening (cf. paper Fig. 11)")
    ax.legend(fontsize=7)
    ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(out, dpi=120)
    return fig


def normal_stress_plot(files, names, out):
    """Fig. 13: normal stress along the interface at construction_stages, per file."""
    fig, axes = plt.subplots(1, 2, figsize=(10, 4), sharey=True)
    for f, name in zip(files, names):
        for ax, (i, title) in zip(axes, construction_stages(f)):
            profile = interface_profile(f, i, "sigma_n")
            if profile is None:
                continue
            y, sn = profile
            ax.plot(sn, y, marker=".", label=f"{name} (stage {i + 1})")
            ax.set_title(title)
            ax.set_xlabel("normal stress (kPa, tension +)")
            ax.axvline(0, color="k", lw=0.5)
            ax.grid(alpha=0.3)
    axes[0].set_ylabel("elevation (m)")
    axes[1].legend(fontsize=7)
    fig.suptitle("normal stress along the interface (cf. paper Fig. 13)")
    fig.tight_layout()
    fig.savefig(out, dpi=120)
    return fig


def slab_plot(files, names, out):
    """Fig. 14: slab stresses at the Gauss points at the end of construction, per file."""
    fig, axes = plt.subplots(1, 2, figsize=(10, 4), sharey=True)
    for f, name in zip(files, names):
        i = construction_stages(f)[1][0]
        for ax, key, what in ((axes[0], "sigma_t", "normal stress along the slab (kPa)"),
                              (axes[1], "tau", "shear stress (kPa)")):
            profile = slab_profile(f, i, key)
            if profile is None:
                continue
            y, v = profile
            ax.plot(v, y, ".", ms=3, label=f"{name} (stage {i + 1})")
            ax.set_xlabel(what)
            ax.xaxis.set_major_locator(MaxNLocator(6))
            ax.grid(alpha=0.3)
    axes[0].set_ylabel("elevation (m)")
    axes[1].legend(fontsize=7)
    fig.suptitle("slab stresses at the Gauss points, end of construction (cf. paper Fig. 14)")
    fig.tight_layout()
    fig.savefig(out, dpi=120)
    return fig


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("results", nargs="+")
    parser.add_argument("--out", required=True)
    args = parser.parse_args(argv)
    files = [h5py.File(p, "r") for p in args.results]
    names = [label(p) for p in args.results]
    opening_plot(files[0], names[0], args.out + "-opening.png")
    normal_stress_plot(files, names, args.out + "-normal-stress.png")
    slab_plot(files, names, args.out + "-slab.png")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
