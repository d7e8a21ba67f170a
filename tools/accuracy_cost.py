#!/usr/bin/env python3
"""Accuracy against time for the Tianshengqiao-I decks (issue 9, section 1; `make accuracy`).

One knob at a time around the default deck (x1 mesh, 1 increment per fill layer and slab
phase, water step 10 m, midpoint, contact SEARCH LINEAR and TOL 1 mm, joints LOBATTO), for
each interface method (bonded, joint, thin, contact):

  mesh        x1, x2, x4, x8 (x8 with --max-refine 8, the default)
  increments  1, 2, 4, 8 per fill layer and slab phase (x1)
  water       reservoir step 10, 5, 2.5 m (x1)
  solver      midpoint against Newton to 1e-10 (x1 and x2; Newton is the reference)
  tol         contact TOL 10, 1, 0.1 mm, 0 (contact decks, x1)
  search      contact SEARCH RPIM against LINEAR (x1, x2, x4)
  rule        joint GAUSS against LOBATTO (x1, x2)

For every run: process wall time, the 1-minute load average at its end, increments,
factorisations, Newton and contact iterations, and the quantities users read (the August
1999 state and the history's largest openings): the maximum settlement, the largest
settlement on the mid-height row line (El. 709.33 m, a line of every mesh), the horizontal
displacement of gauge C1-H5, the phase I and II opening width and depth (largest over the
history, DECK-openings.csv), and the peak contact stress (largest compressive sigma_n on the
slab-cushion interface at the last stage, the toe node on the plinth left out: a point force
that grows without bound as the mesh is refined, docs/tianshengqiao.md section 8).

Errors are relative, against each knob's own reference: a Richardson extrapolation of the
three finest levels of an ordered knob (mesh, increments, water step; refinement ratio 2)
when they converge monotonically with an apparent order of at least 0.7, else the finest
level that ran; Newton for the solver; LOBATTO for the rule, LINEAR for the search (these
two are sensitivities, not errors). A failed run is reported as failed, with cfrd's message.

One cfrd process at a time (the machine is shared); runs under 5 s are made three times and
the fastest kept. Results are cached: a run whose HDF5 (or recorded failure) is newer than
its deck, made by the same cfrd program (sha256), is not run again (--force reruns); a deck
is rewritten only when its text changes.

Output: the tables (markdown) and one plot per method, error against wall time, log-log,
one curve per knob; --doc FILE also replaces the measured part of docs/accuracy-cost.md.

    python3 tools/accuracy_cost.py [--cfrd bin/cfrd] [--workdir build/accuracy]
        [--max-refine 8] [--methods bonded,joint,thin,contact] [--markdown FILE]
        [--plot-prefix PREFIX] [--doc docs/accuracy-cost.md] [--force] [--repeat 3]
    python3 tools/accuracy_cost.py --selftest      # the arithmetic, on closed forms
"""

import argparse
import csv
import json
import math
import os
import re
import subprocess
import sys
import time

import numpy as np

from cfrdtools import results, runner

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
GEN = os.path.join(HERE, "tianshengqiao.py")
TOML = os.path.join(ROOT, "inputs", "tianshengqiao-i.toml")
MID_ROW = 709.3333333
METHODS = ("bonded", "joint", "thin", "contact")
DEFAULT = dict(refine=1, inc=1, step=10.0, solver="midpoint", tol=0.001, search="LINEAR",
               rule="LOBATTO")
QUANTITIES = [  # key, label, unit
    ("settl", "max settlement", "m"),
    ("settl709", "max settl. El. 709.3", "m"),
    ("c1h5", "C1-H5 ux", "m"),
    ("w1", "phase I width", "m"),
    ("d1", "phase I depth", "m"),
    ("w2", "phase II width", "m"),
    ("d2", "phase II depth", "m"),
    ("sigma", "peak contact stress", "kPa"),
]
OPENINGS = ("w1", "d1", "w2", "d2", "sigma")
BEGIN = "<!-- BEGIN tables written by tools/accuracy_cost.py --doc -->"
END = "<!-- END tables written by tools/accuracy_cost.py --doc -->"


