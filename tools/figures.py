#!/usr/bin/env python3
"""Figures like the paper's from cfrd results files, for any deck, in one command
(docs/results.md, "Figures").

  python3 tools/figures.py RESULT.h5 [MORE.h5 ...] --out DIR [--data] [--reference FILE]
                           [--stage N]
  make figures DECK=inputs/tianshengqiao-x1-joint.dat          (runs the deck first)

The first file gives fig07-settlement.png and fig07-ux.png (contours at the last stage, or at
stage N), fig09-10-gauges.png, fig11-opening.png, fig12-openings.png, fig12-openings-time.png
and fig15-crack-risk.png; every file a curve in fig13-normal-stress.png and fig14-slab.png, a
row of table5-openings.png and, with a perimetric joint (PJOINT line, issue 22), its opening
and settlement in pjoint.png. A figure is drawn when the results hold its data; a line says
which were skipped and why. --reference: the TOML of observed and published values (default:
the first inputs/*-observed.toml whose title_contains is in the results' title; `none`:
without). --data also writes DIR/data/FIGURE.csv: every curve and bar as drawn (read back from
the artists) and every contoured field, with all digits, for tools/check_figures.py.
"""
import argparse
import csv
import datetime
import pathlib
import sys

import h5py
import matplotlib
import matplotlib.tri as mtri
import numpy as np
from matplotlib.ticker import MaxNLocator

from cfrdtools import results
from cfrdtools.plots import note as add_note, plt, save
from cfrdtools.results import text

try:
    import tomllib
except ModuleNotFoundError:  # Python < 3.11
    import tomli as tomllib

ROOT = pathlib.Path(__file__).resolve().parent.parent


def find_reference(title, choice):
    """The reference TOML for these results, or None."""
    if choice:
        return None if choice == "none" else tomllib.loads(pathlib.Path(choice).read_text())
    for path in sorted((ROOT / "inputs").glob("*-observed.toml")):
        ref = tomllib.loads(path.read_text())
        if ref.get("title_contains", "\0") in title:
            return ref
    return None


# ---------------------------------------------------------------------------- the section

def section_field(path, what="settlement", stage=None):
    """The contoured field of one stage: settlement (cm, + down) or ux (cm, + downstream)
    at the nodes, on the active quads; `used` are the nodes drawn."""
    with h5py.File(path, "r") as h5:
        xy, conn = h5["mesh/coordinates"][...], h5["mesh/connectivity"][...] - 1
        name = sorted(h5["stages"])[-1] if stage is None else f"stage_{stage:04d}"
        g = h5["stages"][name]
        u, quads = results.field(g, "displacement_total"), conn[g["active"][...].astype(bool)]
        attrs = {k: text(v) if isinstance(v, (bytes, str)) else v for k, v in g.attrs.items()}
        title = text(h5.attrs["title"])
    value, label = (-u[:, 1] * 100.0, "settlement (cm)") if what == "settlement" else \
        (u[:, 0] * 100.0, "horizontal displacement (cm, + downstream)")
    return dict(xy=xy, quads=quads, used=np.unique(quads), value=value, label=label,
                attrs=attrs, title=title, name=name, what=what)


def section_plot(path, what, out, stage=None, note=None):
    """Filled contours with labelled lines, the outline of the active part, the extreme
    value starred, the reservoir level (Fig. 7)."""
    field = section_field(path, what, stage)
    xy, quads, used, value = field["xy"], field["quads"], field["used"], field["value"]
    fig, ax = plt.subplots(figsize=(12, 4.8))
    tris = np.vstack([quads[:, [0, 1, 2]], quads[:, [0, 2, 3]]])
    # Joints and repeated-node triangles are degenerate: drop zero-area triangles.
    p = xy[tris]
    area = (p[:, 1, 0] - p[:, 0, 0]) * (p[:, 2, 1] - p[:, 0, 1]) - \
        (p[:, 2, 0] - p[:, 0, 0]) * (p[:, 1, 1] - p[:, 0, 1])
    tri = mtri.Triangulation(xy[:, 0], xy[:, 1], tris[np.abs(area) > 1e-12])
    levels = np.linspace(value[used].min(), value[used].max(), 15)
    settlement = what == "settlement"
    filled = ax.tricontourf(tri, value, levels=levels, cmap="viridis_r" if settlement
                            else "coolwarm")
    ax.clabel(ax.tricontour(tri, value, levels=levels[::2], colors="k", linewidths=0.5),
              fmt="%.0f", fontsize=7)
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
    attrs = field["attrs"]
    if attrs.get("water_level") is not None:
        ax.axhline(float(np.ravel(attrs["water_level"])[0]), xmax=0.4, color="tab:blue", lw=1)
    ax.set_aspect("equal")
    ax.set_xlabel("x (m)")
    ax.set_ylabel("elevation (m)")
    ax.set_title(f"{field['title']}\n{field['label']}, {field['name']} "
                 f"{attrs.get('name', '')} {attrs.get('date', '')}", fontsize=9)
    fig.colorbar(filled, ax=ax, shrink=0.8, label=field["label"])
    return save(fig, out, 110, add_note(fig, note)), field


