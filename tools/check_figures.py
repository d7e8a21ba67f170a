#!/usr/bin/env python3
"""Check that tools/figures.py plots what the results files hold: run it with --data (the
numbers read back from the drawn curves, bars and contoured fields) and compare them with
the HDF5 datasets read here directly with h5py, without the plotting code. Values pass
through unchanged (the same float64 products, written with Python's repr), so the
tolerance is zero. The first file gives the single-file figures (fig07 to fig12), every
file its curves in fig13 and fig14 and its row in table5. Along the interface, "stations"
are the active interface stations (/interface, decks with INTERFACE) or the placed contact
slave nodes (/contact, decks with CONTACT):

  fig07     the contoured settlement (ux) at the last stage is -100 uy (100 ux) of
            displacement_total at exactly the nodes of the active elements;
  fig09-10  each gauge's curve: time = year + (month - 1)/12 of each dated stage, value =
            -100 uy (settlement, V gauges) or 100 ux (the others) at the gauge node;
  fig11     one curve per stage before each RESET after the first, the last stage and the
            stage of each phase's largest opening width: the stations' (elevation, 100 du_n)
            or (elevation, 100 gap);
  fig12     per slab phase (line or pair, group): (stage, 100 width) and (stage, depth) of
            opening_width and opening_depth;
  fig13     per file, (sigma_n, elevation) of the stations before the 2nd and 3rd RESETs
            and at the first stage of the file's largest opening width, each in its panel;
            contact: the separated nodes (status open) drawn again, and their sigma_n and
            tau exactly zero at every stage (what the hollow markers show);
  fig14     per file, (sigma_t, elevation), (tau, elevation) at the active slab Gauss
            points before the 3rd RESET;
  table5    the paper's rows as in inputs/tianshengqiao-observed.toml; each file's bars the
            largest opening width and depth of its first two phases over all stages.

    python3 tools/check_figures.py --run CFRD --workdir DIR   (what make test runs)
    python3 tools/check_figures.py RESULTS.h5 [MORE.h5 ...] --workdir DIR   (existing runs)

--run runs the Goodman-joint and the contact Tianshengqiao-I decks (every figure has data)
and checks the figures of the joint run alone (lines `figures/...`) and of the contact run
with the joint run (`figures-contact/...`: the contact figures, and the multi-file ones
with both methods). Prints one PASS/FAIL line per figure; exit status 1 if any failed.
"""

import argparse
import collections
import csv
import pathlib
import subprocess
import sys

import h5py
import numpy as np

try:
    import tomllib
except ModuleNotFoundError:  # Python < 3.11
    import tomli as tomllib

TOOLS = pathlib.Path(__file__).resolve().parent
DECK = "inputs/tianshengqiao-x1-joint.dat"
CONTACT_DECK = "inputs/tianshengqiao-x1-contact.dat"
REFERENCE = TOOLS.parent / "inputs" / "tianshengqiao-observed.toml"
PANELS = ("before phase II slab", "end of dam body construction", "at the largest opening")


def text(v):
    return v.decode().strip() if isinstance(v, bytes) else str(v).strip()


def read_data(path):
    """{(kind, series): [row]} of one figure's CSV, x and y as read."""
    series = collections.defaultdict(list)
    with open(path) as f:
        for row in csv.DictReader(f):
            series[(row["kind"], row["series"])].append(row)
    return series


def xy(rows):
    return np.array([[float(r["x"]), float(r["y"])] for r in rows]).reshape(-1, 2)


def same_points(a, b):
    """Equal as sets of (x, y) points, bit for bit (order may differ among equal x)."""
    a, b = np.asarray(a, float).reshape(-1, 2), np.asarray(b, float).reshape(-1, 2)
    if a.shape != b.shape:
        return False
    return np.array_equal(a[np.lexsort(a.T[::-1])], b[np.lexsort(b.T[::-1])])