# ------------------------------------------------------------------------------------------
# Arithmetic
# ------------------------------------------------------------------------------------------

def richardson(f1, f2, f3, ratio=2.0):
    """Three values at steps h, h/ratio, h/ratio^2 of f(h) = f0 + c h^p. Returns (f0, p), or
    None unless the sequence converges monotonically (the differences keep their sign and
    shrink)."""
    d1, d2 = f2 - f1, f3 - f2
    if d1 == 0.0 or d2 == 0.0:
        return None
    q = d2 / d1
    if not 0.0 < q < 1.0:
        return None
    p = -math.log(q) / math.log(ratio)
    return f3 + d2 * q / (1.0 - q), p


def rel_error(value, ref):
    """|value - ref| / |ref|; None when either is missing or the reference is zero."""
    if value is None or ref is None or ref == 0.0:
        return None
    return abs(value - ref) / abs(ref)


def knee(points):
    """points: (time, error) along one knob, cheapest first, errors > 0. The knee is the
    point farthest below the chord from the first to the last point in log-log axes scaled
    to the unit square (Kneedle); None with fewer than three points or no point below."""
    pts = [(t, e) for t, e in points if t and e and t > 0 and e > 0]
    if len(pts) < 3:
        return None
    x = np.log10([p[0] for p in pts])
    y = np.log10([p[1] for p in pts])
    if np.ptp(x) == 0 or np.ptp(y) == 0:
        return None
    xs, ys = (x - x.min()) / np.ptp(x), (y - y.min()) / np.ptp(y)
    chord = ys[0] + (ys[-1] - ys[0]) * (xs - xs[0]) / (xs[-1] - xs[0])
    below = chord - ys
    k = int(np.argmax(below))
    return k if below[k] > 1e-9 and 0 < k < len(pts) - 1 else None


def selftest():
    """The arithmetic against closed forms: PASS/FAIL lines for tools/run_tests.sh."""
    results = []

    def check(name, ok, detail):
        results.append(ok)
        print(f"{'PASS' if ok else 'FAIL'} accuracy-cost/{name}: {detail}")

    for f0, c, p, h0 in ((3.65, -0.4, 2.0, 1.0), (0.2475, 0.09, 1.0, 13.0),
                         (-1.5, 1e-3, 0.5, 10.0), (7.9e-3, 2e-3, 1.5, 0.25)):
        f = [f0 + c * (h0 / 2 ** k) ** p for k in range(3)]
        got = richardson(*f)
        ok = got is not None and abs(got[0] - f0) <= 1e-12 * max(1.0, abs(f0)) \
            and abs(got[1] - p) <= 1e-12 * max(1.0, p)
        check(f"richardson-f0-p={p:g}", ok,
              f"f(h) = {f0:g} + {c:g} h^{p:g}: f0 {got[0]:.15g}, p {got[1]:.15g}" if got
              else "no extrapolation")
    # ratio 3 as well: the formula is not tied to halving
    f = [2.0 + 0.5 * (1.0 / 3 ** k) ** 1.7 for k in range(3)]
    got = richardson(*f, ratio=3.0)
    check("richardson-ratio-3", got is not None and abs(got[0] - 2.0) <= 1e-12
          and abs(got[1] - 1.7) <= 1e-12, f"f0 {got[0]:.15g}, p {got[1]:.15g}" if got else "none")
    # a sequence that does not converge monotonically is not extrapolated
    check("richardson-refuses-oscillation", richardson(1.0, 2.0, 1.5) is None
          and richardson(1.0, 1.5, 2.5) is None and richardson(1.0, 1.0, 1.0) is None,
          "alternating, diverging and constant sequences give None")
    check("relative-error", rel_error(1.01, 1.0) == abs(1.01 - 1.0)
          and rel_error(1.0, 0.0) is None and rel_error(None, 1.0) is None,
          "|v - ref| / |ref|; zero reference and missing value give None")
    # knee: error ~ t^-2 up to t = 10, flat after: the knee is the point at t = 10
    pts = [(1, 1.0), (3, 1 / 9), (10, 1e-2), (30, 8e-3), (100, 7e-3)]
    check("knee", knee(pts) == 2, f"knee index {knee(pts)} (expected 2, t = 10)")
    return all(results)