def year_of(date):
    """'1997.05' (or '1997-05') -> 1997.33 (start of the month); '1997-05-16' -> the day's
    fraction of its year."""
    if len(date) == 10 and date[4] == "-" and date[7] == "-":
        day = datetime.date.fromisoformat(date)
        start = datetime.date(day.year, 1, 1)
        return day.year + (day - start).days / (datetime.date(day.year + 1, 1, 1) - start).days
    return int(date[:4]) + (int(date.replace("-", ".")[5:7]) - 1) / 12.0


def gauge_histories(path):
    """Per dated stage: time (years), and ux and settlement (cm) at each gauge."""
    with h5py.File(path, "r") as h5:
        names, nodes = results.gauges(h5)
        dated = [(text(g.attrs.get("date", "")).strip(), results.field(g, "displacement_total"))
                 for g in results.stages(h5)]
        dated = [(d, u) for d, u in dated if d]
    return names, np.array([year_of(d) for d, _ in dated]), \
        np.array([u[nodes, 0] * 100 for _, u in dated]), \
        np.array([-u[nodes, 1] * 100 for _, u in dated])


def histories_plot(path, out, note=None):
    """Settlement of the V gauges and horizontal displacement of the others (Figs. 9, 10)."""
    names, t, ux, sett = gauge_histories(path)
    fig, axes = plt.subplots(1, 2, figsize=(12, 4.2))
    for k, name in enumerate(names):
        if "-V" in name:
            axes[0].plot(t, sett[:, k], "o-", ms=3, label=name)
        else:
            axes[1].plot(t, ux[:, k], "o-", ms=3, label=name)
    for ax, which, fig_no, unit in ((axes[0], "settlement", 9, "cm, + down"),
                                    (axes[1], "horizontal displacement", 10, "cm, + downstream")):
        ax.set_title(f"{which} along the interface (cf. paper Fig. {fig_no})")
        ax.set_ylabel(f"{which} ({unit})")
        ax.set_xlabel("year")
        ax.grid(alpha=0.3)
        if ax.get_lines():
            ax.legend(fontsize=8)
    return save(fig, out, 110, add_note(fig, note))


# ------------------------------------------------------------------------ the interface

def has_contact(h5):
    """Whether the results hold contact results (decks with CONTACT cards)."""
    names = sorted(h5["stages"])
    return bool(names) and "contact" in h5["stages"][names[-1]]


def has_interface(h5):
    return "mesh/interface_elements" in h5 or has_contact(h5)


def method(h5):
    """The slab-cushion method: 'contact', 'joint', 'thin' or None (none, or mixed)."""
    if has_contact(h5):
        return "contact"
    if "mesh/interface_method" in h5:
        kinds = frozenset(int(k) for k in h5["mesh/interface_method"][...])
        return {frozenset({1}): "joint", frozenset({2}): "thin"}.get(kinds)
    return None


def construction_stages(h5):
    """Fig. 13's two stages: before the phase II slab (the stage before the second RESET)
    and the end of construction (before the third); the last stage stands in for either."""
    kinds = [text(g.attrs["kind"]).strip() for g in results.stages(h5)]
    resets = [i for i, k in enumerate(kinds) if k == "RESET"]
    return [(resets[n] - 1 if len(resets) > n else len(kinds) - 1, title)
            for n, title in ((1, "before phase II slab"), (2, "end of dam body construction"))]