class Results:
    """What the checks need of one results file, read straight from its datasets."""

    def __init__(self, path):
        self.path = pathlib.Path(path)
        self.name = self.path.stem
        self.h5 = h5py.File(path, "r")
        self.stages = sorted(self.h5["stages"])
        self.kinds = [text(self.h5["stages"][s].attrs["kind"]) for s in self.stages]
        self.resets = [i for i, k in enumerate(self.kinds) if k == "RESET"]
        self.contact = "contact" in self.h5["stages"][self.stages[-1]]
        self.groups = [text(g) for g in self.h5["mesh/group_names"][...]] \
            if "mesh/group_names" in self.h5 else []

    def group(self, i):
        return self.h5["stages"][self.stages[i]]

    def stations(self, i):
        """(elevation, opening m, sigma_n, separated or None) along the interface at
        stage index i: active interface stations or placed contact slave nodes."""
        if self.contact:
            r = self.group(i)["contact"]
            keep = r["placed"][...] == 1
            return (r["y"][...][keep], r["gap"][...][keep], r["sigma_n"][...][keep],
                    r["status"][...][keep] == 0)
        r = self.group(i)["interface"]
        act = r["active"][...] == 1
        return (r["y"][...][act].ravel(), r["du_n"][...][act].ravel(),
                r["sigma_n"][...][act].ravel(), None)

    def phases(self):
        """{group name: [(stage number, width, depth)]} from opening_* of every stage."""
        where = "contact" if self.contact else "interface"
        phases = collections.defaultdict(list)
        for number, s in enumerate(self.stages, start=1):
            g = self.h5["stages"][s]
            if where not in g or "opening_width" not in g[where]:
                continue
            r = g[where]
            for g, w, d in zip(r["opening_group"][...], r["opening_width"][...],
                               r["opening_depth"][...]):
                phases[self.groups[g - 1]].append((number, w, d))
        return phases

    def before_reset(self, k):
        """Index of the stage before the k-th RESET (1-based), or of the last stage."""
        return self.resets[k - 1] - 1 if len(self.resets) >= k else len(self.stages) - 1

    def largest_stage(self):
        """Index of the first stage with the largest opening width of any phase; None
        when nothing opens."""
        rows = [(w, n - 1) for rows in self.phases().values() for n, w, _ in rows]
        top = max((w for w, _ in rows), default=0.0)
        return None if top <= 0 else min(i for w, i in rows if w == top)


