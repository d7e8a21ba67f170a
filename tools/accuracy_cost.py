#!/usr/bin/env python3
"""Accuracy against time for the Tianshengqiao-I decks (issue 9, section 1; `make accuracy`;
the design, the grid and the results: docs/accuracy-cost.md).

One knob at a time around the default deck (x1 mesh, 1 increment per fill layer and slab
phase, 10 m water steps, midpoint, contact SEARCH LINEAR and TOL 1 mm, joints LOBATTO), for
each interface method; for every run its wall time and work, and the quantities users read
(QUANTITIES), each with its relative error against the knob's reference (a Richardson
extrapolation of the three finest levels when they converge monotonically with an apparent
order of at least 0.7, else the finest; Newton for the solver; LOBATTO and LINEAR for the rule
and the search). Runs under 5 s are made three times, the fastest kept; a run is cached (its
results newer than its deck and made by the same program, sha256; --force reruns). Writes the
tables (markdown) and a plot per method, error against wall time; --doc FILE replaces the
measured part of docs/accuracy-cost.md.

    python3 tools/accuracy_cost.py [--cfrd bin/cfrd] [--workdir build/accuracy]
        [--max-refine 8] [--methods bonded,joint,thin,contact] [--markdown FILE]
        [--plot-prefix PREFIX] [--doc docs/accuracy-cost.md] [--force] [--repeat 3]
    python3 tools/accuracy_cost.py --selftest      # the arithmetic, on closed forms
"""

import argparse
import hashlib
import json
import math
import os
import re
import sys
import time

import numpy as np

from cfrdtools import results, runner, tables
from cfrdtools.checks import Checks

TOML = os.path.join(runner.ROOT, "inputs", "tianshengqiao-i.toml")
MID_ROW = 709.3333333
METHODS = ("bonded", "joint", "thin", "contact")
DEFAULT = dict(refine=1, inc=1, step=10.0, solver="midpoint", tol=0.001, search="LINEAR",
               rule="LOBATTO")
QUANTITIES = [  # key, label, unit
    ("settl", "max settlement", "m"), ("settl709", "max settl. El. 709.3", "m"),
    ("c1h5", "C1-H5 ux", "m"), ("w1", "phase I width", "m"), ("d1", "phase I depth", "m"),
    ("w2", "phase II width", "m"), ("d2", "phase II depth", "m"),
    ("sigma", "peak contact stress", "kPa")]
OPENINGS = ("w1", "d1", "w2", "d2", "sigma")
ORDERED = ("mesh", "increments", "water", "tol")
# Richardson only with an apparent order of at least this: a lower one says the three levels
# are not yet in the asymptotic range, and the extrapolation (3 and more times the last
# difference) would be a guess; the finest level is the reference then.
MIN_ORDER = 0.7
REPEAT_BELOW = 5.0     # s: runs shorter than this are repeated, the fastest kept
FLOOR = 1e-5
BEGIN = "<!-- BEGIN tables written by tools/accuracy_cost.py --doc -->"
END = "<!-- END tables written by tools/accuracy_cost.py --doc -->"


def richardson(f1, f2, f3, ratio=2.0):
    """Three values at steps h, h/ratio, h/ratio^2 of f(h) = f0 + c h^p. Returns (f0, p), or
    None unless the sequence converges monotonically (the differences keep their sign and
    shrink)."""
    d1, d2 = f2 - f1, f3 - f2
    if d1 == 0.0 or d2 == 0.0 or not 0.0 < d2 / d1 < 1.0:
        return None
    q = d2 / d1
    return f3 + d2 * q / (1.0 - q), -math.log(q) / math.log(ratio)


def rel_error(value, ref):
    """|value - ref| / |ref|; None when either is missing or the reference is zero."""
    return None if value is None or ref is None or ref == 0.0 else abs(value - ref) / abs(ref)


def knee(points):
    """points: (time, error) along one knob, cheapest first. The knee is the point farthest
    below the chord from the first to the last point in log-log axes scaled to the unit
    square (Kneedle); None with fewer than three points or no point below."""
    pts = [(t, e) for t, e in points if t and e and t > 0 and e > 0]
    if len(pts) < 3:
        return None
    x, y = np.log10([p[0] for p in pts]), np.log10([p[1] for p in pts])
    if np.ptp(x) == 0 or np.ptp(y) == 0:
        return None
    xs, ys = (x - x.min()) / np.ptp(x), (y - y.min()) / np.ptp(y)
    below = ys[0] + (ys[-1] - ys[0]) * (xs - xs[0]) / (xs[-1] - xs[0]) - ys
    k = int(np.argmax(below))
    return k if below[k] > 1e-9 and 0 < k < len(pts) - 1 else None


