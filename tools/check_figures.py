#!/usr/bin/env python3
"""tools/figures.py plots what the results files hold: run with --data (the numbers read back
from the drawn curves, bars and contoured fields), they are compared here with the HDF5
datasets read with h5py, without the plotting code, to zero difference (the same float64
products, written with repr). The first file gives the single-file figures, every file its
curves in fig13 and fig14 and its row in table5. Along the interface the "stations" are the
active interface stations (/interface) or the placed contact slave nodes (/contact):

  fig07     the contoured settlement (ux) at the last stage is -100 uy (100 ux) of
            displacement_total at exactly the nodes of the active elements;
  fig09-10  each gauge's curve: year + (month - 1)/12 of each dated stage, -100 uy (V gauges)
            or 100 ux (the others) at the gauge node;
  fig11     a curve per stage before each RESET after the first, the last stage and the stage
            of each phase's largest opening width: (elevation, 100 du_n or 100 gap);
  fig12     per slab phase: (stage, 100 width) and (stage, depth) of opening_width and
            opening_depth, and against the stages' years (their `day`) when all are dated;
  fig13     per file, (sigma_n, elevation) before the 2nd and 3rd RESETs and at the first stage
            of the file's largest opening width, each in its panel; contact: the separated
            nodes drawn again, with sigma_n and tau exactly zero at every stage;
  fig14     per file, (sigma_t, elevation), (tau, elevation) at the active slab Gauss points
            before the 3rd RESET;
  fig15     (crack_ratio, section_y) of the slab sections placed (N or M not zero) at the end
            of construction (before the 3rd RESET) and at the last stage, first file;
  table5    the paper's rows as in inputs/tianshengqiao-observed.toml; each file's bars the
            largest opening width and depth of its first two phases over all stages.

    python3 tools/check_figures.py --run CFRD --workdir DIR   (what make test runs)
    python3 tools/check_figures.py RESULTS.h5 [MORE.h5 ...] --workdir DIR   (existing runs)

--run runs the Goodman-joint and the contact Tianshengqiao-I decks and checks the figures of
the joint run alone (`figures/...`) and of the contact run with the joint run
(`figures-contact/...`).
"""

import collections
import csv
import pathlib
import subprocess
import sys

import h5py
import numpy as np

from cfrdtools.checks import Checks, parser
from cfrdtools.results import field, text
from cfrdtools.runner import tool

try:
    import tomllib
except ModuleNotFoundError:  # Python < 3.11
    import tomli as tomllib

DECK = "inputs/tianshengqiao-x1-joint.dat"
CONTACT_DECK = "inputs/tianshengqiao-x1-contact.dat"
REFERENCE = pathlib.Path(__file__).resolve().parent.parent / "inputs/tianshengqiao-observed.toml"
PANELS = ("before phase II slab", "end of dam body construction", "at the largest opening")


def read_data(path):
    """{(kind, series): [row]} of one figure's CSV, x and y as read."""
    series = collections.defaultdict(list)
    with open(path) as f:
        for row in csv.DictReader(f):
            series[(row["kind"], row["series"])].append(row)
    return series


def xy(rows):
    return np.array([[float(r["x"]), float(r["y"])] for r in rows]).reshape(-1, 2)


def panels(rows):
    """The (x, y) points of the rows in each panel, panels in sorted order."""
    return [xy([r for r in rows if r["panel"] == p]) for p in sorted({r["panel"] for r in rows})]


def same_points(a, b):
    """Equal as sets of (x, y) points, bit for bit (order may differ among equal x)."""
    a, b = np.asarray(a, float).reshape(-1, 2), np.asarray(b, float).reshape(-1, 2)
    return a.shape == b.shape and np.array_equal(a[np.lexsort(a.T[::-1])],
                                                 b[np.lexsort(b.T[::-1])])