def check(h5paths, figdir, prefix="figures"):
    results = []

    def verdict(name, ok, detail):
        results.append(bool(ok))
        print(f"{'PASS' if ok else 'FAIL'} {prefix}/{name}: {detail}")

    data = figdir / "data"
    files = [Results(p) for p in h5paths]
    first = files[0]
    h5, stages = first.h5, first.stages
    last = h5["stages"][stages[-1]]
    xyz = h5["mesh/coordinates"][...]
    where = "contact slave nodes" if first.contact else "active interface stations"

    # Fig. 7: contoured fields at the last stage.
    used = np.unique(h5["mesh/connectivity"][...][last["active"][...] == 1]) - 1
    u = last["displacement_total"][...]
    for name, expected in (("fig07-settlement", -u[:, 1] * 100.0), ("fig07-ux", u[:, 0] * 100.0)):
        rows = [r for rows in read_data(data / f"{name}.csv").values() for r in rows
                if r["kind"] == "node"]
        nodes = np.array([int(r["index"]) - 1 for r in rows])
        values = np.array([float(r["value"]) for r in rows])
        ok = (np.array_equal(nodes, used) and np.array_equal(values, expected[used])
              and np.array_equal(xy(rows), xyz[used]))
        what = "-100 uy" if "settl" in name else "100 ux"
        verdict(name, ok, f"{len(rows)} nodal values drawn = {what} of displacement_total at "
                f"the {len(used)} nodes of the active elements (exact)")

    # Figs. 9-10: gauge histories.
    series = read_data(data / "fig09-10-gauges.csv")
    names = [text(n) for n in h5["gauges/names"][...]]
    nodes = h5["gauges/nodes"][...] - 1
    dated = [s for s in stages if text(h5["stages"][s].attrs.get("date", ""))]
    years = np.array([int(d[:4]) + (int(d[5:7]) - 1) / 12.0 for d in
                      (text(h5["stages"][s].attrs["date"]).replace("-", ".") for s in dated)])
    bad = []
    for name, node in zip(names, nodes):
        ut = np.array([h5["stages"][s]["displacement_total"][node] for s in dated])
        expected = -ut[:, 1] * 100 if "-V" in name else ut[:, 0] * 100
        got = xy(series[("line", name)])
        if not (np.array_equal(got[:, 0], years) and np.array_equal(got[:, 1], expected)):
            bad.append(name)
    verdict("fig09-10-gauges", not bad and len(series) == len(names),
            f"{len(names)} gauges x {len(dated)} dated stages: time and displacement (cm) "
            f"at the gauge nodes (exact)" + (f"; differ: {bad}" if bad else ""))

    # Fig. 11: opening along the interface.
    series = read_data(data / "fig11-opening.csv")
    phases = first.phases()
    largest = set()
    for rows in phases.values():
        widths = [w for _, w, _ in rows]
        k = int(np.argmax(widths))
        if widths[k] > 0:
            largest.add(rows[k][0] - 1)
    picks = sorted(set([i - 1 for i in first.resets[1:]] + [len(stages) - 1]) | largest)
    bad = []
    for i in picks:
        y, opening, _, _ = first.stations(i)
        expected = np.column_stack([y, 100 * opening])
        key = [k for k in series if k[1].startswith(f"stage {i + 1} (")]
        if len(key) != 1 or not same_points(xy(series[key[0]]), expected):
            bad.append(i + 1)
    what = "gap" if first.contact else "du_n"
    verdict("fig11-opening", not bad and len(series) == len(picks),
            f"stages {[i + 1 for i in picks]} (before each RESET after the first, the last, "
            f"each phase's largest opening): (elevation, 100 {what}) of the {where} (exact)"
            + (f"; differ: {bad}" if bad else ""))

    # Fig. 12: width and depth of each phase per stage.
    series = read_data(data / "fig12-openings.csv")
    bad = []
    for phase, rows in phases.items():
        rows = np.array(rows)
        lines = [xy([r for r in series[("line", phase)] if r["panel"] == p])
                 for p in sorted({r["panel"] for r in series[("line", phase)]})]
        got = {"width": None, "depth": None}
        for line in lines:
            if np.array_equal(line[:, 1], 100 * rows[:, 1]):
                got["width"] = line
            if np.array_equal(line[:, 1], rows[:, 2]):
                got["depth"] = line
        if any(v is None or not np.array_equal(v[:, 0], rows[:, 0]) for v in got.values()):
            bad.append(phase)
    verdict("fig12-openings", not bad and phases,
            f"phases {sorted(phases)}: (stage, 100 opening_width) and (stage, opening_depth) "
            f"of /{'contact' if first.contact else 'interface'} (exact)"
            + (f"; differ: {bad}" if bad else ""))

    # Fig. 12 against time: the same widths and depths at the stages' times (years from the
    # HDF5 stage attribute `day`), drawn when every stage has a date in a date form.
    days = [first.h5["stages"][k].attrs.get("day") for k in sorted(first.h5["stages"])]
    timed = all(d is not None for d in days)
    if timed:
        years = 1970.0 + np.array(days, dtype=float) / 365.2425
        series = read_data(data / "fig12-openings-time.csv")
        bad = []
        for phase, rows in phases.items():
            rows = np.array(rows)
            t = years[rows[:, 0].astype(int) - 1]
            lines = [xy([r for r in series[("line", phase)] if r["panel"] == p])
                     for p in sorted({r["panel"] for r in series[("line", phase)]})]
            ok_w = any(np.array_equal(l[:, 1], 100 * rows[:, 1]) and np.array_equal(l[:, 0], t)
                       for l in lines)
            ok_d = any(np.array_equal(l[:, 1], rows[:, 2]) and np.array_equal(l[:, 0], t)
                       for l in lines)
            if not (ok_w and ok_d):
                bad.append(phase)
        verdict("fig12-openings-time", not bad and phases,
                f"phases {sorted(phases)}: (year from the stage's day, 100 opening_width) and"
                f" (year, opening_depth) (exact)" + (f"; differ: {bad}" if bad else ""))

    # Fig. 13: normal stress before the phase II slab, at the end of construction and at
    # the largest opening, per file in its panel; separated contact nodes drawn again.
    series = read_data(data / "fig13-normal-stress.csv")
    bad, told, expected_series = [], [], 0
    largest = [f.largest_stage() for f in files]
    for f, big in zip(files, largest):
        picks = [f.before_reset(2), f.before_reset(3)]
        if any(b is not None for b in largest):
            picks.append(big)
        told.append(f"{f.name} {[None if i is None else i + 1 for i in picks]}")
        for panel, i in zip(PANELS, picks):
            if i is None:
                continue
            y, _, sigma_n, separated = f.stations(i)
            wanted = {f"{f.name} (stage {i + 1})": np.column_stack([sigma_n, y])}
            if separated is not None and separated.any():
                wanted[f"{f.name} separated (stage {i + 1})"] = \
                    np.column_stack([sigma_n[separated], y[separated]])
            for label, expected in wanted.items():
                expected_series += 1
                rows = [r for r in series[("line", label)] if r["panel"] == panel]
                if not same_points(xy(rows), expected):
                    bad.append(f"{label} in '{panel}'")
    drawn = sum(len({r["panel"] for r in rows}) for rows in series.values())
    verdict("fig13-normal-stress", not bad and drawn == expected_series,
            f"stages (before the 2nd and 3rd RESET, first of the largest opening) {told}: "
            f"(sigma_n, elevation) of the stations, separated contact nodes again, "
            f"{expected_series} curves (exact)" + (f"; differ: {bad}" if bad else ""))
    for f in files:
        if not f.contact:
            continue
        count, nonzero = 0, []
        for i in range(len(f.stages)):
            r = f.group(i)["contact"]
            sep = (r["placed"][...] == 1) & (r["status"][...] == 0)
            count += int(sep.sum())
            if np.any(r["sigma_n"][...][sep] != 0) or np.any(r["tau"][...][sep] != 0):
                nonzero.append(i + 1)
        verdict(f"fig13-separated-zero-traction/{f.name}", not nonzero,
                f"{count} separated slave node-stages (placed, status open) over the "
                f"{len(f.stages)} stages: sigma_n = tau = 0 exactly"
                + (f"; not at stages {nonzero}" if nonzero else ""))

    # Fig. 14: slab stresses at the end of construction, per file.
    series = read_data(data / "fig14-slab.csv")
    bad, told = [], []
    for f in files:
        i = f.before_reset(3)
        g = f.group(i)
        if "slab" not in g:
            continue
        told.append(f"{f.name} {i + 1}")
        r = g["slab"]
        keep = (g["active"][...] == 1)[r["element"][...] - 1]
        rows = series[("line", f"{f.name} (stage {i + 1})")]
        panels = sorted({row["panel"] for row in rows})
        for key in ("sigma_t", "tau"):
            expected = np.column_stack([r[key][...][keep].ravel(), r["y"][...][keep].ravel()])
            if not any(same_points(xy([row for row in rows if row["panel"] == p]), expected)
                       for p in panels):
                bad.append(f"{f.name} {key}")
    verdict("fig14-slab", not bad and told,
            f"stages {told}: (sigma_t, elevation) and (tau, elevation) at the active slab "
            f"Gauss points (exact)" + (f"; differ: {bad}" if bad else ""))

    # Table 5: bars.
    series = read_data(data / "table5-openings.csv")
    reference = tomllib.loads(REFERENCE.read_text())
    expected, ours = {}, []
    for row in reference["table5"]:
        expected[row["row"]] = ([row["phase_1"]["width"], row["phase_2"]["width"]],
                                [row["phase_1"]["depth"], row["phase_2"]["depth"]])
    for f in files:
        phases = f.phases()
        first_two = sorted(phases, key=f.groups.index)[:2]
        if not first_two:
            continue
        expected[f"cfrd {f.name}"] = ([max(r[1] for r in phases[p]) for p in first_two],
                                      [max(r[2] for r in phases[p]) for p in first_two])
        w, d = expected[f"cfrd {f.name}"]
        ours.append(f"{f.name} {w[0]:.4f} / {w[1]:.4f} m, {d[0]:.2f} / {d[1]:.2f} m")
    bad = []
    for label, (widths, depths) in expected.items():
        rows = series[("bar", label)]
        panels = sorted({r["panel"] for r in rows})
        got = [[float(r["y"]) for r in rows if r["panel"] == p] for p in panels]
        cats = [r["x"] for r in rows if r["panel"] == panels[0]] if panels else []
        if not (len(got) == 2 and got[0] == list(widths) and got[1] == list(depths)
                and cats == ["phase I", "phase II"]):
            bad.append(label)
    verdict("table5-openings", not bad and len(series) == len(expected),
            f"{len(expected)} rows: the paper's from {REFERENCE.name}; the runs' largest "
            f"width and depth of phases I / II over the stages: {'; '.join(ours)} (exact)"
            + (f"; differ: {bad}" if bad else ""))
    pngs = sorted(p.name for p in figdir.glob("*.png"))
    wanted = 9 if timed else 8      # fig12-openings-time with dated stages
    verdict("files", len(pngs) == wanted, f"{len(pngs)} PNG files (expected {wanted}): "
            f"{', '.join(pngs)}")
    return all(results)


