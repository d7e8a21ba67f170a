#!/usr/bin/env python3
"""Checks of the plinth and the perimetric joint (issue 22; docs/theory.md section 12),
against statics closed forms computed here without cfrd code:

  blocks-compression  a slab block (1 m, 24 kN/m3, nu = 0) resting on a plinth block fixed
                      on the rock through a PJOINT line: the joint carries the slab's weight,
                      sigma_n = -24 kPa, and closes by 24 / KNC; no settlement (1e-9);
  blocks-tension      the same slab pulled up by 30 kPa on its top: the waterstops carry
                      the 6 kPa left over, the joint opens by 6 / KNT (Newton to 1e-10; 1e-8);
  results             DECK-pjoint.csv, the HDF5 group /stages/stage_0001/pjoint and the
                      listing's PERIMETRIC JOINT table hold the same numbers;
  figure              tools/figures.py --data draws pjoint.png with the HDF5 group's opening
                      and settlement (mm) at each stage, exactly;
  generator           tools/tianshengqiao.py --plinth writes, for every interface method, an
                      x1 deck that cfrd reads and validates (cfrd --check): the joint's pairs
                      coincide, the plinth lies on the base, the stiffnesses are positive.

  python3 tools/check_plinth.py --cfrd bin/cfrd --workdir build/plinth   (PASS/FAIL lines)
"""

import csv
import os
import sys

from cfrdtools.checks import Checks, fresh, parser
from cfrdtools.decks import fmt_alpha as fa, fmt_int as fi, fmt_real as fr
from cfrdtools.results import open_results
from cfrdtools.runner import run, run_text, tianshengqiao, tool

KNC, KNT, KS = 1.0e7, 1.0e3, 1.0e3          # kPa/m, the deck's PJOINT card
GAMMA, HS, PULL = 24.0, 1.0, 30.0            # kN/m3, m (slab block), kPa (tension case)
check = Checks("plinth")


def deck(pull):
    """The two blocks: plinth (nodes 1-4, y 0-1) on the rock, slab (5-8, y 1-2) on it,
    joined by one PJOINT joint between pairs 3/5 and 4/6; gravity, and `pull` kPa upwards on
    the slab's top (nodal forces of 2 m of it)."""
    control = " " * 15 + fi(1) + fr(101.325) + fr(9.81) + fa("KN-M") + fi(0) + fi(3) \
        + fr(1.0e-10) + fi(30)
    force = [] if not pull else ["FORCE         7    8    1" + fr(0.0) + fr(pull)]
    return "\n".join(
        ["TITLE     plinth blocks (tools/check_plinth.py)", "CONTROL", control, "NODES",
         "    1    2    1       0.0       0.0       2.0       0.0",
         "    3    4    1       0.0       1.0       2.0       1.0",
         "    5    6    1       0.0       1.0       2.0       1.0",
         "    7    8    1       0.0       2.0       2.0       2.0",
         "ELEMENTS",
         "    1    1    2    4    3    1    0    1 PLINTH",
         "    2    5    6    8    7    1    0    1 SLAB",
         "MATERIALS", "    1ELASTIC   concrete", "     3.0E7       0.0" + fr(GAMMA),
         "    2PJOINT    perimetric joint", fr(KNC) + fr(KNT) + fr(KS),
         "INTERFACE", "    2    3    5    1    1    1    2JOINT     LOBATTO   SLAB",
         "PLINTH", "          PLINTH", "BOUNDARY", "    1    2    1    1    1",
         "LOADS", "GRAVITY"] + force + ["END"]) + "\n"


def rows(path):
    with open(path) as f:
        return list(csv.DictReader(line for line in f if not line.startswith("#")))


def close(a, b, rel):
    return abs(a - b) <= rel * abs(b)


def blocks(cfrd, work):
    cases = (("compression", 0.0, -GAMMA * HS, -GAMMA * HS / KNC, 1e-9),
             ("tension", PULL, PULL - GAMMA * HS, (PULL - GAMMA * HS) / KNT, 1e-8))
    for name, pull, sigma, opening, rel in cases:
        path = os.path.join(work, f"blocks-{name}.dat")
        # FORCE: the 2 m of top on its 2 nodes, 1 m each: pull kN/m per node = pull kPa
        h5 = run_text(cfrd, path, deck(pull))
        row = rows(path[:-4] + "-pjoint.csv")[-1]
        got = {k: float(row[k]) for k in ("opening_m", "settlement_m", "sigma_n_kpa")}
        check(f"blocks-{name}", close(got["opening_m"], opening, rel)
              and close(got["sigma_n_kpa"], sigma, rel) and abs(got["settlement_m"]) <= 1e-12,
              f"opening {got['opening_m']:.6e} m (closed form {opening:.6e}), sigma_n "
              f"{got['sigma_n_kpa']:.6e} kPa ({sigma:.6e}), settlement "
              f"{got['settlement_m']:.1e} m")
        if name == "tension":
            with open_results(h5) as f:
                g = f["stages/stage_0001/pjoint"]
                # the CSV holds 10 significant digits
                same = (int(g["line"][0]) == int(row["line"]) == 2
                        and close(float(g["opening"][0]), float(row["opening_m"]), 1e-9)
                        and abs(float(g["settlement"][0]) - float(row["settlement_m"])) <= 1e-15
                        and float(g["shear"][0]) == 0.0)
            with open(path[:-4] + ".out") as f:
                listing = f.read()
            check("results", same and "PERIMETRIC JOINT" in listing
                  and f"{1e3 * float(row['opening_m']):.3f}" in listing,
                  "the CSV row, the HDF5 group pjoint and the listing's table agree")


def figure(work):
    """pjoint.png's curves (figures.py --data) against the HDF5 group of the tension case."""
    h5 = os.path.join(work, "blocks-tension.h5")
    out = os.path.join(work, "figures")
    status, text = tool("figures.py", h5, "--out", out, "--data", "--reference", "none")
    data = rows(os.path.join(out, "data", "pjoint.csv"))
    with open_results(h5) as f:
        g = f["stages/stage_0001/pjoint"]
        want = {"perimetric joint: opening": 1e3 * float(g["opening"][0]),
                "perimetric joint: settlement": 1e3 * float(g["settlement"][0])}
    got = {r["panel"]: (float(r["x"]), float(r["y"])) for r in data}
    check("figure", status == 0 and all(got.get(k) == (1.0, v) for k, v in want.items()),
          f"pjoint.png: {got} against the HDF5 group {want} (exact)")


def generator(cfrd, work):
    for method in ("bonded", "joint", "thin", "contact"):
        path = tianshengqiao(os.path.join(work, f"tsq-{method}.dat"), "--refine", "1",
                             "--interface", method, "--plinth")
        done = run(cfrd, path, "--check", check=False)
        with open(path) as f:
            text = f.read()
        check(f"generator-{method}", done.returncode == 0 and "\nPLINTH\n" in text
              and "PJOINT" in text, f"cfrd --check exit {done.returncode}"
              + (f": {done.stderr.strip()[:200]}" if done.returncode else ""))


def main():
    args = parser(__doc__, cfrd=True, workdir="build/plinth").parse_args()
    work = fresh(args.workdir)
    check.guard("blocks", blocks, args.cfrd, work)
    check.guard("figure", figure, work)
    check.guard("generator", generator, args.cfrd, work)
    sys.exit(check.status)


if __name__ == "__main__":
    main()