# ------------------------------------------------------------------------------------------
# Runs
# ------------------------------------------------------------------------------------------

def settings_name(method, s):
    tol = f"{s['tol'] * 1000:g}mm".replace(".", "p")
    step = f"{s['step']:g}".replace(".", "p")
    name = f"{method}-x{s['refine']}-i{s['inc']}-w{step}-{s['solver']}"
    if method == "contact":
        name += f"-t{tol}-{s['search'].lower()}"
    if method == "joint":
        name += f"-{s['rule'].lower()}"
    return name


def write_if_changed(path, text):
    if os.path.exists(path):
        with open(path) as f:
            if f.read() == text:
                return False
    with open(path, "w") as f:
        f.write(text)
    return True


def geometry_file(workdir, s):
    """A copy of the geometry file with the increments, water step and contact tolerance."""
    with open(TOML) as f:
        text = f.read()
    subs = (("fill_layer", str(s["inc"])), ("slab_phase", str(s["inc"])),
            ("water_step", repr(float(s["step"]))), ("contact_tolerance", repr(float(s["tol"]))))
    for key, value in subs:
        text, n = re.subn(rf"^({key}\s*=\s*\{{\s*value\s*=\s*)[^,]+", rf"\g<1>{value}", text,
                          flags=re.M)
        assert n == 1, key
    step = f"{s['step']:g}".replace(".", "p")
    path = os.path.join(workdir, f"geometry-i{s['inc']}-w{step}-t{s['tol']:g}.toml")
    write_if_changed(path, text)
    return path


def make_deck(workdir, method, s):
    """Generate the deck (rewritten only when its text changes, so the cache holds)."""
    name = settings_name(method, s)
    deck = os.path.join(workdir, name + ".dat")
    tmp = os.path.join(workdir, name + ".tmp")
    cmd = [sys.executable, GEN, "--refine", str(s["refine"]), "--interface", method,
           "--solver", s["solver"], "--rule", s["rule"], "--geometry",
           geometry_file(workdir, s), "--deck", tmp]
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL)
    with open(tmp) as f:
        text = f.read()
    os.remove(tmp)
    if method == "contact" and s["search"] != "LINEAR":
        lines = text.split("\n")
        hits = [i for i, l in enumerate(lines) if l.startswith("PAIR ")]
        assert len(hits) == 1
        line = lines[hits[0]]
        assert line[60:70] == "LINEAR    ", line
        lines[hits[0]] = line[:60] + f"{s['search']:<10s}" + line[70:]
        text = "\n".join(lines)
    write_if_changed(deck, text)
    return deck


def load1():
    try:
        return os.getloadavg()[0]
    except OSError:
        return float("nan")


def program_hash(path, _memo={}):
    """sha256 of the cfrd program: a cached run counts only for the program that made it
    (`make build` rewrites bin/cfrd's time stamp on every call, not its bytes)."""
    if path not in _memo:
        import hashlib
        with open(path, "rb") as f:
            _memo[path] = hashlib.sha256(f.read()).hexdigest()
    return _memo[path]


REPEAT_BELOW = 5.0     # s: runs shorter than this are repeated, the fastest kept