def phase_openings(h5):
    """Per slab phase (line or contact pair, group), in order: its name and its opening
    width and depth (m) at every stage that has it, as (stage number, width, depth) arrays."""
    groups, phases = results.group_names(h5), {}
    for number, g in enumerate(results.stages(h5), start=1):
        for where, line_key in (("interface", "opening_line"), ("contact", "opening_pair")):
            if where in g and "opening_width" in g[where]:
                r = g[where]
                for line, group, width, depth in zip(r[line_key][...], r["opening_group"][...],
                                                     r["opening_width"][...],
                                                     r["opening_depth"][...]):
                    phases.setdefault((int(line), int(group)), []).append((number, width, depth))
    out = []
    for (line, group), rows in sorted(phases.items()):
        rows = np.array(rows)
        out.append((groups[group - 1] if 0 < group <= len(groups) else f"line {line}",
                    rows[:, 0].astype(int), rows[:, 1], rows[:, 2]))
    return out


def largest_opening_stage(h5):
    """Stage index of the largest opening width of any phase (the first stage that has
    it), or None when nothing opens."""
    rows = [(width[k], int(stage[k]) - 1) for _, stage, width, _ in phase_openings(h5)
            for k in range(len(stage))]
    top = max((w for w, _ in rows), default=0.0)
    return None if top <= 0 else min(i for w, i in rows if w == top)


def profile(h5, i, what):
    """Along the interface at stage index i, by elevation: (elevation, values, separated)
    of the active interface stations or the placed contact slave nodes; `what` is 'opening'
    (du_n or gap, m) or 'sigma_n' (kPa); separated (status open) is None for interfaces;
    None without results."""
    g = results.stages(h5)[i]
    contact = has_contact(h5)
    where, key = ("contact", "gap") if contact else ("interface", "du_n")
    if where not in g:
        return None
    r = g[where]
    keep = r["placed"][...] == 1 if contact else r["active"][...].astype(bool)
    y = r["y"][...][keep].ravel()
    v = r[key if what == "opening" else what][...][keep].ravel()
    order = np.argsort(y, kind="stable")
    return y[order], v[order], (r["status"][...][keep] == 0)[order] if contact else None


def opening_plot(h5, name, out):
    """Fig. 11: the opening (cm) along the interface at the end of each slab-casting period
    (the stage before each RESET after the first), at the last stage and at the stage of
    each phase's largest opening."""
    fig, ax = plt.subplots(figsize=(9.5, 4))
    st = results.stages(h5)
    resets = [i for i, g in enumerate(st) if text(g.attrs["kind"]).strip() == "RESET"]
    notes = {}
    for phase, stage, width, _ in phase_openings(h5):
        k = int(np.argmax(width))
        if width[k] > 0:
            notes.setdefault(int(stage[k]) - 1, []).append(phase)
    for i in sorted(set([i - 1 for i in resets[1:]] + [len(st) - 1]) | set(notes)):
        found = profile(h5, i, "opening")
        if found is not None:
            note = f", largest {', '.join(notes[i])} opening" if i in notes else ""
            ax.plot(found[0], 100 * found[1], marker=".", label=f"stage {i + 1} "
                    f"({text(st[i].attrs.get('date', '')).strip()}{note})")
    ax.set_xlabel("elevation (m)")
    ax.set_ylabel("gap at the slab's slave nodes (cm, open +)" if has_contact(h5) else
                  "relative normal displacement (cm, opening +)")
    ax.set_title(f"{name}: slab-cushion opening (cf. paper Fig. 11)")
    ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1), borderaxespad=0)
    ax.grid(alpha=0.3)
    return save(fig, out)


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
    """Fig. 13: normal stress along the interface at construction_stages and at the largest
    opening, per file; separated contact nodes hollow (their traction is zero). A value far
    off the scale (the toe corner of a contact run) is left off the axis, written at its
    edge."""
    largest = [largest_opening_stage(f) for f in files]
    npanel = 3 if any(i is not None for i in largest) else 2
    fig, axes = plt.subplots(1, npanel, figsize=(5 * npanel, 4.4), sharey=True)
    for k, (f, name) in enumerate(zip(files, names)):
        picks = construction_stages(f) + ([(largest[k], "at the largest opening")]
                                          if npanel == 3 else [])
        for ax, (i, title) in zip(axes, picks):
            ax.set_title(title)
            found = None if i is None else profile(f, i, "sigma_n")
            if found is None:
                continue
            y, sn, separated = found
            ax.plot(sn, y, marker=".", color=f"C{k}", label=f"{name} (stage {i + 1})")
            if separated is not None and separated.any():
                ax.plot(sn[separated], y[separated], "o", mfc="none", ms=7, color=f"C{k}",
                        label=f"{name} separated (stage {i + 1})")
    for ax in axes:
        ax.set_xlabel("normal stress (kPa, tension +)")
        ax.axvline(0, color="k", lw=0.5)
        ax.grid(alpha=0.3)
        points = [ln.get_xydata() for ln in ax.get_lines() if not ln.get_label().startswith("_")]
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
            ax.annotate(f"off scale: {x:.0f} kPa at El. {y:.0f} m", (left, y), xytext=(6, -3),
                        textcoords="offset points", fontsize=7, color="0.3", va="top")
    axes[0].set_ylabel("elevation (m)")
    fig.suptitle("normal stress along the interface (cf. paper Fig. 13)"
                 + ("\ncontact: at the slab's slave nodes; hollow circles: separated from the "
                    "cushion" if any(has_contact(f) for f in files) else ""), fontsize=10)
    return save(fig, out)


