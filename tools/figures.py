#!/usr/bin/env python3
"""Figures like the paper's from cfrd results files, for any deck, in one command.

  python3 tools/figures.py RESULT.h5 [MORE.h5 ...] --out DIR [--data] [--reference FILE]
  make figures DECK=inputs/tianshengqiao-x1-joint.dat          (runs the deck first)

The first file gives the single-file figures; every file gives a curve in Figs. 13 and 14
and a row of the Table 5 comparison. Written into DIR, each only when the results hold its
data (a line says which were skipped and why):

  fig07-settlement.png  settlement contours at the last stage (paper Fig. 7)
  fig07-ux.png          horizontal displacement contours at the last stage
  fig09-10-gauges.png   settlement and horizontal displacement at the gauges against time
                        (Figs. 9 and 10; decks with GAUGES and dated stages)
  fig11-opening.png     opening along the interface at the end of each slab period, at
                        the last stage and at each phase's largest opening (Fig. 11; decks
                        with INTERFACE: du_n of the stations, or CONTACT: gap of the slave
                        nodes)
  fig12-openings.png    width and depth of each slab phase's opening, stage by stage, with
                        the observed maxima (cf. Figs. 11-12 and Table 5)
  fig12-openings-time.png  the same against time (decks whose stages all carry dates in a
                        date form, e.g. the creep decks: tools/tianshengqiao.py --creep)
  fig13-normal-stress.png  normal stress along the interface before the phase II slab, at
                        the end of construction and at the largest opening (Fig. 13;
                        contact: the slave nodes' traction, separated nodes hollow)
  fig14-slab.png        slab stresses at the Gauss points at the end of construction
                        (Fig. 14; decks with SLAB)
  table5-openings.png   largest opening width and depth of phases I and II against the
                        paper's Table 5, each run beside the paper's row of its method
                        (decks with INTERFACE or CONTACT)

--reference names a TOML file of observed and published values (default: the first of
inputs/*-observed.toml whose title_contains is in the results' title, e.g.
inputs/tianshengqiao-observed.toml); `--reference none` draws without.
--data also writes DIR/data/FIGURE.csv for each figure: every curve and bar as drawn (read
back from matplotlib's artists) and every contoured field, with all digits (Python repr),
so that tools/check_figures.py can compare what is plotted with the HDF5 datasets.
"""
import argparse
import csv
import pathlib
import sys

import h5py
import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
from cfrdtools import results
from cfrdtools.results import text

import plot_interface
import plot_section

try:
    import tomllib
except ModuleNotFoundError:  # Python < 3.11
    import tomli as tomllib

ROOT = pathlib.Path(__file__).resolve().parent.parent


def find_reference(title, choice):
    """The reference TOML for these results, or None."""
    if choice == "none":
        return None
    if choice:
        return tomllib.loads(pathlib.Path(choice).read_text())
    for path in sorted((ROOT / "inputs").glob("*-observed.toml")):
        ref = tomllib.loads(path.read_text())
        if ref.get("title_contains", "\0") in title:
            return ref
    return None


phase_openings = plot_interface.phase_openings


def openings_history_plot(h5, name, out, reference, years=None):
    """Width (cm) and depth (m) of each phase's opening per stage, observed maxima dashed;
    with `years` (the stages' times) against time."""
    phases = phase_openings(h5)
    fig, axes = plt.subplots(1, 2, figsize=(11, 4))
    for k, (phase, stage, width, depth) in enumerate(phases):
        colour = f"C{k}"
        x = stage if years is None else years[stage - 1]
        axes[0].plot(x, 100 * width, ".-", color=colour, label=phase)
        axes[1].plot(x, depth, ".-", color=colour, label=phase)
        observed = table5_row(reference, "in-situ", k)
        if observed is not None:
            axes[0].axhline(100 * observed[0], color=colour, ls="--", lw=0.8)
            axes[1].axhline(observed[1], color=colour, ls="--", lw=0.8)
    axes[0].set_ylabel("opening width (cm)")
    axes[1].set_ylabel("opening depth from the phase's top (m)")
    for ax in axes:
        ax.set_xlabel("stage" if years is None else "year")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8)
    note = "dashed: in-situ maxima of phases I and II (paper Table 5)" if reference else ""
    what = "per stage (cf. paper Figs. 11-12)" if years is None else "against time"
    fig.suptitle(f"{name}: opening of each slab phase {what}"
                 + (f"\n{note}" if note else ""), fontsize=10)
    fig.tight_layout()
    fig.savefig(out, dpi=120)
    return fig