def run_deck(cfrd, deck, force=False, repeat=3):
    """Run cfrd on deck unless cached; returns the record (also kept in DECK.run.json).
    Runs under REPEAT_BELOW seconds are made up to `repeat` times and the fastest kept, with
    the load average at its end."""
    base = deck[:-4]
    h5, meta = base + ".h5", base + ".run.json"
    t_deck = os.path.getmtime(deck)
    program = program_hash(cfrd)
    if not force and os.path.exists(meta) and os.path.getmtime(meta) >= t_deck:
        with open(meta) as f:
            rec = json.load(f)
        fresh = rec.get("cfrd_sha256") == program
        if fresh and (rec["status"] != "ok" or (os.path.exists(h5)
                                                and os.path.getmtime(h5) >= t_deck)):
            rec["cached"] = True
            return rec
    for old in (h5, base + "-openings.csv"):
        if os.path.exists(old):
            os.remove(old)
    best = None
    for attempt in range(repeat):
        done = runner.run(cfrd, deck, check=False)
        wall = done.wall
        if best is None or wall < best[0]:
            best = (wall, load1(), done)
        # repeat only short runs that succeed: a shared machine's noise is largest there
        if done.returncode != 0 or wall > REPEAT_BELOW:
            break
    wall, load, done = best
    rec = dict(wall=wall, load1=load, status="ok", cfrd_sha256=program)
    if done.returncode != 0 or not os.path.exists(h5):
        msg = [l.strip() for l in (done.stderr + "\n" + done.stdout).splitlines() if l.strip()]
        rec["status"] = "failed"
        # cfrd's diagnostic: the line naming the stage and what failed, and what follows
        start = max([i for i, l in enumerate(msg) if l.startswith("cfrd:")] or [0])
        rec["error"] = " ".join(msg[start:start + 4]).split("; stopped")[0][:300] or "?"
    else:
        rec.update(read_results(base))
    with open(meta, "w") as f:
        json.dump(rec, f, indent=1)
    rec["cached"] = False
    return rec


def read_results(base):
    import h5py
    out = {}
    with h5py.File(base + ".h5") as f:
        st = results.stages(f)
        out["stages"] = len(st)
        out["increments"] = sum(int(g.attrs["increments"]) for g in st)
        out["factorisations"] = sum(int(g.attrs["factorisations"]) for g in st)
        out["iterations"] = sum(int(g.attrs["iterations"]) for g in st)
        out["contact_iterations"] = int(sum(
            float(np.ravel(g["solver"].attrs.get("contact_iterations", 0))[0]) for g in st))
        out["analysis"] = float(np.ravel(f["run"].attrs["wall_time"])[0])
        x = f["mesh/coordinates"][...]
        last = st[-1]
        u = last["displacement_total"][...]
        out["settl"] = float(-u[:, 1].min())
        row = np.abs(x[:, 1] - MID_ROW) < 1e-3
        out["settl709"] = float(np.max(-u[row, 1])) if row.any() else None
        names = [n.decode().strip() if isinstance(n, bytes) else str(n).strip()
                 for n in f["gauges/names"][...]]
        nodes = f["gauges/nodes"][...] - 1
        out["c1h5"] = float(u[nodes[names.index("C1-H5")], 0])
        base_y = float(x[:, 1].min())
        sigma = None
        for key in ("contact", "interface"):
            if key in last:
                g = last[key]
                sn = np.asarray(g["sigma_n"][...], float)
                y = np.asarray(g["y"][...], float)
                if key == "contact":
                    keep = (np.asarray(g["placed"][...]) > 0) & (y > base_y + 1e-6)
                else:
                    keep = y > base_y + 1e-6
                sigma = float(max(0.0, -sn[keep].min())) if keep.any() else None
        out["sigma"] = sigma
    path = base + "-openings.csv"
    if os.path.exists(path):
        with open(path) as f:     # skip the '# cfrd run_id' comment line
            rows = list(csv.DictReader(line for line in f if not line.startswith("#")))
        for phase, (w, d) in ((1, ("w1", "d1")), (2, ("w2", "d2"))):
            sel = [r for r in rows if r["group"].strip() == f"SLAB{phase}"]
            out[w] = max((float(r["width_m"]) for r in sel), default=None)
            out[d] = max((float(r["depth_m"]) for r in sel), default=None)
    return out


# ------------------------------------------------------------------------------------------
# The study
# ------------------------------------------------------------------------------------------

def knob_levels(method, max_refine):
    """[(knob, level label, settings, ordered)] around the default, cheapest first."""
    out = []

    def add(knob, label, **change):
        s = dict(DEFAULT)
        s.update(change)
        out.append((knob, label, s))
    for r in (1, 2, 4, 8):
        if r <= max_refine:
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
        for r in (1, 2, 4):
            if r <= max_refine:
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