def slab_plot(files, names, out):
    """Fig. 14: slab stresses at the Gauss points at the end of construction, per file."""
    fig, axes = plt.subplots(1, 2, figsize=(10, 4), sharey=True)
    for f, name in zip(files, names):
        i = construction_stages(f)[1][0]
        g = results.stages(f)[i]
        if "slab" not in g:
            continue
        r = g["slab"]
        keep = g["active"][...].astype(bool)[r["element"][...] - 1]
        for ax, key, what in ((axes[0], "sigma_t", "normal stress along the slab (kPa)"),
                              (axes[1], "tau", "shear stress (kPa)")):
            ax.plot(r[key][...][keep].ravel(), r["y"][...][keep].ravel(), ".", ms=3,
                    label=f"{name} (stage {i + 1})")
            ax.set_xlabel(what)
            ax.xaxis.set_major_locator(MaxNLocator(6))
            ax.grid(alpha=0.3)
    axes[0].set_ylabel("elevation (m)")
    axes[1].legend(fontsize=7)
    fig.suptitle("slab stresses at the Gauss points, end of construction (cf. paper Fig. 14)")
    return save(fig, out)


def placed_sections(g):
    """(section index mask, elevation, crack-risk ratio) of the slab sections placed at stage
    group g: a section not yet placed has N = M = 0 exactly in the results file."""
    r = g["slab"]
    placed = (r["axial"][...] != 0.0) | (r["moment"][...] != 0.0)
    return placed, r["section_y"][...][placed], r["crack_ratio"][...][placed]


def has_crack_ratio(h5):
    """The slab's sections carry a crack-risk ratio (an FT on the slab's ELASTIC material)."""
    g = results.last_stage(h5)
    return "slab" in g and "tensile_strength" in g["slab"] and \
        bool(np.any(g["slab/tensile_strength"][...] > 0.0))


def crack_risk_plot(h5, name, out):
    """The slab's crack-risk ratio sigma_1 / f_t (the larger fibre stress of each section
    over the concrete's tensile strength) along the slope, at the end of construction and at
    the last stage (docs/theory.md section 13)."""
    fig, ax = plt.subplots(figsize=(6, 5))
    last = len(results.stages(h5)) - 1
    picks = [(construction_stages(h5)[1][0], "end of construction"), (last, "last stage")]
    for i, title in (picks if picks[0][0] != last else picks[1:]):
        g = results.stages(h5)[i]
        _, y, ratio = placed_sections(g)
        ax.plot(ratio, y, ".-", ms=4, label=f"{title} (stage {i + 1}, "
                f"{text(g.attrs.get('date', ''))})")
    ax.axvline(1.0, color="k", lw=0.8, ls="--")
    ft = results.last_stage(h5)["slab/tensile_strength"][...]
    ax.set_xlabel(f"crack-risk ratio sigma_1 / f_t (f_t = {ft[ft > 0].min() / 1000.0:g} MPa)")
    ax.set_ylabel("elevation (m)")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7)
    ax.set_title(f"{name}: slab crack risk along the slope\n(the larger fibre stress "
                 "N/h +- 6M/h^2 over f_t; > 1: tension beyond f_t)", fontsize=9)
    return save(fig, out)


