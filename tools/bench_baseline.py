#!/usr/bin/env python3
"""Before and after in one run (`make bench BASELINE=path/to/old/cfrd`; issue 21): the
baseline binary and this one on the same decks, alternately, ROUNDS rounds each, and the
ratios new / baseline of the user CPU time, the analysis time and the factorisation time
(symbolic + numeric) of the listing; then whether the two result sets agree (tools/compare.py
with --atol 1e-8max: every quantity but the solver's counts to 1e-8 of its largest value; the
relative residual, a converged one at round-off, to 1e-9 absolute as in tools/regression.py).

    python3 tools/bench_baseline.py --baseline OLD [--cfrd bin/cfrd] [--rounds 3]
                                    [--refine 4] [--interfaces bonded,joint,thin,contact]
                                    [--solvers midpoint,newton] [--workdir DIR] [DECK ...]

Decks named on the command line replace the generated Tianshengqiao-I ones
(tools/tianshengqiao.py --refine R --interface I --solver S). The machine's one-minute load
average is printed before each run: on a shared machine the spread of the rounds and the
load say how far a ratio can be trusted. The medians of the rounds are compared; the user
time is the child's own (getrusage), the times of the listing are cfrd's own clocks.
"""

import argparse
import os
import re
import resource
import statistics
import subprocess
import sys
import time

from cfrdtools import runner
from compare import QUANTITIES

TIMES = {"analysis": r"TOTAL ANALYSIS TIME\s+([0-9.]+)",
         "symbolic": r"^\s+symbolic factorisation\s+\S+\s+([0-9.]+)",
         "numeric": r"^\s+numeric factorisation\s+\S+\s+([0-9.]+)",
         "solve": r"^\s+solve\s+\S+\s+([0-9.]+)"}
COUNTS = {"factorisations": r"^\s+numeric factorisations\s+\d+\s+(\d+)",
          "cholmod": r"^\s+of which CHOLMOD \(L L\^T\)\s+\d+\s+(\d+)"}


def listing_figures(out):
    """The times (s, all stages) and counts of a listing's SOLVER block."""
    text = open(out).read()
    fig = {}
    for key, pattern in list(TIMES.items()) + list(COUNTS.items()):
        m = re.search(pattern, text, re.M)
        fig[key] = float(m.group(1)) if m else None
    return fig


def timed_run(cfrd, deck, outdir):
    """Run cfrd on deck into outdir; returns (user s, system s, wall s, load before, the
    listing's figures)."""
    os.makedirs(outdir, exist_ok=True)
    load = os.getloadavg()[0]
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.perf_counter()
    done = subprocess.run([cfrd, "--quiet", "--out", outdir, deck], capture_output=True,
                          text=True)
    wall = time.perf_counter() - t0
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if done.returncode:
        raise runner.CfrdFailed(f"{cfrd} failed on {deck}: {done.stderr.strip()[:300]}")
    stem = os.path.join(outdir, os.path.splitext(os.path.basename(deck))[0])
    return (after.ru_utime - before.ru_utime, after.ru_stime - before.ru_stime, wall, load,
            listing_figures(stem + ".out"))


def agreement(a_h5, b_h5):
    """tools/compare.py A B --rtol 0 --atol 1e-8max, the relative residual to 1e-9 absolute
    (a converged residual is round-off, 1e-13 to 1e-11: tools/regression.py's tolerance),
    every quantity but the counts (how many factorisations and updates a solver makes is
    what a change of the solver may change; the increments and iterations are in the
    listings): (agree, its last line)."""
    status, text = runner.tool("compare.py", a_h5, b_h5, "--rtol", "0", "--atol", "1e-8max",
                               "--tol", "residual=0,1e-9", "--quantities",
                               ",".join(q for q in QUANTITIES if q != "counts"))
    last = [ln for ln in text.splitlines() if ln.strip()][-1:] or ["(no output)"]
    return status == 0, last[0]


def ratio(new, old):
    return f"{new / old:.3f}" if new is not None and old else "-"