def selftest():
    """The arithmetic against closed forms: PASS/FAIL lines for tools/run_tests.sh."""
    check = Checks("accuracy-cost")
    for f0, c, p, h0 in ((3.65, -0.4, 2.0, 1.0), (0.2475, 0.09, 1.0, 13.0),
                         (-1.5, 1e-3, 0.5, 10.0), (7.9e-3, 2e-3, 1.5, 0.25)):
        got = richardson(*[f0 + c * (h0 / 2 ** k) ** p for k in range(3)])
        check(f"richardson-f0-p={p:g}", got is not None and abs(got[0] - f0) <= 1e-12 * max(
            1.0, abs(f0)) and abs(got[1] - p) <= 1e-12 * max(1.0, p),
            f"f(h) = {f0:g} + {c:g} h^{p:g}: f0 {got[0]:.15g}, p {got[1]:.15g}" if got
            else "no extrapolation")
    # ratio 3 as well: the formula is not tied to halving
    got = richardson(*[2.0 + 0.5 * (1.0 / 3 ** k) ** 1.7 for k in range(3)], ratio=3.0)
    check("richardson-ratio-3", got is not None and abs(got[0] - 2.0) <= 1e-12
          and abs(got[1] - 1.7) <= 1e-12, f"f0 {got[0]:.15g}, p {got[1]:.15g}" if got else "none")
    check("richardson-refuses-oscillation", richardson(1.0, 2.0, 1.5) is None
          and richardson(1.0, 1.5, 2.5) is None and richardson(1.0, 1.0, 1.0) is None,
          "alternating, diverging and constant sequences give None")
    check("relative-error", rel_error(1.01, 1.0) == abs(1.01 - 1.0) and rel_error(1.0, 0.0)
          is None and rel_error(None, 1.0) is None,
          "|v - ref| / |ref|; zero reference and missing value give None")
    # error ~ t^-2 up to t = 10, flat after: the knee is the point at t = 10
    k = knee([(1, 1.0), (3, 1 / 9), (10, 1e-2), (30, 8e-3), (100, 7e-3)])
    check("knee", k == 2, f"knee index {k} (expected 2, t = 10)")
    return not check.failed


def settings_name(method, s):
    step = f"{s['step']:g}".replace(".", "p")
    name = f"{method}-x{s['refine']}-i{s['inc']}-w{step}-{s['solver']}"
    if method == "contact":
        name += f"-t{s['tol'] * 1000:g}mm".replace(".", "p") + f"-{s['search'].lower()}"
    return name + (f"-{s['rule'].lower()}" if method == "joint" else "")


def write_if_changed(path, text):
    if not os.path.exists(path) or open(path).read() != text:
        with open(path, "w") as f:
            f.write(text)


def make_deck(workdir, method, s):
    """Generate the deck (rewritten only when its text changes, so the cache holds), from a
    copy of the geometry file with the increments, water step and contact tolerance."""
    text = open(TOML).read()
    for key, value in (("fill_layer", str(s["inc"])), ("slab_phase", str(s["inc"])),
                       ("water_step", repr(float(s["step"]))),
                       ("contact_tolerance", repr(float(s["tol"])))):
        text, n = re.subn(rf"^({key}\s*=\s*\{{\s*value\s*=\s*)[^,]+", rf"\g<1>{value}", text,
                          flags=re.M)
        assert n == 1, key
    step = f"{s['step']:g}".replace(".", "p")
    geometry = os.path.join(workdir, f"geometry-i{s['inc']}-w{step}-t{s['tol']:g}.toml")
    write_if_changed(geometry, text)
    name = settings_name(method, s)
    tmp = runner.tianshengqiao(os.path.join(workdir, name + ".tmp"), "--refine", s["refine"],
                               "--interface", method, "--solver", s["solver"], "--rule",
                               s["rule"], "--geometry", geometry)
    text = open(tmp).read()
    os.remove(tmp)
    if method == "contact" and s["search"] != "LINEAR":
        lines = text.split("\n")
        hits = [i for i, ln in enumerate(lines) if ln.startswith("PAIR ")]
        assert len(hits) == 1 and lines[hits[0]][60:70] == "LINEAR    ", hits
        lines[hits[0]] = lines[hits[0]][:60] + f"{s['search']:<10s}" + lines[hits[0]][70:]
        text = "\n".join(lines)
    deck = os.path.join(workdir, name + ".dat")
    write_if_changed(deck, text)
    return deck


