#!/usr/bin/env python3
"""Zig-zag of the normal stress along the slab-cushion interface, from a cfrd interface CSV.

  python3 tools/interface_zigzag.py DECK-interface.csv [--stages 34,42,45]
  python3 tools/interface_zigzag.py --slab DECK.h5 [--stages 42,45]
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

--slab: the zig-zag of the slab's shear stress tau from Gauss point to Gauss point within
each element (the HDF5 file's /stages/*/slab/tau): the largest spread max - min of an
element's four values, in kPa and relative to the mean |tau| of the placed slab elements,
the toe element (the lowest, whose lower end lies on the base) left out. A Q4S element has
one shear strain, that of its centre, in its natural frame: on a rectangle tau is the same
at its four points (spread 0); on the skewed parallelograms of a slab cut along the body's
row lines the bending strain leaks into tau and alternates across the thickness (docs/theory.md
section 3).
"""
import h5py
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


def element_spread(tau):
    """Largest spread (max - min over an element's Gauss points) of tau (4, n), and its
    element index."""
    spread = np.ptp(np.asarray(tau, dtype=float), axis=0)
    i = int(np.argmax(spread))
    return float(spread[i]), i


def skew(xy, conn):
    """Largest deviation of each quad's corner angles from 90 deg (deg); xy (nnode, 2),
    conn (nelem, 4) 0-based."""
    p = xy[conn]                                   # (nelem, 4, 2)
    a = np.roll(p, -1, axis=1) - p
    b = np.roll(p, 1, axis=1) - p
    with np.errstate(invalid="ignore", divide="ignore"):      # triangles: a zero edge
        cos = np.sum(a * b, axis=2) / (np.linalg.norm(a, axis=2) * np.linalg.norm(b, axis=2))
    cos = np.nan_to_num(cos)
    return np.max(np.abs(np.degrees(np.arccos(np.clip(cos, -1.0, 1.0))) - 90.0), axis=1)


def slab_shear(path, stages):
    """Print the within-element spread of the slab's tau at the given stages (1-based; None:
    the last), over the slab's rectangles and over its skewed elements (a corner more than
    1 deg off 90); returns 0, or 1 without slab results."""
    with h5py.File(path, "r") as h5:
        names = sorted(h5["stages"])
        angle = skew(h5["mesh/coordinates"][...][:, :2], h5["mesh/connectivity"][...] - 1)
        print(f"{'stage':>5} {'elements':>17} {'mean|tau| kPa':>13} {'spread kPa':>10} "
              f"{'% of mean':>9} {'at El. m':>8}")
        for k in stages or [len(names)]:
            g = h5["stages"][names[k - 1]]
            if "slab" not in g or "tau" not in g["slab"]:
                print(f"stage {k}: no slab results", file=sys.stderr)
                return 1
            r = g["slab"]
            element = r["element"][...] - 1
            keep = g["active"][...].astype(bool)[element]
            # (nslab, 4) in the file: Fortran's (4, nslab)
            tau, y = r["tau"][...][keep].T, r["y"][...][keep].T
            skewed = angle[element[keep]] > 1.0
            mean = float(np.mean(np.abs(tau)))
            for what, sel in (("rectangles", ~skewed), ("skewed", skewed)):
                if not sel.any():
                    continue
                amp, i = element_spread(tau[:, sel])
                print(f"{k:5d} {sel.sum():6d} {what:>10} {mean:13.0f} {amp:10.1f} "
                      f"{100 * amp / mean:9.1f} {y[:, sel][:, i].mean():8.1f}")
    return 0


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
            ("decaying 1/sqrt(r) at the nodes", zigzag(s + 1.0, 1.0 / np.sqrt(s + 1.0))[0], 0.0),
            ("element spread: constant tau per element", element_spread(
                np.tile([3.0, -2.0, 7.0], (4, 1)))[0], 0.0),
            ("element spread: +-150 across an element", element_spread(
                np.array([[10.0, 150.0], [10.0, -150.0], [10.0, -150.0], [10.0, 150.0]]))[0],
             300.0)):
        check(name, abs(got - want) <= 1e-12 * max(1.0, abs(want)),
              f"{got:.3e} (closed form {want}, tol 1e-12)")
    return check.status


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("csv", nargs="?", help="DECK-interface.csv written by cfrd")
    parser.add_argument("--stages", help="comma-separated stage numbers (default: the last)")
    parser.add_argument("--selftest", action="store_true")
    parser.add_argument("--slab", help="a cfrd HDF5 results file: the slab's shear zig-zag")
    args = parser.parse_args(argv)
    if args.selftest:
        return selftest()
    if args.slab:
        return slab_shear(args.slab, [int(k) for k in args.stages.split(",")]
                          if args.stages else None)
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