class Results:
    """What the checks need of one results file, read straight from its datasets."""

    def __init__(self, path):
        self.path = pathlib.Path(path)
        self.name = self.path.stem
        self.h5 = h5py.File(path, "r")
        self.stages = sorted(self.h5["stages"])
        self.resets = [i for i, s in enumerate(self.stages)
                       if text(self.h5["stages"][s].attrs["kind"]).strip() == "RESET"]
        self.contact = "contact" in self.h5["stages"][self.stages[-1]]
        self.groups = [text(g).strip() for g in self.h5["mesh/group_names"][...]] \
            if "mesh/group_names" in self.h5 else []

    def group(self, i):
        return self.h5["stages"][self.stages[i]]

    def stations(self, i):
        """(elevation, opening m, sigma_n, separated or None) along the interface at stage
        index i: active interface stations or placed contact slave nodes."""
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
        where, phases = "contact" if self.contact else "interface", collections.defaultdict(list)
        for number, s in enumerate(self.stages, start=1):
            r = self.h5["stages"][s].get(where)
            if r is not None and "opening_width" in r:
                for g, w, d in zip(r["opening_group"][...], r["opening_width"][...],
                                   r["opening_depth"][...]):
                    phases[self.groups[g - 1]].append((number, w, d))
        return phases

    def before_reset(self, k):
        """Index of the stage before the k-th RESET (1-based), or of the last stage."""
        return self.resets[k - 1] - 1 if len(self.resets) >= k else len(self.stages) - 1

    def largest_stage(self):
        """Index of the first stage with the largest opening width of any phase; None when
        nothing opens."""
        rows = [(w, n - 1) for rows in self.phases().values() for n, w, _ in rows]
        top = max((w for w, _ in rows), default=0.0)
        return None if top <= 0 else min(i for w, i in rows if w == top)