def draw(h5paths, figdir):
    """figures.py --data on the files; None, or the FAIL line's detail."""
    run = subprocess.run([sys.executable, str(TOOLS / "figures.py"), *map(str, h5paths),
                          "--out", str(figdir), "--data"], capture_output=True, text=True)
    if run.returncode != 0:
        return f"figures.py exit {run.returncode}: {run.stderr[-500:]}"
    return None


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("results", nargs="*")
    parser.add_argument("--run", metavar="CFRD")
    parser.add_argument("--workdir", default="build/figures-check")
    args = parser.parse_args(argv)
    work = pathlib.Path(args.workdir)
    work.mkdir(parents=True, exist_ok=True)
    if args.run:
        runs = []
        for deck in (DECK, CONTACT_DECK):
            run = subprocess.run([args.run, "--quiet", "--out", str(work), deck],
                                 capture_output=True, text=True)
            if run.returncode != 0:
                print(f"FAIL figures/run: {args.run} {deck}: exit {run.returncode}: "
                      f"{run.stderr[-300:]}")
                return 1
            runs.append(work / (pathlib.Path(deck).stem + ".h5"))
        jobs = [([runs[0]], work / "figures", "figures"),
                ([runs[1], runs[0]], work / "figures-contact", "figures-contact")]
    elif args.results:
        jobs = [([pathlib.Path(p) for p in args.results], work / "figures", "figures")]
    else:
        parser.error("give RESULTS.h5 or --run CFRD")
    ok = True
    for paths, figdir, prefix in jobs:
        failure = draw(paths, figdir)
        if failure:
            print(f"FAIL {prefix}/run: {failure}")
            ok = False
            continue
        ok = check(paths, figdir, prefix) and ok
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
