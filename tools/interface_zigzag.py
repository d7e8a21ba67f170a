#!/usr/bin/env python3
"""Zig-zag of the normal stress along the slab-cushion interface, from a cfrd interface CSV.

  python3 tools/interface_zigzag.py DECK-interface.csv [--stages 34,42,45]
  python3 tools/interface_zigzag.py --selftest

For each stage asked (default: the last) and each slab phase (interface group), the stations
in order along the line (both Gauss points of every joint, or the Newton-Cotes nodes once
each) and the zig-zag amplitude of sigma_n: the measure of the test
analysis_interface/stiff_joint_notch_oscillation (docs/theory.md section 12). From the second
divided differences D_i of successive stations (a zig-zag of amplitude a on spacing h has
|D| = 4a/h^2, alternating in sign): where two neighbouring D differ in sign, the smaller
|D| h^2/4 counts; the largest is printed in kPa and relative to the phase's mean |sigma_n|,
with the elevation of the station where it is. A smooth profile gives 0 whatever its slope or
station spacing. Each phase is measured on its own: the traction steps where one phase
meets the next (each counts its displacements from its own placement).
"""
import argparse
import csv
import sys

import numpy as np

from cfrdtools.checks import Checks


def zigzag(s, y):
    """Largest zig-zag amplitude of y at increasing stations s, and its index (or None)."""
    s, y = np.asarray(s, dtype=float), np.asarray(y, dtype=float)
    d, a = np.zeros(len(y)), np.zeros(len(y))
    ds, dy = np.diff(s), np.diff(y)
    d[1:-1] = 2.0 * (dy[1:] / ds[1:] - dy[:-1] / ds[:-1]) / (s[2:] - s[:-2])
    a[1:-1] = np.abs(d[1:-1]) * (0.5 * (s[2:] - s[:-2])) ** 2 / 4.0
    pair = np.where(d[1:-2] * d[2:-1] < 0.0, np.minimum(a[1:-2], a[2:-1]), 0.0)
    i = int(np.argmax(pair)) if pair.size else 0
    return (float(pair[i]), i + 1) if pair.size and pair[i] > 0.0 else (0.0, None)


def phases(rows):
    """{group: (s, sigma_n, elevation)} in order along the line, shared stations once."""
    groups = {}
    for r in rows:
        groups.setdefault(r["group"].strip(), []).append(
            (float(r["s_m"]), float(r["sigma_n_kPa"]), float(r["y_m"])))
    out = {}
    for g, v in groups.items():
        v.sort(key=lambda t: t[0])
        s = np.array([t[0] for t in v])
        keep = np.concatenate([[True], np.diff(s) > 1e-9 * max(1.0, s[-1])])
        out[g] = tuple(np.array([t[k] for t in v])[keep] for k in range(3))
    return out


def selftest():
    """The measure on closed forms: PASS/FAIL lines."""
    h = 1.5
    s = h * np.arange(12)
    g = 1.0 / np.sqrt(3.0)
    gauss = np.ravel([[k + 0.5 * (1 - g), k + 0.5 * (1 + g)] for k in range(10)]) * h
    check = Checks("interface-zigzag")
    for name, got, want in (
            ("sawtooth of amplitude 2.5 on a line, uniform spacing",
             zigzag(s, 3.0 + 0.7 * s + 2.5 * (-1.0) ** np.arange(12))[0], 2.5),
            ("straight line at the Gauss stations", zigzag(gauss, 4.0 - 3.0 * gauss)[0], 0.0),
            ("parabola at the Gauss stations", zigzag(gauss, 1.0 + gauss ** 2)[0], 0.0),
            ("decaying 1/sqrt(r) at the nodes", zigzag(s + 1.0, 1.0 / np.sqrt(s + 1.0))[0], 0.0)):
        check(name, abs(got - want) <= 1e-12 * max(1.0, abs(want)),
              f"{got:.3e} (closed form {want}, tol 1e-12)")
    return check.status


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("csv", nargs="?", help="DECK-interface.csv written by cfrd")
    parser.add_argument("--stages", help="comma-separated stage numbers (default: the last)")
    parser.add_argument("--selftest", action="store_true")
    args = parser.parse_args(argv)
    if args.selftest:
        return selftest()
    if not args.csv:
        parser.error("an interface CSV is needed (or --selftest)")
    with open(args.csv, newline="") as f:     # skip the '# cfrd run_id' comment line
        rows = list(csv.DictReader(line for line in f if not line.startswith("#")))
    by_stage = {}
    for r in rows:
        by_stage.setdefault(int(r["stage"]), []).append(r)
    stages = ([int(k) for k in args.stages.split(",")] if args.stages
              else [max(by_stage)])
    print(f"{'stage':>5} {'date':>8} {'phase':>6} {'stations':>8} {'mean|sn| kPa':>12} "
          f"{'zig-zag kPa':>11} {'% of mean':>9} {'at El. m':>8}")
    for k in stages:
        if k not in by_stage:
            print(f"stage {k}: no interface rows (not a stage with active interface elements)",
                  file=sys.stderr)
            return 1
        date = by_stage[k][0]["date"].strip()
        for g, (s, y, el) in sorted(phases(by_stage[k]).items()):
            amp, i = zigzag(s, y)
            mean = float(np.mean(np.abs(y)))
            where = f"{el[i]:8.1f}" if i is not None else f"{'-':>8}"
            print(f"{k:5d} {date:>8} {g:>6} {len(s):8d} {mean:12.0f} {amp:11.1f} "
                  f"{100 * amp / mean:9.1f} {where}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