def load1(_done=None):
    try:
        return os.getloadavg()[0]
    except OSError:
        return float("nan")


def program_hash(path, _memo={}):
    """sha256 of the cfrd program: a cached run counts only for the program that made it
    (`make build` rewrites bin/cfrd's time stamp on every call, not its bytes)."""
    if path not in _memo:
        _memo[path] = hashlib.sha256(open(path, "rb").read()).hexdigest()
    return _memo[path]


def run_deck(cfrd, deck, force=False, repeat=3):
    """Run cfrd on deck unless cached; returns the record (also kept in DECK.run.json).
    Runs under REPEAT_BELOW seconds are made up to `repeat` times and the fastest kept, with
    the load average at its end."""
    base = deck[:-4]
    h5, meta = base + ".h5", base + ".run.json"
    t_deck, program = os.path.getmtime(deck), program_hash(cfrd)
    if not force and os.path.exists(meta) and os.path.getmtime(meta) >= t_deck:
        rec = json.load(open(meta))
        if rec.get("cfrd_sha256") == program and (rec["status"] != "ok" or (
                os.path.exists(h5) and os.path.getmtime(h5) >= t_deck)):
            rec["cached"] = True
            return rec
    for old in (h5, base + "-openings.csv"):
        if os.path.exists(old):
            os.remove(old)
    # repeat only short runs that succeed: a shared machine's noise is largest there
    done, load = runner.best_of(cfrd, deck, repeat, REPEAT_BELOW, load1)
    rec = dict(wall=done.wall, load1=load, status="ok", cfrd_sha256=program)
    if done.returncode != 0 or not os.path.exists(h5):
        msg = [ln.strip() for ln in (done.stderr + "\n" + done.stdout).splitlines() if ln.strip()]
        # cfrd's diagnostic: the line naming the stage and what failed, and what follows
        start = max([i for i, ln in enumerate(msg) if ln.startswith("cfrd:")] or [0])
        rec.update(status="failed",
                   error=" ".join(msg[start:start + 4]).split("; stopped")[0][:300] or "?")
    else:
        rec.update(read_results(base))
    with open(meta, "w") as f:
        json.dump(rec, f, indent=1)
    rec["cached"] = False
    return rec


def read_results(base):
    with results.open_results(base + ".h5") as f:
        out = results.summary(f, ("contact_iterations",))
        out["contact_iterations"] = int(out["contact_iterations"])
        x, last = f["mesh/coordinates"][...], results.last_stage(f)
        u = results.field(last, "displacement_total")
        row = np.abs(x[:, 1] - MID_ROW) < 1e-3
        names, nodes = results.gauges(f)
        out.update(settl=float(-u[:, 1].min()), c1h5=float(u[nodes[names.index("C1-H5")], 0]),
                   settl709=float(np.max(-u[row, 1])) if row.any() else None, sigma=None)
        for key in ("contact", "interface"):
            if key in last:
                g = last[key]
                sn, y = np.asarray(g["sigma_n"][...], float), np.asarray(g["y"][...], float)
                keep = y > float(x[:, 1].min()) + 1e-6
                if key == "contact":
                    keep &= np.asarray(g["placed"][...]) > 0
                out["sigma"] = float(max(0.0, -sn[keep].min())) if keep.any() else None
    if os.path.exists(base + "-openings.csv"):
        found = results.openings(base + "-openings.csv")
        for phase, (w, d) in ((1, ("w1", "d1")), (2, ("w2", "d2"))):
            out[w], out[d] = found.get(f"SLAB{phase}", (None, None))
    return out