def stage_years(h5):
    """Time of each stage in years (from its `day` attribute), or None when some stage has
    none (decks without dates in a date form)."""
    years = []
    for s in sorted(h5["stages"]):
        day = h5["stages"][s].attrs.get("day")
        if day is None:
            return None
        years.append(1970.0 + float(day) / 365.2425)
    return np.array(years)


def table5_row(reference, prefix, phase):
    """(width, depth) of the reference row starting with `prefix` for phase index 0 or 1."""
    if not reference or phase > 1:
        return None
    for row in reference.get("table5", []):
        if row["row"].startswith(prefix):
            p = row[f"phase_{phase + 1}"]
            return p["width"], p["depth"]
    return None


def table5_plot(files, names, out, reference):
    """Grouped bars: width (m) and depth (m) of phases I and II, the paper's rows and ours
    (the largest over the stages), each bar labelled with its value. Each run (hatched)
    stands beside the paper's row of its method, in that row's colour."""
    paper = [(row["row"], row.get("method"),
              [row["phase_1"]["width"], row["phase_2"]["width"]],
              [row["phase_1"]["depth"], row["phase_2"]["depth"]])
             for row in (reference or {}).get("table5", [])]
    ours = []
    for f, name in zip(files, names):
        phases = phase_openings(f)[:2]
        if phases:
            ours.append((f"cfrd {name}", plot_interface.method(f),
                         [float(p[2].max()) for p in phases],
                         [float(p[3].max()) for p in phases]))
    # (label, widths, depths, colour, hatch): the paper's rows in order, each followed by
    # the runs of its method; runs of no listed method at the end.
    rows, placed = [], set()
    for j, (row, how, widths, depths) in enumerate(paper):
        rows.append((row, widths, depths, f"C{j}", None))
        for k, (label, m, w, d) in enumerate(ours):
            if how is not None and m == how:
                runs = sum(1 for r in rows if r[3] == f"C{j}") - 1
                hatch = ["//", "xx", "\\\\", ".."][runs % 4]
                rows.append((label, w, d, f"C{j}", hatch))
                placed.add(k)
    for k, (label, m, w, d) in enumerate(ours):
        if k not in placed:
            rows.append((label, w, d, f"C{len(paper) + k}", "//"))
    nphase = max(len(r[1]) for r in rows)
    fig, axes = plt.subplots(1, 2, figsize=(12, 4.8))
    width = 0.8 / len(rows)
    for j, (row, widths, depths, colour, hatch) in enumerate(rows):
        x = np.arange(len(widths)) + (j - (len(rows) - 1) / 2) * width
        for ax, values, fmt in ((axes[0], widths, "{:.3f}"), (axes[1], depths, "{:.1f}")):
            face = colour if hatch is None else \
                0.5 + 0.5 * np.array(matplotlib.colors.to_rgb(colour))
            bars = ax.bar(x, values, width, label=row, color=face, hatch=hatch,
                          edgecolor="k", lw=0.4)
            ax.bar_label(bars, [fmt.format(v) for v in values], fontsize=6, rotation=90,
                         padding=2)
    for ax, what in ((axes[0], "largest opening width (m)"),
                     (axes[1], "largest opening depth (m)")):
        ax.set_xticks(range(nphase), [f"phase {'I' * (k + 1)}" for k in range(nphase)])
        ax.set_ylabel(what)
        ax.margins(y=0.18)
        ax.grid(axis="y", alpha=0.3)
    axes[1].legend(fontsize=7, loc="upper left")
    head = ("slab openings against the paper's Table 5 (hatched: this run, beside the "
            "paper's row of its method)") if paper else "largest slab openings (hatched: this run)"
    fig.suptitle(head + "\nwidth: largest separation (contact: gap; joints, "
                 "thin layers: relative normal displacement); depth: opened length from the "
                 "phase's top\n(contact: down to where the gap closes; joints, thin layers: "
                 "the tensile zone)", fontsize=9)
    fig.tight_layout()
    fig.savefig(out, dpi=120)
    return fig


def artist_rows(fig):
    """Every labelled curve and every bar of the figure as (panel, series, kind, index, x, y)."""
    rows = []
    for p, ax in enumerate(fig.axes):
        panel = ax.get_title() or f"axes {p}"
        for line in ax.get_lines():
            label = line.get_label()
            if label.startswith("_"):
                continue        # outlines, reference lines
            for i, (x, y) in enumerate(line.get_xydata()):
                rows.append((panel, label, "line", i, repr(float(x)), repr(float(y))))
        ticks = {round(t, 9): lab.get_text() for t, lab in
                 zip(ax.get_xticks(), ax.get_xticklabels())}
        for container in ax.containers:
            label = container.get_label()
            for i, bar in enumerate(container.patches):
                centre = bar.get_x() + bar.get_width() / 2
                category = min(ticks.items(), key=lambda kv: abs(kv[0] - centre))[1] \
                    if ticks else repr(centre)
                rows.append((panel, label, "bar", i, category, repr(float(bar.get_height()))))
    return rows