def best_estimate(method, knobs):
    """The converged value of each quantity to first order, the knobs' errors adding: the
    mesh reference plus the increments' and the water step's corrections at x1 (reference
    minus the default run). No solver correction: the midpoint method's out-of-balance
    vanishes as the increments are refined, so the increments' reference includes it."""
    default = knobs["mesh"]["runs"][0]
    best = {}
    for k, _, _ in quantities_of(method):
        parts = [knobs[kn]["refs"].get(k, (None,))[0] for kn in ("mesh", "increments", "water")]
        d = default.get(k) if default["status"] == "ok" else None
        if d is None or any(p is None for p in parts):
            best[k] = None
            continue
        best[k] = parts[0] + (parts[1] - d) + (parts[2] - d)
    return best


ORDERED = ("mesh", "increments", "water", "tol")
# Richardson only with an apparent order of at least this: a lower one says the three levels
# are not yet in the asymptotic range, and the extrapolation (3 and more times the last
# difference) would be a guess; the finest level is the reference then.
MIN_ORDER = 0.7


def quantities_of(method):
    if method == "bonded":
        return [q for q in QUANTITIES if q[0] not in OPENINGS]
    return QUANTITIES


def references(method, knob, runs):
    """{quantity: (value, how)} for an ordered knob: Richardson of the three finest levels
    when they converge monotonically, else the finest level that ran."""
    ok = [r for r in runs if r["status"] == "ok"]
    refs = {}
    for key, _, _ in quantities_of(method):
        vals = [r.get(key) for r in ok]
        vals = [v for v in vals if v is not None]
        if not vals:
            continue
        rich = None
        # Richardson needs consecutive levels (ratio 2): mesh x2,x4,x8; increments 2,4,8;
        # water 10,5,2.5; not the tolerance (no step size).
        if knob in ("mesh", "increments", "water") and len(ok) == len(runs) and len(vals) >= 3 \
                and len(vals) == len(ok):
            rich = richardson(*vals[-3:])
        if rich is not None and rich[1] >= MIN_ORDER:
            refs[key] = (rich[0], f"Richardson (p = {rich[1]:.2f})")
        else:
            refs[key] = (vals[-1], f"finest ({ok[-1]['label']})")
    return refs


def errors_for(method, knob, runs):
    """Adds run['err'][key] (relative error against the knob's reference) to each run and
    returns the references {key: (value, how)}."""
    qs = quantities_of(method)
    if knob in ORDERED:
        refs = references(method, knob, runs)
        for r in runs:
            r["err"] = {k: rel_error(r.get(k), refs.get(k, (None,))[0]) for k, _, _ in qs}
            r["refval"] = {k: refs.get(k, (None,))[0] for k, _, _ in qs}
        return refs
    # paired knobs: (default choice, other choice) at each mesh; the reference is Newton
    # (solver), LOBATTO (rule), LINEAR (search)
    refs = {}
    ref_label = {"solver": "Newton", "rule": "LOBATTO", "search": "LINEAR"}[knob]
    for a, b in zip(runs[0::2], runs[1::2]):
        ref = b if knob == "solver" else a
        for r in (a, b):
            r["err"] = {k: (rel_error(r.get(k), ref.get(k)) if ref["status"] == "ok" and
                            r["status"] == "ok" else None) for k, _, _ in qs}
            r["refval"] = {k: ref.get(k) if ref["status"] == "ok" else None for k, _, _ in qs}
            r["ref_failed"] = ref["status"] != "ok"
    for k, _, _ in qs:
        refs[k] = (None, ref_label + " at the same mesh")
    return refs


def run_study(args):
    os.makedirs(args.workdir, exist_ok=True)
    study = {}
    t_start = time.perf_counter()
    methods = [m for m in args.methods.split(",") if m]
    plan = []
    for method in methods:
        for knob, label, s in knob_levels(method, args.max_refine):
            plan.append((method, knob, label, s))
    # cheap runs first (estimated cost: elements x 10 for Newton): x8 last
    plan.sort(key=lambda p: (p[3]["refine"] ** 2 * (10 if p[3]["solver"] == "newton" else 1)))
    done = {}
    for method, knob, label, s in plan:
        name = settings_name(method, s)
        if name not in done:
            deck = make_deck(args.workdir, method, s)
            rec = run_deck(args.cfrd, deck, args.force, args.repeat)
            rec["name"] = name
            done[name] = rec
            print(f"  {name}: {rec['status']} {rec['wall']:.2f} s (load {rec['load1']:.2f})"
                  f"{' cached' if rec['cached'] else ''} {rec.get('error', '')}",
                  file=sys.stderr, flush=True)
    for method in methods:
        study[method] = {}
        for knob, label, s in knob_levels(method, args.max_refine):
            rec = dict(done[settings_name(method, s)])
            rec["label"] = label
            rec["settings"] = s
            study[method].setdefault(knob, []).append(rec)
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
    total = sum(r["wall"] for r in done.values())
    return study, total, time.perf_counter() - t_start, len(done)


