#!/usr/bin/env python3
"""Check that tools/figures.py plots what the results file holds: run it with --data (the
numbers read back from the drawn curves, bars and contoured fields) and compare them with
the HDF5 datasets read here directly with h5py, without the plotting code. Values pass
through unchanged (the same float64 products, written with Python's repr), so the
tolerance is zero.

  fig07     the contoured settlement (ux) at the last stage is -100 uy (100 ux) of
            displacement_total at exactly the nodes of the active elements;
  fig09-10  each gauge's curve: time = year + (month - 1)/12 of each dated stage, value =
            -100 uy (settlement, V gauges) or 100 ux (the others) at the gauge node;
  fig11     one curve per stage before each RESET after the first and the last stage:
            the active stations' (elevation, 100 du_n);
  fig12     per slab phase (line, group): (stage, 100 width) and (stage, depth);
  fig13     (sigma_n, elevation) of the active stations before the 2nd and 3rd RESETs;
  fig14     (sigma_t, elevation), (tau, elevation) at the active slab Gauss points;
  table5    the paper's rows as in inputs/tianshengqiao-observed.toml; this run's bars the
            largest opening width and depth of the first two phases over all stages.

    python3 tools/check_figures.py --run CFRD --workdir DIR   (what make test runs)
    python3 tools/check_figures.py RESULTS.h5 --workdir DIR   (an existing run)

--run runs the Goodman-joint Tianshengqiao-I deck (every figure has data). Prints one
PASS/FAIL line per figure; exit status 1 if any failed.
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
REFERENCE = TOOLS.parent / "inputs" / "tianshengqiao-observed.toml"


def text(v):
    return v.decode().strip() if isinstance(v, bytes) else str(v).strip()


def read_data(path):
    """{series: [(panel, x, y, value)]} of one figure's CSV, x and y as read."""
    series = collections.defaultdict(list)
    with open(path) as f:
        for row in csv.DictReader(f):
            series[(row["kind"], row["series"])].append(row)
    return series


def xy(rows):
    return np.array([[float(r["x"]), float(r["y"])] for r in rows])


def same_points(a, b):
    """Equal as sets of (x, y) points, bit for bit (order may differ among equal x)."""
    a, b = np.asarray(a, float), np.asarray(b, float)
    if a.shape != b.shape:
        return False
    return np.array_equal(a[np.lexsort(a.T[::-1])], b[np.lexsort(b.T[::-1])])