def knob_levels(method, max_refine):
    """[(knob, level label, settings)] around the default, cheapest first."""
    out = []

    def add(knob, label, **change):
        out.append((knob, label, dict(DEFAULT, **change)))
    for r in (r for r in (1, 2, 4, 8) if r <= max_refine):
        add("mesh", f"x{r}", refine=r)
    for n in (1, 2, 4, 8):
        add("increments", f"{n}/layer", inc=n)
    for w in (10.0, 5.0, 2.5):
        add("water", f"{w:g} m", step=w)
    for r in (1, 2):
        add("solver", f"midpoint x{r}", refine=r)
        add("solver", f"Newton x{r}", refine=r, solver="newton")
    if method == "contact":
        for t in (0.01, 0.001, 0.0001, 0.0):
            add("tol", f"{t * 1000:g} mm", tol=t)
        for r in (r for r in (1, 2, 4) if r <= max_refine):
            add("search", f"LINEAR x{r}", refine=r)
            add("search", f"RPIM x{r}", refine=r, search="RPIM")
    if method == "joint":
        for r in (1, 2):
            add("rule", f"LOBATTO x{r}", refine=r)
            add("rule", f"GAUSS x{r}", refine=r, rule="GAUSS")
    # knobs together, at the knees (docs/accuracy-cost.md), against the best estimate
    add("combined", "x2, 2/layer, 5 m", refine=2, inc=2, step=5.0)
    if method == "contact" and max_refine >= 4:
        add("combined", "x4, 2/layer, 5 m", refine=4, inc=2, step=5.0)
    return out


def quantities_of(method):
    return [q for q in QUANTITIES if q[0] not in OPENINGS] if method == "bonded" else QUANTITIES


def errors_for(method, knob, runs):
    """Adds run['err'][key] (relative error against the knob's reference) and run['refval']
    to each run; returns the references {key: (value, how)}. An ordered knob's reference:
    Richardson of the three finest levels when they converge monotonically (consecutive
    levels of ratio 2: mesh, increments, water; not the tolerance), else the finest level
    that ran. Paired knobs, (default choice, other choice) at each mesh: Newton for the
    solver, LOBATTO for the rule, LINEAR for the search."""
    keys = [k for k, _, _ in quantities_of(method)]
    if knob in ORDERED:
        ok, refs = [r for r in runs if r["status"] == "ok"], {}
        for key in keys:
            vals = [v for v in (r.get(key) for r in ok) if v is not None]
            if not vals:
                continue
            rich = richardson(*vals[-3:]) if knob != "tol" and len(ok) == len(runs) and \
                len(vals) >= 3 and len(vals) == len(ok) else None
            refs[key] = (rich[0], f"Richardson (p = {rich[1]:.2f})") if rich and \
                rich[1] >= MIN_ORDER else (vals[-1], f"finest ({ok[-1]['label']})")
        for r in runs:
            r["refval"] = {k: refs.get(k, (None,))[0] for k in keys}
            r["err"] = {k: rel_error(r.get(k), r["refval"][k]) for k in keys}
        return refs
    for a, b in zip(runs[0::2], runs[1::2]):
        ref = b if knob == "solver" else a
        for r in (a, b):
            good = ref["status"] == "ok"
            r["err"] = {k: rel_error(r.get(k), ref.get(k)) if good and r["status"] == "ok"
                        else None for k in keys}
            r["refval"] = {k: ref.get(k) if good else None for k in keys}
            r["ref_failed"] = not good
    label = {"solver": "Newton", "rule": "LOBATTO", "search": "LINEAR"}[knob]
    return {k: (None, label + " at the same mesh") for k in keys}


def best_estimate(method, knobs):
    """The converged value of each quantity to first order, the knobs' errors adding: the
    mesh reference plus the increments' and the water step's corrections at x1 (reference
    minus the default run). No solver correction: the midpoint method's out-of-balance
    vanishes as the increments are refined, so the increments' reference includes it."""
    default, best = knobs["mesh"]["runs"][0], {}
    for k, _, _ in quantities_of(method):
        parts = [knobs[kn]["refs"].get(k, (None,))[0] for kn in ("mesh", "increments", "water")]
        d = default.get(k) if default["status"] == "ok" else None
        best[k] = None if d is None or None in parts else \
            parts[0] + (parts[1] - d) + (parts[2] - d)
    return best


