#!/usr/bin/env python3
"""Interface figures like the paper's Figures 11, 13 and 14 from cfrd HDF5 results.

  python3 tools/plot_interface.py RESULTS.h5 [RESULTS2.h5 ...] --out PREFIX

Writes PREFIX-opening.png (relative normal displacement along the interface at the end of
each slab-casting period and at the last stage, Fig. 11), PREFIX-normal-stress.png (normal
stress along the interface just before the phase II slab is cast and at the end of the dam
body's construction, one curve per results file, Fig. 13) and PREFIX-slab.png (normal stress
along the slab axis and shear stress at the end of construction, Fig. 14). "Before phase II"
is the stage before the second RESET, "end of construction" the stage before the third.
"""
import argparse

import h5py
import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402


def stages(h5):
    names = sorted(h5["stages"])
    kinds = [h5["stages"][s].attrs["kind"] for s in names]
    kinds = [k.decode() if isinstance(k, bytes) else str(k) for k in kinds]
    resets = [i for i, k in enumerate(kinds) if k.strip() == "RESET"]
    return names, resets


def label(path):
    return path.rsplit("/", 1)[-1].replace(".h5", "")


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("results", nargs="+")
    parser.add_argument("--out", required=True)
    args = parser.parse_args(argv)
    files = [h5py.File(p, "r") for p in args.results]

    # Fig. 11: opening along the interface (first file).
    h5 = files[0]
    names, resets = stages(h5)
    picks = [i - 1 for i in resets[1:]] + [len(names) - 1]
    fig, ax = plt.subplots(figsize=(7, 4))
    for i in picks:
        g = h5["stages"][names[i]]
        if "interface" not in g:
            continue
        r = g["interface"]
        act = r["active"][...].astype(bool)
        y = r["y"][...][act].ravel()
        du = r["du_n"][...][act].ravel()
        order = np.argsort(y)
        date = g.attrs.get("date", b"")
        date = date.decode() if isinstance(date, bytes) else str(date)
        ax.plot(y[order], 100 * du[order], marker=".", label=f"stage {i + 1} ({date})")
    ax.set_xlabel("elevation (m)")
    ax.set_ylabel("relative normal displacement (cm, opening +)")
    ax.set_title(f"{label(args.results[0])}: slab-cushion opening (cf. paper Fig. 11)")
    ax.legend(fontsize=7)
    ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(args.out + "-opening.png", dpi=120)

    # Fig. 13: normal stress along the interface at two stages.
    fig, axes = plt.subplots(1, 2, figsize=(10, 4), sharey=True)
    for f, path in zip(files, args.results):
        names, resets = stages(f)
        for ax, i, title in ((axes[0], resets[1] - 1, "before phase II slab"),
                             (axes[1], resets[2] - 1, "end of dam body construction")):
            r = f["stages"][names[i]]["interface"]
            act = r["active"][...].astype(bool)
            y = r["y"][...][act].ravel()
            sn = r["sigma_n"][...][act].ravel()
            order = np.argsort(y)
            ax.plot(sn[order], y[order], marker=".", label=label(path))
            ax.set_title(title)
            ax.set_xlabel("normal stress (kPa, tension +)")
            ax.axvline(0, color="k", lw=0.5)
            ax.grid(alpha=0.3)
    axes[0].set_ylabel("elevation (m)")
    axes[1].legend(fontsize=7)
    fig.suptitle("normal stress along the interface (cf. paper Fig. 13)")
    fig.tight_layout()
    fig.savefig(args.out + "-normal-stress.png", dpi=120)

    # Fig. 14: slab stresses at the end of construction.
    fig, axes = plt.subplots(1, 2, figsize=(10, 4), sharey=True)
    for f, path in zip(files, args.results):
        names, resets = stages(f)
        g = f["stages"][names[resets[2] - 1]]
        if "slab" not in g:
            continue
        r = g["slab"]
        act = f["stages"][names[resets[2] - 1]]["active"][...].astype(bool)
        elems = r["element"][...] - 1
        keep = act[elems]
        y = r["y"][...][keep].ravel()
        for ax, key, what in ((axes[0], "sigma_t", "normal stress along the slab (kPa)"),
                              (axes[1], "tau", "shear stress (kPa)")):
            v = r[key][...][keep].ravel()
            ax.plot(v, y, ".", ms=3, label=label(path))
            ax.set_xlabel(what)
            ax.grid(alpha=0.3)
    axes[0].set_ylabel("elevation (m)")
    axes[1].legend(fontsize=7)
    fig.suptitle("slab stresses at the Gauss points, end of construction (cf. paper Fig. 14)")
    fig.tight_layout()
    fig.savefig(args.out + "-slab.png", dpi=120)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
