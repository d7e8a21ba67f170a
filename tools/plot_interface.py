#!/usr/bin/env python3
"""Interface figures like the paper's Figures 11, 13 and 14 from cfrd HDF5 results, for
the three methods: Goodman joints and thin layers (INTERFACE cards: the stations of
/stages/*/interface) and contact (CONTACT cards: the slave nodes of /stages/*/contact).

  python3 tools/plot_interface.py RESULTS.h5 [RESULTS2.h5 ...] --out PREFIX

Writes PREFIX-opening.png (the opening along the interface, Fig. 11: relative normal
displacement du_n of the interface stations, or the gap of the contact slave nodes, at the
end of each slab-casting period, at the last stage and at the stage of each slab phase's
largest opening), PREFIX-normal-stress.png (normal stress along the interface just before
the phase II slab is cast, at the end of the dam body's construction and at the stage of the
largest opening, one curve per results file, Fig. 13; separated contact nodes hollow) and
PREFIX-slab.png (normal stress along the slab axis and shear stress at the end of
construction, Fig. 14). "Before phase II" is the stage before the second RESET, "end of
construction" the stage before the third (the last stage when a deck has fewer RESETs).
Contact results are drawn at the placed slave nodes (all pairs together, by elevation).
tools/figures.py draws these with the others.
"""
import argparse

import h5py
import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.ticker import MaxNLocator  # noqa: E402
import numpy as np  # noqa: E402
from cfrdtools import results
from cfrdtools.results import text


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


def has_contact(h5):
    """True when the results hold contact results (decks with CONTACT cards)."""
    names = sorted(h5["stages"])
    return bool(names) and "contact" in h5["stages"][names[-1]]


def has_interface(h5):
    """True when the results hold interface results (decks with INTERFACE cards)."""
    return "mesh/interface_elements" in h5


def method(h5):
    """The slab-cushion method of the results: 'contact', 'joint', 'thin' or None (none,
    or joints and thin layers mixed)."""
    if has_contact(h5):
        return "contact"
    if "mesh/interface_method" in h5:
        kinds = set(int(k) for k in h5["mesh/interface_method"][...])
        return {frozenset({1}): "joint", frozenset({2}): "thin"}.get(frozenset(kinds))
    return None


def phase_openings(h5):
    """Per slab phase (line or contact pair, group), in order: the phase's name and its
    opening width and depth (m) at every stage that has it, as (stage number, width, depth)
    arrays. Interface results: /interface/opening_*; contact results: /contact/opening_*."""
    groups = [text(g).strip() for g in h5["mesh/group_names"][...]] \
        if "mesh/group_names" in h5 else []
    phases = {}
    for number, s in enumerate(sorted(h5["stages"]), start=1):
        g = h5["stages"][s]
        for where, line_key in (("interface", "opening_line"), ("contact", "opening_pair")):
            if where not in g or "opening_width" not in g[where]:
                continue
            r = g[where]
            for line, group, width, depth in zip(r[line_key][...], r["opening_group"][...],
                                                 r["opening_width"][...],
                                                 r["opening_depth"][...]):
                phases.setdefault((int(line), int(group)), []).append((number, width, depth))
    out = []
    for (line, group), rows in sorted(phases.items()):
        name = groups[group - 1] if 0 < group <= len(groups) else f"line {line}"
        rows = np.array(rows)
        out.append((name, rows[:, 0].astype(int), rows[:, 1], rows[:, 2]))
    return out


def largest_opening_stages(h5):
    """Per slab phase that opens: (stage index, phase name) of its largest width (the first
    stage of it); phases that never open are left out."""
    out = []
    for name, stage, width, _ in phase_openings(h5):
        k = int(np.argmax(width))
        if width[k] > 0:
            out.append((int(stage[k]) - 1, name))
    return out


def largest_opening_stage(h5):
    """Stage index of the largest opening width of any phase (the first stage that has
    it), or None when nothing opens."""
    rows = [(width[k], int(stage[k]) - 1) for _, stage, width, _ in phase_openings(h5)
            for k in range(len(stage))]
    top = max((w for w, _ in rows), default=0.0)
    return None if top <= 0 else min(i for w, i in rows if w == top)


def contact_profile(h5, i, key):
    """Elevation, `key` and the separated flag (status open) of the placed contact slave
    nodes of stage index i, sorted by elevation; None when the stage has no contact
    results."""
    g = results.stages(h5)[i]
    if "contact" not in g:
        return None
    r = g["contact"]
    placed = r["placed"][...] == 1
    y = r["y"][...][placed]
    v = r[key][...][placed]
    separated = r["status"][...][placed] == 0
    order = np.argsort(y, kind="stable")
    return y[order], v[order], separated[order]