def write_data(directory, name, fig, field=None):
    directory.mkdir(parents=True, exist_ok=True)
    with open(directory / f"{name}.csv", "w", newline="") as out:
        w = csv.writer(out)
        w.writerow(["panel", "series", "kind", "index", "x", "y", "value"])
        for row in artist_rows(fig):
            w.writerow(list(row) + [""])
        if field is not None:
            for node in field["used"]:
                w.writerow(["field", field["label"], "node", int(node) + 1,
                            repr(float(field["xy"][node, 0])), repr(float(field["xy"][node, 1])),
                            repr(float(field["value"][node]))])


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("results", nargs="+", help="cfrd HDF5 results files")
    parser.add_argument("--out", required=True, help="directory for the PNG files")
    parser.add_argument("--data", action="store_true",
                        help="also write the plotted numbers to OUT/data/*.csv")
    parser.add_argument("--reference", help="TOML of observed values, or 'none'")
    args = parser.parse_args(argv)
    out = pathlib.Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    files = [h5py.File(p, "r") for p in args.results]
    names = [plot_interface.label(p) for p in args.results]
    first, path = files[0], args.results[0]
    title = text(first.attrs.get("title", ""))
    reference = find_reference(title, args.reference)
    if not first.attrs.get("complete", 1):
        print(f"note: {path} is incomplete (complete = 0): "
              f"{text(first.attrs.get('failure', ''))}")
    written, skipped = [], []

    def save(name, fig, field=None):
        written.append(f"{name}.png")
        if args.data:
            write_data(out / "data", name, fig, field)
        plt.close(fig)

    if len(first["stages"]) == 0:
        print(f"{path}: no stage completed, no figure")
        return 1
    note = None
    if reference and "settlement" in reference:
        note = reference["settlement"]["note"]
    fig, field = plot_section.section_plot(path, "settlement", out / "fig07-settlement.png",
                                           note=note)
    save("fig07-settlement", fig, field)
    fig, field = plot_section.section_plot(path, "ux", out / "fig07-ux.png")
    save("fig07-ux", fig, field)

    if "gauges" in first and len(plot_section.gauge_histories(path)[1]) > 0:
        note = reference["gauges"]["note"] if reference and "gauges" in reference else None
        save("fig09-10-gauges", plot_section.histories_plot(path, out / "fig09-10-gauges.png",
                                                            note=note))
    else:
        skipped.append("fig09-10-gauges (no GAUGES or no dated stage)")

    has_interface = plot_interface.has_interface(first) or plot_interface.has_contact(first)
    if has_interface:
        save("fig11-opening", plot_interface.opening_plot(first, names[0],
                                                          out / "fig11-opening.png"))
        if phase_openings(first):
            save("fig12-openings", openings_history_plot(first, names[0],
                                                         out / "fig12-openings.png",
                                                         reference))
            if stage_years(first) is not None:
                save("fig12-openings-time", openings_history_plot(
                    first, names[0], out / "fig12-openings-time.png", reference,
                    stage_years(first)))
            else:
                skipped.append("fig12-openings-time (a stage without a date in a date form)")
        else:
            skipped.append("fig12-openings (no slab phase with an interface)")
    else:
        skipped += ["fig11-opening (no INTERFACE or CONTACT)",
                    "fig12-openings (no INTERFACE or CONTACT)"]
    with_interface = [(f, n) for f, n in zip(files, names)
                      if plot_interface.has_interface(f) or plot_interface.has_contact(f)]
    if with_interface:
        save("fig13-normal-stress", plot_interface.normal_stress_plot(
            [f for f, _ in with_interface], [n for _, n in with_interface],
            out / "fig13-normal-stress.png"))
    else:
        skipped.append("fig13-normal-stress (no INTERFACE or CONTACT)")
    with_slab = [(f, n) for f, n in zip(files, names)
                 if "slab" in results.last_stage(f)]
    if with_slab:
        save("fig14-slab", plot_interface.slab_plot([f for f, _ in with_slab],
                                                    [n for _, n in with_slab],
                                                    out / "fig14-slab.png"))
    else:
        skipped.append("fig14-slab (no SLAB)")
    if any(phase_openings(f) for f in files):
        save("table5-openings", table5_plot(files, names, out / "table5-openings.png",
                                            reference))
    else:
        skipped.append("table5-openings (no slab phase with an interface or contact)")

    print(f"{out}: {', '.join(written)}")
    if skipped:
        print(f"skipped: {'; '.join(skipped)}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