def openings_history_plot(h5, name, out, reference, years=None):
    """Width (cm) and depth (m) of each phase's opening per stage (with `years`, the
    stages' times: against time), observed maxima dashed."""
    fig, axes = plt.subplots(1, 2, figsize=(11, 4))
    for k, (phase, stage, width, depth) in enumerate(phase_openings(h5)):
        x = stage if years is None else years[stage - 1]
        axes[0].plot(x, 100 * width, ".-", color=f"C{k}", label=phase)
        axes[1].plot(x, depth, ".-", color=f"C{k}", label=phase)
        observed = table5_row(reference, "in-situ", k)
        if observed is not None:
            axes[0].axhline(100 * observed[0], color=f"C{k}", ls="--", lw=0.8)
            axes[1].axhline(observed[1], color=f"C{k}", ls="--", lw=0.8)
    axes[0].set_ylabel("opening width (cm)")
    axes[1].set_ylabel("opening depth from the phase's top (m)")
    for ax in axes:
        ax.set_xlabel("stage" if years is None else "year")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8)
    note = "dashed: in-situ maxima of phases I and II (paper Table 5)" if reference else ""
    fig.suptitle(f"{name}: opening of each slab phase "
                 f"{'per stage (cf. paper Figs. 11-12)' if years is None else 'against time'}"
                 + (f"\n{note}" if note else ""), fontsize=10)
    return save(fig, out)


def stage_years(h5):
    """Time of each stage in years (its `day` attribute), or None when a stage has none."""
    days = [g.attrs.get("day") for g in results.stages(h5)]
    return None if any(d is None for d in days) else \
        np.array([1970.0 + float(d) / 365.2425 for d in days])


def pjoint_histories(h5):
    """Per PJOINT line: (line, stage numbers, years or None, opening mm, settlement mm) of
    the stages where the whole line is placed (/stages/N/pjoint, docs/results.md)."""
    years, out = stage_years(h5), {}
    for number, g in enumerate(results.stages(h5), 1):
        if "pjoint" not in g:
            continue
        p = g["pjoint"]
        for j, line in enumerate(p["line"][...]):
            if p["active"][j]:
                rows = out.setdefault(int(line), [])
                rows.append((number, None if years is None else years[number - 1],
                             1e3 * float(p["opening"][j]), 1e3 * float(p["settlement"][j])))
    return [(line, *map(np.array, zip(*rows))) for line, rows in sorted(out.items())]


def pjoint_plot(files, names, out):
    """Opening and settlement of the perimetric joints (PJOINT lines) against time (stage
    numbers when a file has an undated stage), one curve per file and line."""
    fig, axes = plt.subplots(1, 2, figsize=(11, 4))
    for f, name in zip(files, names):
        for line, stage, years, opening, settlement in pjoint_histories(f):
            x = stage if any(y is None for y in years) else years
            label = f"{name} line {line}"
            axes[0].plot(x, opening, ".-", ms=3, label=label)
            axes[1].plot(x, settlement, ".-", ms=3, label=label)
    axes[0].set_title("perimetric joint: opening")
    axes[0].set_ylabel("opening (mm, + open)")
    axes[1].set_title("perimetric joint: settlement")
    axes[1].set_ylabel("settlement normal to the face (mm)")
    for ax in axes:
        ax.set_xlabel("year (stage where undated)")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7)
    fig.suptitle("slab over plinth since placement, means over the joint's line; the shear "
                 "along the joint is out of the section's plane", fontsize=9)
    return save(fig, out)


def table5_row(reference, prefix, phase):
    """(width, depth) of the reference row starting with `prefix` for phase index 0 or 1."""
    for row in (reference or {}).get("table5", []) if phase <= 1 else ():
        if row["row"].startswith(prefix):
            return row[f"phase_{phase + 1}"]["width"], row[f"phase_{phase + 1}"]["depth"]
    return None


