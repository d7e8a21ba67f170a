#!/usr/bin/env python3
"""The OpenMP element loops give the same bits for any thread count (issue 21;
docs/performance.md, "(m) OpenMP"), on the x1 Tianshengqiao-I bonded and contact decks.

    python3 tools/check_threads.py --cfrd build/debug-bin/cfrd --workdir DIR
                                   [--against OTHER_CFRD]

Checks, each printing PASS or FAIL:
  - for each deck, the run with --threads 2 and the run with OMP_NUM_THREADS=2 (no option)
    write the same HDF5 datasets and attributes, bit for bit, timings aside, as the run with
    --threads 1 (reference: that run; compare_stages of tools/check_stop.py);
  - threads-started: a run with --threads 3 has (at least) two more threads than a run with
    --threads 1 while it runs (/proc/PID/task; the program was built with OpenMP), both with
    --linear-solver umfpack (CHOLMOD's own OpenMP loops, held to one thread since
    docs/performance.md (r), are kept out of the count all the same) and
    OPENBLAS_NUM_THREADS=1 (no OpenBLAS workers started when the library loads);
  - --threads 0 and --threads x are usage errors (exit 2, the message names the option);
  - with --against BIN (by hand: another build, e.g. main's bin/cfrd before the change), the
    --threads 1 and --threads 2 runs against BIN's run, the same way, bit for bit.
"""

import os
import subprocess
import sys
import time

from cfrdtools.checks import Checks, fresh, parser
from check_stop import compare_stages

DECKS = ("inputs/tianshengqiao-x1.dat", "inputs/tianshengqiao-x1-contact.dat")


def run(cfrd, folder, deck, threads=None, env=None):
    """Run deck into folder; the HDF5 file's path."""
    args = [cfrd, "--quiet", "--out", folder] + (["--threads", str(threads)] if threads else [])
    subprocess.run(args + [deck], env=env, check=True)
    return os.path.join(folder, os.path.splitext(os.path.basename(deck))[0] + ".h5")


def most_threads(cfrd, folder, deck, threads):
    """The most threads (/proc/PID/task) seen while cfrd runs deck with --threads N."""
    # UMFPACK: CHOLMOD has supernodal loops on OpenMP teams of its own (CHOLMOD_OMP_NUM_THREADS,
    # fixed when SuiteSparse was built: 4 threads were seen with --threads 1 before cfrd held
    # them to one, docs/performance.md (r)); kept out so that only cfrd's own loops count.
    # OPENBLAS_NUM_THREADS=1 for the same reason: OpenBLAS starts its workers when the
    # library loads, before cfrd ends them (docs/performance.md (r)), and a sample taken in
    # that moment would count them with --threads 1 (seen: 2 threads)
    proc = subprocess.Popen([cfrd, "--quiet", "--threads", str(threads), "--linear-solver",
                             "umfpack", "--out", folder, deck],
                            env=dict(os.environ, OMP_WAIT_POLICY="passive",
                                     OPENBLAS_NUM_THREADS="1"))
    most = 0
    while proc.poll() is None:
        try:
            most = max(most, len(os.listdir(f"/proc/{proc.pid}/task")))
        except OSError:
            pass
        time.sleep(0.01)
    return most if proc.returncode == 0 else -1


def same(check, name, reference, candidate, what):
    names, _, differences = compare_stages(candidate, reference)
    check(name, names and not differences,
          f"{len(names)} stages, every dataset and attribute (timings aside) equal to {what}"
          if names and not differences else "; ".join(differences[:4]) or "no stages")


def main():
    ap = parser(__doc__, cfrd="build/debug-bin/cfrd", workdir="build/check-threads")
    ap.add_argument("--against", help="another cfrd whose results must be the same bits")
    args = ap.parse_args()
    check = Checks("threads")
    cfrd, work = os.path.abspath(args.cfrd), fresh(args.workdir)
    # passive: the idle threads of the 2-thread runs sleep instead of spinning (README)
    env = dict({k: v for k, v in os.environ.items() if k != "OMP_NUM_THREADS"},
               OMP_WAIT_POLICY="passive")
    for deck in DECKS:
        tag = os.path.splitext(os.path.basename(deck))[0]
        one = run(cfrd, os.path.join(work, tag, "1"), deck, 1, env)
        two = run(cfrd, os.path.join(work, tag, "2"), deck, 2, env)
        same(check, f"{tag}/2-threads-bit-identical", one, two, "the --threads 1 run")
        envrun = run(cfrd, os.path.join(work, tag, "env"), deck,
                     env=dict(env, OMP_NUM_THREADS="2"))
        same(check, f"{tag}/OMP_NUM_THREADS=2-bit-identical", one, envrun,
             "the --threads 1 run")
        if args.against:
            other = run(os.path.abspath(args.against), os.path.join(work, tag, "against"),
                        deck, env=env)
            same(check, f"{tag}/1-thread-against-{args.against}", other, one, args.against)
            same(check, f"{tag}/2-threads-against-{args.against}", other, two, args.against)
    one = most_threads(cfrd, os.path.join(work, "count-1"), DECKS[0], 1)
    three = most_threads(cfrd, os.path.join(work, "count-3"), DECKS[0], 3)
    check("threads-started", one > 0 and three >= one + 2,
          f"most threads seen: {three} with --threads 3, {one} with --threads 1")
    for bad in ("0", "x"):
        out = subprocess.run([cfrd, "--threads", bad, "--check", DECKS[0]],
                             capture_output=True, text=True)
        check(f"usage-threads-{bad}", out.returncode == 2 and "--threads" in out.stderr,
              f"exit {out.returncode}: {out.stderr.strip()[:120]}")
    return check.status


if __name__ == "__main__":
    sys.exit(main())