# ------------------------------------------------------------------------------------------
# Report
# ------------------------------------------------------------------------------------------

def fmt_val(v, unit):
    if v is None:
        return "-"
    if unit == "kPa":
        return f"{v:.0f}"
    return f"{v:.4f}"


def fmt_err(e):
    if e is None:
        return "-"
    if e == 0:
        return "0"
    return f"{100 * e:.2g} %" if e < 0.1 else f"{100 * e:.0f} %"


def method_table(method, knobs):
    qs = quantities_of(method)
    head = ["knob", "setting", "wall s", "load", "incr.", "fact.", "iter."] + \
        [f"{lab} ({unit})" for _, lab, unit in qs]
    lines = ["| " + " | ".join(head) + " |", "|:---|:---|" + "---:|" * (len(head) - 2)]
    for knob, data in knobs.items():
        for r in data["runs"]:
            it = r.get("iterations", 0)
            if method == "contact":
                it = f"{it}+{r.get('contact_iterations', 0)}c"
            if r["status"] != "ok":
                cells = [knob, r["label"], f"{r['wall']:.2f}", f"{r['load1']:.1f}", "-", "-",
                         "-", f"**failed**: {r.get('error', '')}"] + [""] * (len(qs) - 1)
            else:
                cells = [knob, r["label"], f"{r['wall']:.2f}", f"{r['load1']:.1f}",
                         str(r["increments"]), str(r["factorisations"]), str(it)]
                for k, _, unit in qs:
                    v = r.get(k)
                    e = r["err"].get(k)
                    cell = fmt_val(v, unit)
                    if k in OPENINGS and v == 0.0:
                        cell = "none"
                    if v is not None and e is not None:
                        cell += f" ({fmt_err(e)})"
                    elif r.get("ref_failed"):
                        cell += " (no ref.)"
                    elif v is not None and v != 0.0 and r["refval"].get(k) == 0.0:
                        cell += " (ref. 0)"
                    cells.append(cell)
            lines.append("| " + " | ".join(cells) + " |")
        if knob in ORDERED or knob == "combined":
            cells = [knob, "**reference**" if knob != "combined" else "**best estimate**",
                     "", "", "", "", ""]
            for k, _, unit in qs:
                v, how = data["refs"].get(k, (None, ""))
                cells.append(fmt_val(v, unit) + (" R" if how.startswith("Richardson") else ""))
            lines.append("| " + " | ".join(cells) + " |")
    return "\n".join(lines)


def solves(r):
    """Deterministic cost of a run: factorisations, Newton and contact iterations."""
    return r.get("factorisations", 0) + r.get("iterations", 0) + r.get("contact_iterations", 0)


