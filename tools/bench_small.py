#!/usr/bin/env python3
"""Fixed costs of small decks (issue 21; docs/performance.md (r)): table (b)'s embankment
(tools/ccx_peer.mesh_for, the decks of tools/bench.py) run by one or more cfrd programs and
by CalculiX, in alternating rounds so that a shared machine's load falls on all of them
alike; per program the minimum over the rounds of the wall time and of the CPU time (user
+ system of the process and its threads, from wait4), and the ratios to CalculiX's.

    python3 tools/bench_small.py --cfrd OLD/cfrd,bin/cfrd [--sizes 1000,10000,100000]
                                 [--repeat 3] [--workdir build/bench-small] [--no-ccx]

An entry of --cfrd may carry options after the program ("bin/cfrd --compress 0").

Prints a markdown table. CPU time is less disturbed by the other processes of a shared
machine than wall time (it does not count the time the process waits for a core).
"""

import argparse
import os
import shlex
import subprocess
import sys
import time

import ccx_peer as peer
import embankment as emb


def timed(cmd, cwd):
    """(wall s, user s, system s) of cmd, which must exit 0."""
    t0 = time.perf_counter()
    proc = subprocess.Popen(cmd, cwd=cwd, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    _, status, usage = os.wait4(proc.pid, 0)
    wall = time.perf_counter() - t0
    if os.waitstatus_to_exitcode(status) != 0:
        raise RuntimeError(f"{' '.join(cmd)} exited with {os.waitstatus_to_exitcode(status)}")
    return wall, usage.ru_utime, usage.ru_stime


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--cfrd", default="bin/cfrd", help="comma-separated programs")
    ap.add_argument("--sizes", default="1000,10000,100000")
    ap.add_argument("--repeat", type=int, default=3, help="rounds, minimum taken")
    ap.add_argument("--workdir", default="build/bench-small")
    ap.add_argument("--no-ccx", action="store_true")
    args = ap.parse_args(argv)
    os.makedirs(args.workdir, exist_ok=True)
    programs = [p.strip() for p in args.cfrd.split(",") if p.strip()]
    names = programs + ([] if args.no_ccx else ["ccx"])
    print("| elements | program | wall s | CPU s (user + sys) | user s | sys s | wall / ccx "
          "| CPU / ccx |")
    print("|---:|:---|---:|---:|---:|---:|---:|---:|")
    for n in (int(s) for s in args.sizes.split(",") if s.strip()):
        mesh, _ = peer.mesh_for(n)
        deck, job = os.path.join(args.workdir, f"embankment-{n}.dat"), f"embankment-{n}-ccx"
        emb.write_cfrd_deck(mesh, deck)
        emb.write_ccx_deck(mesh, os.path.join(args.workdir, job + ".inp"))
        runs = {p: [] for p in names}
        for _ in range(args.repeat):
            for p in names:
                cmd = ["ccx", "-i", job] if p == "ccx" else (
                    [os.path.abspath(shlex.split(p)[0])] + shlex.split(p)[1:]
                    + [os.path.abspath(deck), "--quiet"])
                runs[p].append(timed(cmd, args.workdir))
        best = {p: (min(r[0] for r in runs[p]), min(r[1] + r[2] for r in runs[p]),
                    min(r[1] for r in runs[p]), min(r[2] for r in runs[p])) for p in names}
        for p in names:
            w, c, u, s = best[p]
            ratio = ("-", "-") if "ccx" not in best or p == "ccx" else (
                f"{w / best['ccx'][0]:.2f}", f"{c / best['ccx'][1]:.2f}")
            print(f"| {mesh.nelem} | {p} | {w:.3f} | {c:.3f} | {u:.3f} | {s:.3f} | "
                  f"{ratio[0]} | {ratio[1]} |", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
