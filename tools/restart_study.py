#!/usr/bin/env python3
"""Reservoir histories after the end of construction: 10 full runs against one restart point.

    python3 tools/restart_study.py --cfrd bin/cfrd --workdir build/restart-study [--refine 2]

The Tianshengqiao-I contact deck (tools/tianshengqiao.py --interface contact) is built to the
end of slab phase 3 (stage 44); its last stage raises the reservoir to El. 768 m. Ten
scenario decks replace that stage by a history [choice, a test of the restart, not a design
study]: the reservoir to 768 m, drawn down to 765 - 5 i m (i = 0 .. 9, 10 m a step) and
raised to 768 m again. Each scenario is run in full, and from the results of the base deck
at stage 44 (`cfrd --restart BASE.h5 --from-stage 44 SCENARIO.dat`); the restarted results
must equal the full run's to the last bit (tools/check_restart.py's comparison). Times are
CPU seconds (user + system of the cfrd process) and wall seconds, OPENBLAS_NUM_THREADS=1.

With `--before BIN` it measures instead what the restart state costs a plain run: the base
deck run `--pairs` times by BIN (a build without it) and by --cfrd, alternately, CPU seconds
and the size of the results file.
"""

import os
import re
import resource
import subprocess
import sys
import time

from cfrdtools.checks import Checks, fresh, parser
from check_restart import same_results

HERE = os.path.dirname(os.path.abspath(__file__))
check = Checks("restart-study")


def timed(cmd):
    """(exit status, CPU s, wall s) of a quiet run."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.monotonic()
    status = subprocess.run(cmd, capture_output=True, env=dict(
        os.environ, OPENBLAS_NUM_THREADS="1")).returncode
    wall = time.monotonic() - t0
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return status, cpu, wall


def scenario(base_text, i):
    """The base deck with its last stage (WATER 768) replaced by history i."""
    low = 765.0 - 5.0 * i
    down = max(1, round((768.0 - low) / 10.0 + 0.49))
    stages = (f"WATER          768.0    51999.08   reservoir to El. 768.0 m\n"
              f"WATER     {low:10.1f}{down:5d}2000.03    drawdown to El. {low:.1f} m [choice]\n"
              f"WATER          768.0{down:5d}2000.08    refilled to El. 768.0 m [choice]\n")
    text, n = re.subn(r"^WATER          768\.0    51999\.08.*\n", stages, base_text, flags=re.M)
    assert n == 1
    return text


def overhead(args, base, work):
    """CPU seconds of plain runs of `base` by --before and --cfrd, alternately."""
    cpu = {"before": [], "after": []}
    size = {}
    for i in range(args.pairs):
        order = [("before", args.before), ("after", args.cfrd)]
        for name, binary in (order if i % 2 == 0 else order[::-1]):
            folder = os.path.join(work, name)
            status, seconds, _ = timed([binary, "--quiet", "--out", folder, base])
            check(f"overhead/{name}-run-{i + 1}", status == 0, f"{seconds:.2f} s CPU")
            cpu[name].append(seconds)
            size[name] = os.path.getsize(os.path.join(folder, "base.h5"))
    for name in ("before", "after"):
        v = sorted(cpu[name])
        print(f"{name}: CPU s {', '.join(f'{x:.2f}' for x in cpu[name])}; median "
              f"{v[len(v) // 2]:.2f}, mean {sum(v) / len(v):.2f}; results file "
              f"{size[name] / 1e6:.1f} MB")
    b, a = sorted(cpu["before"]), sorted(cpu["after"])
    print(f"after / before: median {a[len(a) // 2] / b[len(b) // 2]:.3f}, mean "
          f"{sum(a) / sum(b):.3f}, fastest {a[0] / b[0]:.3f}; file {size['after'] / size['before']:.3f}")
    return check.status


def main():
    ap = parser(__doc__, cfrd="bin/cfrd", workdir="build/restart-study")
    ap.add_argument("--refine", default="2")
    ap.add_argument("--from-stage", type=int, default=44)
    ap.add_argument("--before", help="a cfrd without the restart state: measure its cost")
    ap.add_argument("--pairs", type=int, default=5)
    args = ap.parse_args()
    work = fresh(args.workdir)
    base = os.path.join(work, "base.dat")
    subprocess.run([sys.executable, os.path.join(HERE, "tianshengqiao.py"), "--refine",
                    args.refine, "--interface", "contact", "--deck", base], check=True,
                   capture_output=True)
    if args.before:
        return overhead(args, base, work)
    text = open(base).read()
    decks = []
    for i in range(10):
        decks.append(os.path.join(work, f"history{i}.dat"))
        open(decks[-1], "w").write(scenario(text, i))
    rows = []
    status, cpu_base, wall_base = timed([args.cfrd, "--quiet", "--out", os.path.join(
        work, "base"), base])
    check("base-run", status == 0, f"exit {status}")
    point = os.path.join(work, "base", "base.h5")
    for deck in decks:
        name = os.path.splitext(os.path.basename(deck))[0]
        full_dir, restart_dir = os.path.join(work, "full"), os.path.join(work, "restart")
        full = timed([args.cfrd, "--quiet", "--out", full_dir, deck])
        restart = timed([args.cfrd, "--quiet", "--restart", point, "--from-stage",
                         str(args.from_stage), "--out", restart_dir, deck])
        ok, detail = (False, f"exit {full[0]}/{restart[0]}") if full[0] or restart[0] else \
            same_results(os.path.join(restart_dir, name + ".h5"), os.path.join(
                full_dir, name + ".h5"), args.from_stage, restart_dir, full_dir, name, name)
        check(f"{name}/restart-equals-full-run", ok, detail)
        rows.append((name, full[1], full[2], restart[1], restart[2]))
    print(f"| history | full CPU s | full wall s | restart CPU s | restart wall s |")
    print("|---|---:|---:|---:|---:|")
    for name, fc, fw, rc, rw in rows:
        print(f"| {name} | {fc:.2f} | {fw:.2f} | {rc:.2f} | {rw:.2f} |")
    fc, fw = sum(r[1] for r in rows), sum(r[2] for r in rows)
    rc, rw = sum(r[3] for r in rows), sum(r[4] for r in rows)
    print(f"| sum of 10 | {fc:.2f} | {fw:.2f} | {rc:.2f} | {rw:.2f} |")
    print(f"base run to the restart point: CPU {cpu_base:.2f} s, wall {wall_base:.2f} s")
    print(f"speed-up, restarts alone: CPU {fc / rc:.1f}x, wall {fw / rw:.1f}x; with the base "
          f"run: CPU {fc / (rc + cpu_base):.1f}x, wall {fw / (rw + wall_base):.1f}x")
    return check.status


if __name__ == "__main__":
    sys.exit(main())