def profile(h5, i, what):
    """Along the slab-cushion interface at stage index i: (elevation, values, separated)
    of the interface stations or the contact slave nodes; `what` is 'opening' (du_n or
    gap, m) or 'sigma_n' (kPa); separated is None for interfaces; None without results."""
    if has_contact(h5):
        return contact_profile(h5, i, "gap" if what == "opening" else what)
    found = interface_profile(h5, i, "du_n" if what == "opening" else what)
    return None if found is None else (found[0], found[1], None)


def interface_profile(h5, i, key):
    """Elevation and `key` of the active stations of stage index i, sorted by elevation;
    None when the stage has no interface results."""
    g = results.stages(h5)[i]
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
    g = results.stages(h5)[i]
    if "slab" not in g:
        return None
    r = g["slab"]
    keep = g["active"][...].astype(bool)[r["element"][...] - 1]
    return r["y"][...][keep].ravel(), r[key][...][keep].ravel()


def opening_plot(h5, name, out):
    """Fig. 11: the opening (cm) along the interface at opening_stages and at the stage of
    each phase's largest opening: relative normal displacement du_n of the interface
    stations, or the gap of the placed contact slave nodes."""
    fig, ax = plt.subplots(figsize=(9.5, 4))
    names = sorted(h5["stages"])
    notes = {}
    for i, phase in largest_opening_stages(h5):
        notes.setdefault(i, []).append(phase)
    for i in sorted(set(opening_stages(h5)) | set(notes)):
        found = profile(h5, i, "opening")
        if found is None:
            continue
        y, du, _ = found
        note = f", largest {', '.join(notes[i])} opening" if i in notes else ""
        ax.plot(y, 100 * du, marker=".",
                label=f"stage {i + 1} ({date_of(h5['stages'][names[i]])}{note})")
    ax.set_xlabel("elevation (m)")
    if has_contact(h5):
        ax.set_ylabel("gap at the slab's slave nodes (cm, open +)")
    else:
        ax.set_ylabel("relative normal displacement (cm, opening +)")
    ax.set_title(f"{name}: slab-cushion opening (cf. paper Fig. 11)")
    ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1), borderaxespad=0)
    ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(out, dpi=120)
    return fig


def off_scale(values):
    """The few compressive values (at most two) so far beyond the rest that they would
    squash the curves (each more than 3 times the next): the contact traction at the toe
    corner, for one. Returns the cut-off below which values are off the scale, or None."""
    v = np.sort(np.asarray(values, float))
    for k in (2, 1):
        if k < len(v) - 1 and v[k] < 0 and v[k - 1] < 3 * v[k]:
            return v[k]
    return None


def normal_stress_plot(files, names, out):
    """Fig. 13: normal stress along the interface at construction_stages and at the stage
    of the largest opening, per file; separated contact nodes are drawn hollow (their
    traction is zero). A value far off the scale (the toe corner of a contact run) is left
    off the axis and written at its edge."""
    largest = [largest_opening_stage(f) for f in files]
    npanel = 3 if any(i is not None for i in largest) else 2
    fig, axes = plt.subplots(1, npanel, figsize=(5 * npanel, 4.4), sharey=True)
    for k, (f, name) in enumerate(zip(files, names)):
        picks = construction_stages(f)
        if npanel == 3:
            picks = picks + [(largest[k], "at the largest opening")]
        for ax, (i, title) in zip(axes, picks):
            ax.set_title(title)
            if i is None:
                continue
            found = profile(f, i, "sigma_n")
            if found is None:
                continue
            y, sn, separated = found
            colour = f"C{k}"
            ax.plot(sn, y, marker=".", color=colour, label=f"{name} (stage {i + 1})")
            if separated is not None and separated.any():
                ax.plot(sn[separated], y[separated], "o", mfc="none", ms=7, color=colour,
                        label=f"{name} separated (stage {i + 1})")
    for ax in axes:
        ax.set_xlabel("normal stress (kPa, tension +)")
        ax.axvline(0, color="k", lw=0.5)
        ax.grid(alpha=0.3)
        points = [line.get_xydata() for line in ax.get_lines()
                  if not line.get_label().startswith("_")]
        if not points:
            continue
        ax.legend(fontsize=7)
        points = np.vstack(points)
        cut = off_scale(points[:, 0])
        if cut is None:
            continue
        left = 1.15 * cut
        ax.set_xlim(left=left, right=max(0.0, points[:, 0].max()) - 0.05 * left)
        for x, y in points[points[:, 0] < cut]:
            ax.plot(left, y, "<", color="0.3", ms=6, clip_on=False, label="_off scale")
            ax.annotate(f"off scale: {x:.0f} kPa at El. {y:.0f} m", (left, y),
                        xytext=(6, -3), textcoords="offset points", fontsize=7, color="0.3",
                        va="top")
    axes[0].set_ylabel("elevation (m)")
    contact = any(has_contact(f) for f in files)
    fig.suptitle("normal stress along the interface (cf. paper Fig. 13)"
                 + ("\ncontact: at the slab's slave nodes; hollow circles: separated from the "
                    "cushion" if contact else ""), fontsize=10)
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