def run_study(args):
    os.makedirs(args.workdir, exist_ok=True)
    t_start, study, done = time.perf_counter(), {}, {}
    methods = [m for m in args.methods.split(",") if m]
    plan = [(m, *level) for m in methods for level in knob_levels(m, args.max_refine)]
    # cheap runs first (estimated cost: elements x 10 for Newton): x8 last
    plan.sort(key=lambda p: p[3]["refine"] ** 2 * (10 if p[3]["solver"] == "newton" else 1))
    for method, knob, label, s in plan:
        name = settings_name(method, s)
        if name not in done:
            rec = run_deck(args.cfrd, make_deck(args.workdir, method, s), args.force,
                           args.repeat)
            rec["name"], done[name] = name, rec
            print(f"  {name}: {rec['status']} {rec['wall']:.2f} s (load {rec['load1']:.2f})"
                  f"{' cached' if rec['cached'] else ''} {rec.get('error', '')}",
                  file=sys.stderr, flush=True)
    for method in methods:
        study[method] = {}
        for knob, label, s in knob_levels(method, args.max_refine):
            study[method].setdefault(knob, []).append(dict(done[settings_name(method, s)],
                                                           label=label, settings=s))
        for knob, runs in study[method].items():
            if knob != "combined":
                study[method][knob] = dict(runs=runs, refs=errors_for(method, knob, runs))
        runs = study[method].pop("combined")
        best = best_estimate(method, study[method])
        for r in runs:
            r["err"] = {k: rel_error(r.get(k), best[k]) if r["status"] == "ok" else None
                        for k, _, _ in quantities_of(method)}
            r["refval"] = dict(best)
        study[method]["combined"] = dict(runs=runs, refs={k: (v, "best estimate")
                                                          for k, v in best.items()})
    return study, sum(r["wall"] for r in done.values()), time.perf_counter() - t_start, \
        len(done)


def fmt_val(v, unit):
    return "-" if v is None else f"{v:.0f}" if unit == "kPa" else f"{v:.4f}"


def fmt_err(e):
    return "-" if e is None else "0" if e == 0 else f"{100 * e:.2g} %" if e < 0.1 else \
        f"{100 * e:.0f} %"


def method_table(method, knobs):
    qs = quantities_of(method)
    head = ["knob", "setting", "wall s", "load", "incr.", "fact.", "iter."] + \
        [f"{lab} ({unit})" for _, lab, unit in qs]
    lines = [tables.row(head), "|:---|:---|" + "---:|" * (len(head) - 2)]
    for knob, data in knobs.items():
        for r in data["runs"]:
            cells = [knob, r["label"], f"{r['wall']:.2f}", f"{r['load1']:.1f}"]
            if r["status"] != "ok":
                cells += ["-", "-", "-", f"**failed**: {r.get('error', '')}"] + [""] * (len(qs) - 1)
            else:
                it = r.get("iterations", 0)
                cells += [str(r["increments"]), str(r["factorisations"]), str(it) if method !=
                          "contact" else f"{it}+{r.get('contact_iterations', 0)}c"]
                for k, _, unit in qs:
                    v, e = r.get(k), r["err"].get(k)
                    cell = "none" if k in OPENINGS and v == 0.0 else fmt_val(v, unit)
                    if v is not None and e is not None:
                        cell += f" ({fmt_err(e)})"
                    elif r.get("ref_failed"):
                        cell += " (no ref.)"
                    elif v is not None and v != 0.0 and r["refval"].get(k) == 0.0:
                        cell += " (ref. 0)"
                    cells.append(cell)
            lines.append(tables.row(cells))
        if knob in ORDERED or knob == "combined":
            refs = [data["refs"].get(k, (None, "")) + (unit,) for k, _, unit in qs]
            lines.append(tables.row(
                [knob, "**reference**" if knob != "combined" else "**best estimate**"]
                + [""] * 5 + [fmt_val(v, unit) + (" R" if how.startswith("Richardson") else "")
                              for v, how, unit in refs]))
    return "\n".join(lines)


def solves(r):
    """Deterministic cost of a run: factorisations, Newton and contact iterations."""
    return r.get("factorisations", 0) + r.get("iterations", 0) + r.get("contact_iterations", 0)