def fmt(values):
    return ", ".join("-" if v is None else f"{v:.2f}" for v in values)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--baseline", required=True, help="the cfrd binary to compare against")
    ap.add_argument("--cfrd", default=os.path.join(runner.ROOT, "bin", "cfrd"))
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--refine", default="4")
    ap.add_argument("--interfaces", default="bonded,joint,thin,contact")
    ap.add_argument("--solvers", default="midpoint,newton")
    ap.add_argument("--workdir", default=os.path.join(runner.ROOT, "build", "bench-baseline"))
    ap.add_argument("decks", nargs="*")
    args = ap.parse_args(argv)
    for path in (args.baseline, args.cfrd):
        if not os.access(path, os.X_OK):
            print(f"bench_baseline: no program at {path}", file=sys.stderr)
            return 2
    os.makedirs(args.workdir, exist_ok=True)
    decks = [os.path.abspath(d) for d in args.decks]
    if not decks:
        for interface in args.interfaces.split(","):
            for solver in args.solvers.split(","):
                deck = os.path.join(args.workdir, f"x{args.refine}-{interface}-{solver}.dat")
                runner.tianshengqiao(deck, "--refine", args.refine, "--interface", interface,
                                     "--solver", solver)
                decks.append(deck)
    print(runner.machine())
    print(f"baseline {os.path.abspath(args.baseline)}, new {os.path.abspath(args.cfrd)}; "
          f"{args.rounds} rounds, alternating")
    rows, failed = [], False
    for deck in decks:
        name = os.path.splitext(os.path.basename(deck))[0]
        runs = {"baseline": [], "new": []}
        for k in range(args.rounds):
            for label, binary in (("baseline", args.baseline), ("new", args.cfrd)):
                r = timed_run(binary, deck, os.path.join(args.workdir, label))
                runs[label].append(r)
                print(f"  {name} {label} round {k + 1}: load {r[3]:.2f}, user {r[0]:.2f} s, "
                      f"analysis {r[4]['analysis']} s, factorisation "
                      f"{(r[4]['symbolic'] or 0) + (r[4]['numeric'] or 0):.3f} s",
                      file=sys.stderr, flush=True)
        ok, verdict = agreement(os.path.join(args.workdir, "baseline", name + ".h5"),
                                os.path.join(args.workdir, "new", name + ".h5"))
        failed = failed or not ok
        med = {}
        for label, rs in runs.items():
            med[label] = {"user": statistics.median(r[0] for r in rs),
                          "analysis": statistics.median(r[4]["analysis"] for r in rs),
                          "fact": statistics.median((r[4]["symbolic"] or 0) +
                                                    (r[4]["numeric"] or 0) for r in rs)}
        last = runs["new"][-1][4]
        rows.append((name, fmt(r[3] for r in runs["baseline"] + runs["new"]),
                     fmt(r[0] for r in runs["baseline"]), fmt(r[0] for r in runs["new"]),
                     ratio(med["new"]["user"], med["baseline"]["user"]),
                     fmt(r[4]["analysis"] for r in runs["baseline"]),
                     fmt(r[4]["analysis"] for r in runs["new"]),
                     ratio(med["new"]["analysis"], med["baseline"]["analysis"]),
                     fmt((r[4]["symbolic"] or 0) + (r[4]["numeric"] or 0)
                         for r in runs["baseline"]),
                     fmt((r[4]["symbolic"] or 0) + (r[4]["numeric"] or 0) for r in runs["new"]),
                     ratio(med["new"]["fact"], med["baseline"]["fact"]),
                     f"{last['cholmod']:.0f}/{last['factorisations']:.0f}"
                     if last["cholmod"] is not None else "-",
                     verdict))
    header = ("deck", "load before each run", "user s, baseline", "user s, new", "user ratio",
              "analysis s, baseline", "analysis s, new", "analysis ratio",
              "factorisation s, baseline", "factorisation s, new", "factorisation ratio",
              "CHOLMOD / all factorisations (new)", "results to 1e-8 of max")
    print("| " + " | ".join(header) + " |")
    print("|" + "---|" * len(header))
    for row in rows:
        print("| " + " | ".join(row) + " |")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