def cheapest(method, knobs, tol):
    """Per quantity: for each ordered knob and the solver, the cheapest level whose own error
    is within tol. Mesh, increments and water step are listed coarsest (cheapest) first and
    the first level from which on every level is within tol is taken (wall times of sub-second runs are noise on a shared
    machine); the contact TOL, whose levels cost about the same, by the fewest solves."""
    out = {}
    for k, lab, _ in quantities_of(method):
        picks = {}
        for knob in ("mesh", "increments", "water", "solver", "tol"):
            if knob not in knobs:
                continue
            data = knobs[knob]
            runs = data["runs"] if knob != "solver" else data["runs"][0::2]
            ok = [r for r in runs if r["status"] == "ok"]
            within = [r["err"].get(k) is not None and r["err"][k] <= tol for r in ok]
            if knob in ("mesh", "increments", "water"):
                # the coarsest level from which on every finer level stays within tol (a
                # non-monotone sequence can pass through the reference by chance)
                stay = [all(within[i:]) for i in range(len(ok))]
                good = [r for r, g in zip(ok, stay) if g]
            else:
                good = [r for r, g in zip(ok, within) if g]
            how = data["refs"].get(k, (None, ""))[1]
            refv = data["refs"].get(k, (None,))[0]
            if knob == "tol" and good:
                good = [min(good, key=solves)]
            if good:
                best = good[0]
                last = knob != "solver" and best is ok[-1] and not how.startswith("Richardson")
                picks[knob] = best["label"] + (" only (the reference)" if last else "")
            elif knob == "solver":
                errs = [r["err"].get(k) for r in ok]
                newton = [r for r in data["runs"][1::2] if r["status"] == "ok"]
                picks[knob] = ("- (Newton failed)" if not newton
                               else "n/a (no opening)" if all(e is None for e in errs)
                               else "Newton")
            elif refv == 0.0:
                picks[knob] = "n/a (no opening)"
            else:
                picks[knob] = "not reached"
        out[k] = picks
    return out


FLOOR = 1e-5


def plot(study, prefix):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    paths = []
    colours = {"mesh": "C0", "increments": "C1", "water": "C2", "solver": "C3", "tol": "C4",
               "search": "C5", "rule": "C6", "combined": "C8"}
    for method, knobs in study.items():
        qs = quantities_of(method)
        ncol = 4
        nrow = math.ceil(len(qs) / ncol)
        fig, axes = plt.subplots(nrow, ncol, figsize=(4 * ncol, 3.3 * nrow), squeeze=False)
        for ax, (k, lab, unit) in zip(axes.ravel(), qs):
            floor = None
            for knob, data in knobs.items():
                pts = [(r["wall"], max(FLOOR, r["err"][k])) for r in data["runs"]
                       if r["status"] == "ok" and r["err"].get(k)]
                fails = [r["wall"] for r in data["runs"] if r["status"] != "ok"]
                if fails:
                    ax.plot(fails, [1.0] * len(fails), "x", color=colours[knob], ms=9,
                            label=f"{knob}: failed")
                if not pts:
                    continue
                t, e = zip(*pts)
                ax.loglog(t, e, "o-" if knob in ORDERED else "D" if knob == "combined" else "s",
                          color=colours[knob],
                          label=knob, ms=4)
                floor = min(e) if floor is None else min(floor, min(e))
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
        handles, labels = [], []
        for ax in axes.ravel():
            for h, l in zip(*ax.get_legend_handles_labels()):
                if l not in labels:
                    handles.append(h)
                    labels.append(l)
        fig.legend(handles, labels, loc="lower center", ncol=min(len(labels), 8), fontsize=8)
        fig.suptitle(f"Tianshengqiao-I, {method}: relative error against wall time, one knob "
                     f"at a time (dashed: 1 % and 5 %; x at 1: failed run; errors below "
                     f"{FLOOR:g} drawn at {FLOOR:g}; zero errors, the references, not drawn)",
                     fontsize=10)
        fig.tight_layout(rect=(0, 0.05, 1, 0.95))
        path = f"{prefix}-{method}.png"
        os.makedirs(os.path.dirname(path) or ".", exist_ok=True)
        fig.savefig(path, dpi=90)
        plt.close(fig)
        paths.append(path)
    return paths


def knees(study):
    """{method: {quantity: {knob: label of the knee}}}: each ordered knob's error against
    wall time, per quantity (the references, error 0, left out)."""
    out = {}
    for method, knobs in study.items():
        out[method] = {}
        for k, _, _ in quantities_of(method):
            out[method][k] = {}
            for knob in ("mesh", "increments", "water"):
                runs = [r for r in knobs[knob]["runs"] if r["status"] == "ok"
                        and r["err"].get(k)]
                i = knee([(r["wall"], r["err"][k]) for r in runs])
                out[method][k][knob] = runs[i]["label"] if i is not None else None
    return out