def cheapest(method, knobs, tol):
    """Per quantity and knob, the cheapest level whose own error is within tol: for mesh,
    increments and water step (coarsest first) the first level from which on every level is
    within tol (a non-monotone sequence can pass through the reference by chance; wall times
    of sub-second runs are noise on a shared machine); the solver: midpoint where it is
    within tol of Newton; the contact TOL, whose levels cost about the same, the fewest
    solves."""
    out = {}
    for k, _, _ in quantities_of(method):
        picks = out[k] = {}
        for knob in (kn for kn in ("mesh", "increments", "water", "solver", "tol") if kn in knobs):
            data = knobs[knob]
            ok = [r for r in (data["runs"] if knob != "solver" else data["runs"][0::2])
                  if r["status"] == "ok"]
            within = [r["err"].get(k) is not None and r["err"][k] <= tol for r in ok]
            if knob in ("mesh", "increments", "water"):
                good = [r for i, r in enumerate(ok) if all(within[i:])]
            else:
                good = [r for r, g in zip(ok, within) if g]
            refv, how = data["refs"].get(k, (None, ""))
            if knob == "tol" and good:
                good = [min(good, key=solves)]
            if good:
                last = knob != "solver" and good[0] is ok[-1] and not how.startswith("Richardson")
                picks[knob] = good[0]["label"] + (" only (the reference)" if last else "")
            elif knob == "solver":
                errs = [r["err"].get(k) for r in ok]
                picks[knob] = ("- (Newton failed)" if not [r for r in data["runs"][1::2]
                                                          if r["status"] == "ok"]
                               else "n/a (no opening)" if all(e is None for e in errs)
                               else "Newton")
            else:
                picks[knob] = "n/a (no opening)" if refv == 0.0 else "not reached"
    return out


def plot(study, prefix):
    from cfrdtools.plots import plt, save
    colours = {"mesh": "C0", "increments": "C1", "water": "C2", "solver": "C3", "tol": "C4",
               "search": "C5", "rule": "C6", "combined": "C8"}
    paths = []
    for method, knobs in study.items():
        qs = quantities_of(method)
        ncol, nrow = 4, math.ceil(len(qs) / 4)
        fig, axes = plt.subplots(nrow, ncol, figsize=(4 * ncol, 3.3 * nrow), squeeze=False)
        for ax, (k, lab, unit) in zip(axes.ravel(), qs):
            for knob, data in knobs.items():
                pts = [(r["wall"], max(FLOOR, r["err"][k])) for r in data["runs"]
                       if r["status"] == "ok" and r["err"].get(k)]
                fails = [r["wall"] for r in data["runs"] if r["status"] != "ok"]
                if fails:
                    ax.plot(fails, [1.0] * len(fails), "x", color=colours[knob], ms=9,
                            label=f"{knob}: failed")
                if pts:
                    ax.loglog(*zip(*pts), "o-" if knob in ORDERED else "D" if knob ==
                              "combined" else "s", color=colours[knob], label=knob, ms=4)
            for level in (0.01, 0.05):
                ax.axhline(level, color="0.6", lw=0.7, ls="--")
            d = knobs["mesh"]["runs"][0]          # the default deck
            if d["status"] == "ok" and d["err"].get(k):
                ax.plot([d["wall"]], [max(FLOOR, d["err"][k])], "*", color="k", ms=11,
                        zorder=5, label="default deck (mesh error)")
            ax.set_ylim(bottom=FLOOR / 2)
            ax.set_title(lab, fontsize=9)
            ax.set_xlabel("wall time (s)", fontsize=8)
            ax.set_ylabel("relative error", fontsize=8)
            ax.tick_params(labelsize=7)
            ax.grid(True, which="both", lw=0.3, alpha=0.5)
        for ax in axes.ravel()[len(qs):]:
            ax.axis("off")
        legend = {}
        for ax in axes.ravel():
            for h, lab in zip(*ax.get_legend_handles_labels()):
                legend.setdefault(lab, h)
        fig.legend(list(legend.values()), list(legend), loc="lower center",
                   ncol=min(len(legend), 8), fontsize=8)
        fig.suptitle(f"Tianshengqiao-I, {method}: relative error against wall time, one knob "
                     f"at a time (dashed: 1 % and 5 %; x at 1: failed run; errors below "
                     f"{FLOOR:g} drawn at {FLOOR:g}; zero errors, the references, not drawn)",
                     fontsize=10)
        path = f"{prefix}-{method}.png"
        os.makedirs(os.path.dirname(path) or ".", exist_ok=True)
        save(fig, path, 90, (0, 0.05, 1, 0.95), close=True)
        paths.append(path)
    return paths