def check(h5paths, figdir, prefix="figures"):
    verdict = Checks(prefix)
    data = figdir / "data"
    files = [Results(p) for p in h5paths]
    first = files[0]
    h5, stages = first.h5, first.stages
    last = h5["stages"][stages[-1]]
    xyz = h5["mesh/coordinates"][...]
    where = "contact slave nodes" if first.contact else "active interface stations"

    def differ(bad):
        return f"; differ: {bad}" if bad else ""
    # Fig. 7: contoured fields at the last stage.
    used = np.unique(h5["mesh/connectivity"][...][last["active"][...] == 1]) - 1
    u = field(last, "displacement_total")
    for name, expected in (("fig07-settlement", -u[:, 1] * 100.0), ("fig07-ux", u[:, 0] * 100.0)):
        rows = [r for rows in read_data(data / f"{name}.csv").values() for r in rows
                if r["kind"] == "node"]
        nodes = np.array([int(r["index"]) - 1 for r in rows])
        values = np.array([float(r["value"]) for r in rows])
        verdict(name, np.array_equal(nodes, used) and np.array_equal(values, expected[used])
                and np.array_equal(xy(rows), xyz[used]), f"{len(rows)} nodal values drawn = "
                f"{'-100 uy' if 'settl' in name else '100 ux'} of displacement_total at the "
                f"{len(used)} nodes of the active elements (exact)")
    # Figs. 9-10: gauge histories.
    series = read_data(data / "fig09-10-gauges.csv")
    names = [text(n) for n in h5["gauges/names"][...]]
    nodes = h5["gauges/nodes"][...] - 1
    dated = [s for s in stages if text(h5["stages"][s].attrs.get("date", ""))]
    years = np.array([int(d[:4]) + (int(d[5:7]) - 1) / 12.0 for d in
                      (text(h5["stages"][s].attrs["date"]).replace("-", ".") for s in dated)])
    bad = []
    for name, node in zip(names, nodes):
        ut = np.array([field(h5["stages"][s], "displacement_total")[node] for s in dated])
        got = xy(series[("line", name)])
        if not (np.array_equal(got[:, 0], years) and np.array_equal(
                got[:, 1], -ut[:, 1] * 100 if "-V" in name else ut[:, 0] * 100)):
            bad.append(name)
    verdict("fig09-10-gauges", not bad and len(series) == len(names), f"{len(names)} gauges x "
            f"{len(dated)} dated stages: time and displacement (cm) at the gauge nodes (exact)"
            + differ(bad))
    # Fig. 11: opening along the interface.
    series = read_data(data / "fig11-opening.csv")
    phases = first.phases()
    largest = {rows[int(np.argmax([w for _, w, _ in rows]))][0] - 1 for rows in phases.values()
               if max(w for _, w, _ in rows) > 0}
    picks = sorted(set([i - 1 for i in first.resets[1:]] + [len(stages) - 1]) | largest)
    bad = []
    for i in picks:
        y, opening, _, _ = first.stations(i)
        key = [k for k in series if k[1].startswith(f"stage {i + 1} (")]
        if len(key) != 1 or not same_points(xy(series[key[0]]),
                                            np.column_stack([y, 100 * opening])):
            bad.append(i + 1)
    verdict("fig11-opening", not bad and len(series) == len(picks), f"stages "
            f"{[i + 1 for i in picks]} (before each RESET after the first, the last, each "
            f"phase's largest opening): (elevation, 100 {'gap' if first.contact else 'du_n'}) "
            f"of the {where} (exact)" + differ(bad))
    # Fig. 12: width and depth of each phase per stage, and against time (years from the
    # stage attribute `day`) when every stage has a date in a date form.
    days = [h5["stages"][k].attrs.get("day") for k in stages]
    timed = all(d is not None for d in days)
    for name, x_of, what in (("fig12-openings", lambda n: n, "stage"),
                             ("fig12-openings-time", lambda n: 1970.0 + np.array(
                                 days, dtype=float)[n - 1] / 365.2425, "year from the stage's "
                              "day") if timed else (None,) * 3):
        if name is None:
            continue
        series = read_data(data / f"{name}.csv")
        bad = []
        for phase, rows in phases.items():
            rows = np.array(rows)
            t, lines = x_of(rows[:, 0].astype(int)), panels(series[("line", phase)])
            if not all(any(np.array_equal(ln[:, 1], v) and np.array_equal(ln[:, 0], t)
                           for ln in lines) for v in (100 * rows[:, 1], rows[:, 2])):
                bad.append(phase)
        verdict(name, not bad and phases, f"phases {sorted(phases)}: ({what}, 100 opening_width)"
                f" and ({what.split(' ')[0]}, opening_depth) of /"
                f"{'contact' if first.contact else 'interface'} (exact)" + differ(bad))
    # Fig. 13: normal stress before the phase II slab, at the end of construction and at the
    # largest opening, per file in its panel; separated contact nodes drawn again.
    series = read_data(data / "fig13-normal-stress.csv")
    bad, told, expected_series = [], [], 0
    largest = [f.largest_stage() for f in files]
    for f, big in zip(files, largest):
        picks = [f.before_reset(2), f.before_reset(3)] + ([big] if any(
            b is not None for b in largest) else [])
        told.append(f"{f.name} {[None if i is None else i + 1 for i in picks]}")
        for panel, i in ((p, i) for p, i in zip(PANELS, picks) if i is not None):
            y, _, sigma_n, separated = f.stations(i)
            wanted = {f"{f.name} (stage {i + 1})": np.column_stack([sigma_n, y])}
            if separated is not None and separated.any():
                wanted[f"{f.name} separated (stage {i + 1})"] = \
                    np.column_stack([sigma_n[separated], y[separated]])
            for label, expected in wanted.items():
                expected_series += 1
                if not same_points(xy([r for r in series[("line", label)]
                                       if r["panel"] == panel]), expected):
                    bad.append(f"{label} in '{panel}'")
    drawn = sum(len({r["panel"] for r in rows}) for rows in series.values())
    verdict("fig13-normal-stress", not bad and drawn == expected_series, f"stages (before the "
            f"2nd and 3rd RESET, first of the largest opening) {told}: (sigma_n, elevation) of "
            f"the stations, separated contact nodes again, {expected_series} curves (exact)"
            + differ(bad))
    for f in (f for f in files if f.contact):
        count, nonzero = 0, []
        for i in range(len(f.stages)):
            r = f.group(i)["contact"]
            sep = (r["placed"][...] == 1) & (r["status"][...] == 0)
            count += int(sep.sum())
            if np.any(r["sigma_n"][...][sep] != 0) or np.any(r["tau"][...][sep] != 0):
                nonzero.append(i + 1)
        verdict(f"fig13-separated-zero-traction/{f.name}", not nonzero, f"{count} separated "
                f"slave node-stages (placed, status open) over the {len(f.stages)} stages: "
                f"sigma_n = tau = 0 exactly" + (f"; not at stages {nonzero}" if nonzero else ""))
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
        lines = panels(series[("line", f"{f.name} (stage {i + 1})")])
        bad += [f"{f.name} {key}" for key in ("sigma_t", "tau") if not any(same_points(
            ln, np.column_stack([r[key][...][keep].ravel(), r["y"][...][keep].ravel()]))
            for ln in lines)]
    verdict("fig14-slab", not bad and told, f"stages {told}: (sigma_t, elevation) and (tau, "
            f"elevation) at the active slab Gauss points (exact)" + differ(bad))
    # Fig. 15: the slab's crack-risk ratio along the slope, first file.
    series = read_data(data / "fig15-crack-risk.csv")
    picks = sorted({first.before_reset(3), len(stages) - 1})
    bad = []
    for i in picks:
        r = first.group(i)["slab"]
        placed = (r["axial"][...] != 0.0) | (r["moment"][...] != 0.0)
        rows = [rows for (kind, name), rows in series.items()
                if kind == "line" and f"(stage {i + 1}," in name]
        if len(rows) != 1 or not same_points(xy(rows[0]), np.column_stack(
                [r["crack_ratio"][...][placed], r["section_y"][...][placed]])):
            bad.append(i + 1)
    verdict("fig15-crack-risk", not bad, f"stages {[i + 1 for i in picks]}: (crack_ratio, "
            f"section_y) of the placed slab sections (exact)" + differ(bad))
    # Table 5: bars.
    series = read_data(data / "table5-openings.csv")
    expected, ours = {}, []
    for row in tomllib.loads(REFERENCE.read_text())["table5"]:
        expected[row["row"]] = ([row["phase_1"]["width"], row["phase_2"]["width"]],
                                [row["phase_1"]["depth"], row["phase_2"]["depth"]])
    for f in files:
        phases = f.phases()
        first_two = sorted(phases, key=f.groups.index)[:2]
        if first_two:
            w, d = expected[f"cfrd {f.name}"] = ([max(r[1] for r in phases[p]) for p in first_two],
                                                 [max(r[2] for r in phases[p]) for p in first_two])
            ours.append(f"{f.name} {w[0]:.4f} / {w[1]:.4f} m, {d[0]:.2f} / {d[1]:.2f} m")
    bad = []
    for label, (widths, depths) in expected.items():
        rows = series[("bar", label)]
        names = sorted({r["panel"] for r in rows})
        got = [[float(r["y"]) for r in rows if r["panel"] == p] for p in names]
        cats = [r["x"] for r in rows if r["panel"] == names[0]] if names else []
        if not (len(got) == 2 and got[0] == list(widths) and got[1] == list(depths)
                and cats == ["phase I", "phase II"]):
            bad.append(label)
    verdict("table5-openings", not bad and len(series) == len(expected), f"{len(expected)} rows:"
            f" the paper's from {REFERENCE.name}; the runs' largest width and depth of phases I "
            f"/ II over the stages: {'; '.join(ours)} (exact)" + differ(bad))
    pngs = sorted(p.name for p in figdir.glob("*.png"))
    wanted = 10 if timed else 9     # fig12-openings-time with dated stages
    verdict("files", len(pngs) == wanted, f"{len(pngs)} PNG files (expected {wanted}): "
            f"{', '.join(pngs)}")
    return not verdict.failed