def table5_plot(files, names, out, reference):
    """Grouped bars: width (m) and depth (m) of phases I and II, the paper's rows and ours
    (the largest over the stages), each labelled with its value; each run (hatched) beside
    the paper's row of its method, in that row's colour."""
    paper = [(row["row"], row.get("method"), [row["phase_1"]["width"], row["phase_2"]["width"]],
              [row["phase_1"]["depth"], row["phase_2"]["depth"]])
             for row in (reference or {}).get("table5", [])]
    ours = [(f"cfrd {name}", method(f), [float(p[2].max()) for p in phases],
             [float(p[3].max()) for p in phases])
            for f, name in zip(files, names) for phases in [phase_openings(f)[:2]] if phases]
    # (label, widths, depths, colour, hatch): the paper's rows in order, each followed by the
    # runs of its method; runs of no listed method at the end.
    rows, placed = [], set()
    for j, (row, how, widths, depths) in enumerate(paper):
        rows.append((row, widths, depths, f"C{j}", None))
        for k, (label, m, w, d) in enumerate(ours):
            if how is not None and m == how:
                runs = sum(1 for r in rows if r[3] == f"C{j}") - 1
                rows.append((label, w, d, f"C{j}", ["//", "xx", "\\\\", ".."][runs % 4]))
                placed.add(k)
    rows += [(label, w, d, f"C{len(paper) + k}", "//")
             for k, (label, m, w, d) in enumerate(ours) if k not in placed]
    fig, axes = plt.subplots(1, 2, figsize=(12, 4.8))
    width = 0.8 / len(rows)
    for j, (row, widths, depths, colour, hatch) in enumerate(rows):
        x = np.arange(len(widths)) + (j - (len(rows) - 1) / 2) * width
        face = colour if hatch is None else 0.5 + 0.5 * np.array(matplotlib.colors.to_rgb(colour))
        for ax, values, fmt in ((axes[0], widths, "{:.3f}"), (axes[1], depths, "{:.1f}")):
            bars = ax.bar(x, values, width, label=row, color=face, hatch=hatch, edgecolor="k",
                          lw=0.4)
            ax.bar_label(bars, [fmt.format(v) for v in values], fontsize=6, rotation=90,
                         padding=2)
    nphase = max(len(r[1]) for r in rows)
    for ax, what in ((axes[0], "largest opening width (m)"),
                     (axes[1], "largest opening depth (m)")):
        ax.set_xticks(range(nphase), [f"phase {'I' * (k + 1)}" for k in range(nphase)])
        ax.set_ylabel(what)
        ax.margins(y=0.18)
        ax.grid(axis="y", alpha=0.3)
    axes[1].legend(fontsize=7, loc="upper left")
    head = ("slab openings against the paper's Table 5 (hatched: this run, beside the "
            "paper's row of its method)") if paper else "largest slab openings (hatched: this run)"
    fig.suptitle(head + "\nwidth: largest separation (contact: gap; joints, thin layers: "
                 "relative normal displacement); depth: opened length from the phase's top\n"
                 "(contact: down to where the gap closes; joints, thin layers: the tensile "
                 "zone)", fontsize=9)
    return save(fig, out)


# ------------------------------------------------------------------------------ the data