def report(study, total, n_runs, plots, args):
    md = [f"Machine: {runner.machine()}. {n_runs} distinct runs, {total:.0f} s of cfrd wall time "
          f"in all (one process at a time; `load` is the 1-minute load average at the end of "
          f"each run: the machine is shared).", ""]
    for method, knobs in study.items():
        md += [f"#### {method}", "", method_table(method, knobs), ""]
    md += ["#### Cheapest settings per quantity", "",
           "Per knob, the cheapest level from which on its own error stays within 1 % / 5 % "
           "(mesh, increments, water step; the solver: midpoint where it is within the "
           "tolerance of Newton on the same mesh), the other knobs at the default.", ""]
    contact = "contact" in study
    for tol in (0.01, 0.05):
        md += [f"**Within {100 * tol:.0f} %**", "",
               "| method | quantity | mesh | increments | water step | solver |"
               + (" contact TOL |" if contact else ""),
               "|:---|:---|:---|:---|:---|:---|" + (":---|" if contact else "")]
        for method, knobs in study.items():
            picks = cheapest(method, knobs, tol)
            md += [tables.row([method, lab] + [picks[k].get(kn, "-") for kn in (
                "mesh", "increments", "water", "solver") + (("tol",) if contact else ())])
                for k, lab, _ in quantities_of(method)]
        md.append("")
    md += ["#### Knees", "",
           "Per quantity, the knee of each knob's error against wall time (log-log; the point "
           "farthest below the chord from the cheapest to the dearest point with a non-zero "
           "error; `-`: fewer than three such points, or none below the chord).", "",
           "| method | quantity | mesh | increments | water step |", "|:---|:---|:---|:---|:---|"]
    for method, knobs in study.items():
        for k, lab, _ in quantities_of(method):
            cells = []
            for knob in ("mesh", "increments", "water"):
                runs = [r for r in knobs[knob]["runs"] if r["status"] == "ok" and r["err"].get(k)]
                i = knee([(r["wall"], r["err"][k]) for r in runs])
                cells.append(runs[i]["label"] if i is not None else "-")
            md.append(tables.row([method, lab] + cells))
    md.append("")
    where = os.path.dirname(os.path.abspath(args.doc or args.markdown))
    for p in plots:
        md += [f"![{os.path.basename(p)[:-4].rsplit('-', 1)[-1]}: error against wall time]"
               f"({os.path.relpath(p, where)})", ""]
    return "\n".join(md)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--cfrd", default=os.path.join(runner.ROOT, "bin", "cfrd"))
    ap.add_argument("--workdir", default=os.path.join(runner.ROOT, "build", "accuracy"))
    ap.add_argument("--max-refine", type=int, default=8, choices=[2, 4, 8],
                    help="finest mesh of the mesh axis (x8 is 4 of the grid's ~6 minutes)")
    ap.add_argument("--methods", default=",".join(METHODS))
    ap.add_argument("--markdown", default=os.path.join(runner.ROOT, "build", "accuracy",
                                                       "accuracy-cost-tables.md"))
    ap.add_argument("--plot-prefix", default=os.path.join(runner.ROOT, "build", "accuracy",
                                                          "accuracy-cost"))
    ap.add_argument("--json", help="also write every run's record here")
    ap.add_argument("--doc", help="replace the measured part of this markdown file (between "
                    "its BEGIN and END markers) with the tables, e.g. docs/accuracy-cost.md")
    ap.add_argument("--force", action="store_true", help="rerun cached runs")
    ap.add_argument("--repeat", type=int, default=3, help=f"runs under {REPEAT_BELOW:g} s are "
                    "made this many times, the fastest kept")
    ap.add_argument("--selftest", action="store_true")
    args = ap.parse_args(argv)
    if args.selftest:
        return 0 if selftest() else 1
    args.cfrd = os.path.abspath(args.cfrd)
    study, total, elapsed, n = run_study(args)
    text = report(study, total, n, plot(study, args.plot_prefix), args)
    os.makedirs(os.path.dirname(os.path.abspath(args.markdown)), exist_ok=True)
    with open(args.markdown, "w") as f:
        f.write(text)
    if args.doc:
        doc = open(args.doc).read()
        i, j = doc.index(BEGIN), doc.index(END)
        with open(args.doc, "w") as f:
            f.write(doc[:i + len(BEGIN)] + "\n" + text.rstrip() + "\n" + doc[j:])
    if args.json:
        with open(args.json, "w") as f:
            json.dump(study, f, indent=1, default=str)
    print(text)
    print(f"accuracy-cost: {n} runs, {total:.0f} s of cfrd wall time, {elapsed:.0f} s elapsed;"
          f" tables in {args.markdown}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