def report(study, total, n_runs, plots, args):
    from bench import machine
    md = [f"Machine: {machine()}. {n_runs} distinct runs, {total:.0f} s of cfrd wall time "
          f"in all (one process at a time; `load` is the 1-minute load average at the end of "
          f"each run: the machine is shared).", ""]
    for method, knobs in study.items():
        md += [f"#### {method}", "", method_table(method, knobs), ""]
    md += ["#### Cheapest settings per quantity", "",
           "Per knob, the cheapest level from which on its own error stays within 1 % / 5 % "
           "(mesh, increments, water step; the solver: midpoint where it is within the "
           "tolerance of Newton on the same mesh), the other knobs at the default.", ""]
    for tol in (0.01, 0.05):
        md += [f"**Within {100 * tol:.0f} %**", "",
               "| method | quantity | mesh | increments | water step | solver |"
               + (" contact TOL |" if "contact" in study else ""),
               "|:---|:---|:---|:---|:---|:---|" + (":---|" if "contact" in study else "")]
        for method, knobs in study.items():
            picks = cheapest(method, knobs, tol)
            for k, lab, _ in quantities_of(method):
                p = picks[k]
                cells = [method, lab] + [p.get(kn, "-") for kn in ("mesh", "increments",
                                                                   "water", "solver")]
                if "contact" in study:
                    cells.append(p.get("tol", "-"))
                md.append("| " + " | ".join(cells) + " |")
        md.append("")
    kn = knees(study)
    md += ["#### Knees", "",
           "Per quantity, the knee of each knob's error against wall time (log-log; the point "
           "farthest below the chord from the cheapest to the dearest point with a non-zero "
           "error; `-`: fewer than three such points, or none below the chord).", "",
           "| method | quantity | mesh | increments | water step |", "|:---|:---|:---|:---|:---|"]
    for method, d in kn.items():
        for k, lab, _ in quantities_of(method):
            md.append(f"| {method} | {lab} | " + " | ".join(
                d[k][kb] or "-" for kb in ("mesh", "increments", "water")) + " |")
    md.append("")
    where = os.path.dirname(os.path.abspath(args.doc or args.markdown))
    for p in plots:
        method = os.path.basename(p)[:-4].rsplit("-", 1)[-1]
        md += [f"![{method}: error against wall time]({os.path.relpath(p, where)})", ""]
    return "\n".join(md)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--cfrd", default=os.path.join(ROOT, "bin", "cfrd"))
    ap.add_argument("--workdir", default=os.path.join(ROOT, "build", "accuracy"))
    ap.add_argument("--max-refine", type=int, default=8, choices=[2, 4, 8],
                    help="finest mesh of the mesh axis (x8 is 4 of the grid's ~6 minutes)")
    ap.add_argument("--methods", default=",".join(METHODS))
    ap.add_argument("--markdown", default=os.path.join(ROOT, "build", "accuracy",
                                                       "accuracy-cost-tables.md"))
    ap.add_argument("--plot-prefix", default=os.path.join(ROOT, "build", "accuracy",
                                                          "accuracy-cost"))
    ap.add_argument("--json", help="also write every run's record here")
    ap.add_argument("--doc", help="replace the measured part of this markdown file (between "
                    "its BEGIN and END markers) with the tables, e.g. docs/accuracy-cost.md")
    ap.add_argument("--force", action="store_true", help="rerun cached runs")
    ap.add_argument("--repeat", type=int, default=3,
                    help=f"runs under {REPEAT_BELOW:g} s are made this many times, the fastest kept")
    ap.add_argument("--selftest", action="store_true")
    args = ap.parse_args(argv)
    if args.selftest:
        return 0 if selftest() else 1
    args.cfrd = os.path.abspath(args.cfrd)
    study, total, elapsed, n = run_study(args)
    plots = plot(study, args.plot_prefix)
    text = report(study, total, n, plots, args)
    os.makedirs(os.path.dirname(os.path.abspath(args.markdown)), exist_ok=True)
    with open(args.markdown, "w") as f:
        f.write(text)
    if args.doc:
        with open(args.doc) as f:
            doc = f.read()
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