def write_data(directory, name, fig, field=None):
    """Every labelled curve and every bar of the figure as (panel, series, kind, index, x,
    y), and the contoured field at its nodes, with all digits."""
    directory.mkdir(parents=True, exist_ok=True)
    with open(directory / f"{name}.csv", "w", newline="") as out:
        w = csv.writer(out)
        w.writerow(["panel", "series", "kind", "index", "x", "y", "value"])
        for p, ax in enumerate(fig.axes):
            panel = ax.get_title() or f"axes {p}"
            for line in ax.get_lines():
                if not line.get_label().startswith("_"):      # outlines, reference lines
                    w.writerows([panel, line.get_label(), "line", i, repr(float(x)),
                                 repr(float(y)), ""] for i, (x, y) in enumerate(line.get_xydata()))
            ticks = {round(t, 9): lab.get_text() for t, lab in
                     zip(ax.get_xticks(), ax.get_xticklabels())}
            for container in ax.containers:
                for i, bar in enumerate(container.patches):
                    centre = bar.get_x() + bar.get_width() / 2
                    category = min(ticks.items(), key=lambda kv: abs(kv[0] - centre))[1] \
                        if ticks else repr(centre)
                    w.writerow([panel, container.get_label(), "bar", i, category,
                                repr(float(bar.get_height())), ""])
        if field is not None:
            w.writerows(["field", field["label"], "node", int(node) + 1,
                         repr(float(field["xy"][node, 0])), repr(float(field["xy"][node, 1])),
                         repr(float(field["value"][node]))] for node in field["used"])


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("results", nargs="+", help="cfrd HDF5 results files")
    ap.add_argument("--out", required=True, help="directory for the PNG files")
    ap.add_argument("--data", action="store_true",
                    help="also write the plotted numbers to OUT/data/*.csv")
    ap.add_argument("--reference", help="TOML of observed values, or 'none'")
    ap.add_argument("--stage", type=int, help="stage of the contours (default: the last)")
    args = ap.parse_args(argv)
    out = pathlib.Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    files = [h5py.File(p, "r") for p in args.results]
    names = [p.rsplit("/", 1)[-1].replace(".h5", "") for p in args.results]
    first, path = files[0], args.results[0]
    reference = find_reference(text(first.attrs.get("title", "")), args.reference)
    if not first.attrs.get("complete", 1):
        print(f"note: {path} is incomplete (complete = 0): "
              f"{text(first.attrs.get('failure', ''))}")
    written, skipped = [], []

    def save_as(name, fig, field=None):
        written.append(f"{name}.png")
        if args.data:
            write_data(out / "data", name, fig, field)
        plt.close(fig)

    def draw(name, why, plot, *args_):
        if why:
            skipped.append(f"{name} ({why})")
        else:
            save_as(name, plot(*args_, out / f"{name}.png", *([reference] if plot in (
                openings_history_plot, table5_plot) else [])))
    if len(first["stages"]) == 0:
        print(f"{path}: no stage completed, no figure")
        return 1
    note = reference["settlement"]["note"] if reference and "settlement" in reference else None
    save_as("fig07-settlement", *section_plot(path, "settlement", out / "fig07-settlement.png",
                                              args.stage, note))
    save_as("fig07-ux", *section_plot(path, "ux", out / "fig07-ux.png", args.stage))
    if "gauges" in first and len(gauge_histories(path)[1]) > 0:
        note = reference["gauges"]["note"] if reference and "gauges" in reference else None
        save_as("fig09-10-gauges", histories_plot(path, out / "fig09-10-gauges.png", note))
    else:
        skipped.append("fig09-10-gauges (no GAUGES or no dated stage)")
    none = "no INTERFACE or CONTACT"
    draw("fig11-opening", not has_interface(first) and none, opening_plot, first, names[0])
    phases = has_interface(first) and phase_openings(first)
    draw("fig12-openings", not has_interface(first) and none or not phases and
         "no slab phase with an interface", openings_history_plot, first, names[0])
    if phases:
        years = stage_years(first)
        if years is None:
            skipped.append("fig12-openings-time (a stage without a date in a date form)")
        else:
            save_as("fig12-openings-time", openings_history_plot(
                first, names[0], out / "fig12-openings-time.png", reference, years))
    pick = [(f, n) for f, n in zip(files, names) if has_interface(f)]
    draw("fig13-normal-stress", not pick and none, normal_stress_plot, [f for f, _ in pick],
         [n for _, n in pick])
    pick = [(f, n) for f, n in zip(files, names) if "slab" in results.last_stage(f)]
    draw("fig14-slab", not pick and "no SLAB", slab_plot, [f for f, _ in pick],
         [n for _, n in pick])
    draw("fig15-crack-risk", not has_crack_ratio(first) and "no SLAB with FT", crack_risk_plot,
         first, names[0])
    pick = [(f, n) for f, n in zip(files, names) if pjoint_histories(f)]
    draw("pjoint", not pick and "no perimetric joint (PJOINT line)", pjoint_plot,
         [f for f, _ in pick], [n for _, n in pick])
    draw("table5-openings", not any(phase_openings(f) for f in files) and
         "no slab phase with an interface or contact", table5_plot, files, names)
    print(f"{out}: {', '.join(written)}")
    if skipped:
        print(f"skipped: {'; '.join(skipped)}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