def main(argv=None):
    ap = parser(__doc__, workdir="build/figures-check")
    ap.add_argument("results", nargs="*")
    ap.add_argument("--run", metavar="CFRD")
    args = ap.parse_args(argv)
    work = pathlib.Path(args.workdir)
    work.mkdir(parents=True, exist_ok=True)
    if args.run:
        for deck in (DECK, CONTACT_DECK):
            run = subprocess.run([args.run, "--quiet", "--out", str(work), deck],
                                 capture_output=True, text=True)
            if run.returncode != 0:
                return Checks("figures")("run", False, f"{args.run} {deck}: exit "
                                         f"{run.returncode}: {run.stderr[-300:]}") or 1
        runs = [work / (pathlib.Path(d).stem + ".h5") for d in (DECK, CONTACT_DECK)]
        jobs = [([runs[0]], "figures"), ([runs[1], runs[0]], "figures-contact")]
    elif args.results:
        jobs = [([pathlib.Path(p) for p in args.results], "figures")]
    else:
        ap.error("give RESULTS.h5 or --run CFRD")
    ok = True
    for paths, prefix in jobs:
        status, out = tool("figures.py", *paths, "--out", work / prefix, "--data")
        if status != 0:
            Checks(prefix)("run", False, f"figures.py exit {status}: {out[-500:]}")
            ok = False
        else:
            ok = check(paths, work / prefix, prefix) and ok
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