def check(h5path, figdir):
    results = []

    def verdict(name, ok, detail):
        results.append(ok)
        print(f"{'PASS' if ok else 'FAIL'} figures/{name}: {detail}")

    data = figdir / "data"
    h5 = h5py.File(h5path, "r")
    stages = sorted(h5["stages"])
    last = h5["stages"][stages[-1]]
    xyz = h5["mesh/coordinates"][...]
    kinds = [text(h5["stages"][s].attrs["kind"]) for s in stages]
    resets = [i for i, k in enumerate(kinds) if k == "RESET"]

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
    picks = sorted(set([i - 1 for i in resets[1:]] + [len(stages) - 1]))
    bad = []
    for i in picks:
        r = h5["stages"][stages[i]]["interface"]
        act = r["active"][...] == 1
        expected = np.column_stack([r["y"][...][act].ravel(), 100 * r["du_n"][...][act].ravel()])
        key = [k for k in series if k[1].startswith(f"stage {i + 1} (")]
        if len(key) != 1 or not same_points(xy(series[key[0]]), expected):
            bad.append(i + 1)
    verdict("fig11-opening", not bad and len(series) == len(picks),
            f"stages {[i + 1 for i in picks]} (before each RESET after the first, and the "
            f"last): (elevation, 100 du_n) of the active stations (exact)"
            + (f"; differ: {bad}" if bad else ""))

    # Fig. 12: width and depth of each phase per stage.
    series = read_data(data / "fig12-openings.csv")
    groups = [text(g) for g in h5["mesh/group_names"][...]]
    phases = collections.defaultdict(list)
    for number, s in enumerate(stages, start=1):
        r = h5["stages"][s]["interface"]
        if "opening_width" not in r:
            continue
        for g, w, d in zip(r["opening_group"][...], r["opening_width"][...],
                           r["opening_depth"][...]):
            phases[groups[g - 1]].append((number, w, d))
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
            f"(exact)" + (f"; differ: {bad}" if bad else ""))

    # Fig. 13: normal stress before the phase II slab and at the end of construction.
    series = read_data(data / "fig13-normal-stress.csv")
    picks = [resets[1] - 1, resets[2] - 1]
    bad = []
    for i in picks:
        r = h5["stages"][stages[i]]["interface"]
        act = r["active"][...] == 1
        expected = np.column_stack([r["sigma_n"][...][act].ravel(), r["y"][...][act].ravel()])
        key = [k for k in series if k[1].endswith(f"(stage {i + 1})")]
        if len(key) != 1 or not same_points(xy(series[key[0]]), expected):
            bad.append(i + 1)
    verdict("fig13-normal-stress", not bad,
            f"stages {[i + 1 for i in picks]} (before the 2nd and 3rd RESET): (sigma_n, "
            f"elevation) of the active stations (exact)" + (f"; differ: {bad}" if bad else ""))

    # Fig. 14: slab stresses at the end of construction.
    series = read_data(data / "fig14-slab.csv")
    i = resets[2] - 1
    g = h5["stages"][stages[i]]
    r = g["slab"]
    keep = (g["active"][...] == 1)[r["element"][...] - 1]
    bad = []
    for key, panel_word in (("sigma_t", "normal stress"), ("tau", "shear")):
        expected = np.column_stack([r[key][...][keep].ravel(), r["y"][...][keep].ravel()])
        rows = [row for k, rows in series.items() if k[1].endswith(f"(stage {i + 1})")
                for row in rows]
        panels = sorted({row["panel"] for row in rows})
        if not any(same_points(xy([row for row in rows if row["panel"] == p]), expected)
                   for p in panels):
            bad.append(key)
    verdict("fig14-slab", not bad,
            f"stage {i + 1}: (sigma_t, elevation) and (tau, elevation) at the active slab "
            f"Gauss points (exact)" + (f"; differ: {bad}" if bad else ""))

    # Table 5: bars.
    series = read_data(data / "table5-openings.csv")
    reference = tomllib.loads(REFERENCE.read_text())
    name = pathlib.Path(h5path).stem
    first_two = [p for p in sorted(phases, key=lambda p: groups.index(p))][:2]
    expected = {f"cfrd {name}": ([max(r[1] for r in phases[p]) for p in first_two],
                                 [max(r[2] for r in phases[p]) for p in first_two])}
    for row in reference["table5"]:
        expected[row["row"]] = ([row["phase_1"]["width"], row["phase_2"]["width"]],
                                [row["phase_1"]["depth"], row["phase_2"]["depth"]])
    bad = []
    for label, (widths, depths) in expected.items():
        rows = series[("bar", label)]
        panels = sorted({r["panel"] for r in rows})
        got = [[float(r["y"]) for r in rows if r["panel"] == p] for p in panels]
        cats = [r["x"] for r in rows if r["panel"] == panels[0]] if panels else []
        if not (len(got) == 2 and got[0] == list(widths) and got[1] == list(depths)
                and cats == ["phase I", "phase II"]):
            bad.append(label)
    ours = expected[f"cfrd {name}"]
    verdict("table5-openings", not bad and len(series) == len(expected),
            f"{len(expected)} rows: the paper's from {REFERENCE.name}, this run's largest "
            f"width {ours[0][0]:.4f} / {ours[0][1]:.4f} m and depth {ours[1][0]:.2f} / "
            f"{ours[1][1]:.2f} m of {first_two} over the stages (exact)"
            + (f"; differ: {bad}" if bad else ""))
    pngs = sorted(p.name for p in figdir.glob("*.png"))
    verdict("files", len(pngs) == 8, f"{len(pngs)} PNG files: {', '.join(pngs)}")
    return all(results)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("results", nargs="?")
    parser.add_argument("--run", metavar="CFRD")
    parser.add_argument("--workdir", default="build/figures-check")
    args = parser.parse_args(argv)
    work = pathlib.Path(args.workdir)
    work.mkdir(parents=True, exist_ok=True)
    if args.run:
        run = subprocess.run([args.run, "--quiet", "--out", str(work), DECK],
                             capture_output=True, text=True)
        if run.returncode != 0:
            print(f"FAIL figures/run: {args.run} {DECK}: exit {run.returncode}: "
                  f"{run.stderr[-300:]}")
            return 1
        h5path = work / (pathlib.Path(DECK).stem + ".h5")
    elif args.results:
        h5path = pathlib.Path(args.results)
    else:
        parser.error("give RESULTS.h5 or --run CFRD")
    figdir = work / "figures"
    run = subprocess.run([sys.executable, str(TOOLS / "figures.py"), str(h5path), "--out",
                          str(figdir), "--data"], capture_output=True, text=True)
    if run.returncode != 0:
        print(f"FAIL figures/run: figures.py exit {run.returncode}: {run.stderr[-500:]}")
        return 1
    return 0 if check(h5path, figdir) else 1


if __name__ == "__main__":
    sys.exit(main())
