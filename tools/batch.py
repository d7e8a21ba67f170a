#!/usr/bin/env python3
"""Run many decks at once, one cfrd process per deck on every core (issue 8, section 3).

    python3 tools/batch.py [--cfrd bin/cfrd] [--out DIR] [--jobs N] DECK [DECK ...]
    make batch DECKS="inputs/a.dat inputs/b.dat" [OUT=DIR] [JOBS=N]

Each deck runs as `cfrd --out DIR DECK` in its own process, at most N at a time (default:
the cores this process may use), with OPENBLAS_NUM_THREADS=1 so that N processes do not
start N threads each. Its listing, HDF5 file and CSVs go to DIR, what it prints (stage
progress, result table, messages) to DIR/DECK.log. A deck that fails does not stop the
others. When all have finished, a summary table is printed and written to
DIR/batch-summary.csv: deck, status, stages, wall time, the largest settlement since
placement over all stages (with its node and stage) and the largest interface opening over
all stages (with its slab phase and stage; blank for decks without INTERFACE cards).

SIGINT (Ctrl-C) or SIGTERM (Slurm's time limit) stops the batch: the signal is passed on to
the decks running, which stop before their next load increment and keep their completed
stages in DIR/DECK.incomplete.h5 (docs/results.md, "Stopped runs"); the decks not yet
started are not run; the summary table and CSV are still written, with the status
"stopped (SIGTERM)" or "not run". A second signal ends the batch at once.

Exit status: 0 when every deck ran; otherwise the number of decks that failed (1-100,
100 meaning 100 or more); 101 when the batch could not start (bad arguments, no cfrd
program, --out naming a file, two decks that would write the same result files, which is
checked before any run: the message names both); 130 / 143 when stopped by SIGINT /
SIGTERM. (The batch's own "could not start" is 101, not cfrd's 2: here 2 means that two
decks failed.)
"""

import argparse
import concurrent.futures
import csv
import os
import signal
import subprocess
import sys
import threading
import time

import h5py
import numpy as np

from cfrdtools import results

BATCH_ERROR = 101
MAX_COUNT = 100
STATUS_TEXT = {0: "ok", 1: "failed", 2: "bad input", 130: "stopped (SIGINT)",
               143: "stopped (SIGTERM)"}


class Stopped(Exception):
    """SIGINT or SIGTERM arrived (raised in the main thread by the handler)."""

    def __init__(self, signum):
        super().__init__(signal.Signals(signum).name)
        self.signum = signum


def stop_on_signal(signum, frame):
    # A second signal ends the batch at once (the decks running have the first already).
    default_signals()
    raise Stopped(signum)


def default_signals():
    for signum in (signal.SIGINT, signal.SIGTERM):
        signal.signal(signum, signal.SIG_DFL)


class Running:
    """The cfrd processes running, and the signal that stops the batch (0: none)."""

    def __init__(self):
        self.lock = threading.Lock()
        self.procs = set()
        self.signum = 0

    def start(self, proc):
        with self.lock:
            self.procs.add(proc)
            if self.signum:
                proc.send_signal(self.signum)    # started while the batch was stopping

    def end(self, proc):
        with self.lock:
            self.procs.discard(proc)

    def stop(self, signum):
        with self.lock:
            self.signum = signum
            for proc in self.procs:
                proc.send_signal(signum)


class DeckRun:
    """What one deck's run gave: exit status, time and the key results of its HDF5 file."""

    def __init__(self, deck, stem):
        self.deck = deck
        self.stem = stem
        self.returncode = None
        self.wall = 0.0
        self.stages = None
        self.max_settlement = None      # (value m, node, stage)
        self.max_opening = None         # (value m, phase, stage)
        self.message = ""

    @property
    def ok(self):
        return self.returncode == 0

    @property
    def status(self):
        if self.returncode is None:
            return "not run"
        if self.returncode < 0:
            return f"killed ({signal.Signals(-self.returncode).name})"
        return STATUS_TEXT.get(self.returncode, f"exit {self.returncode}")


def stem_of(deck):
    return os.path.splitext(os.path.basename(deck))[0]


def key_results(path):
    """(stages, max settlement (m, node, stage), max opening (m, phase, stage) or None)
    from a cfrd HDF5 file (layout: docs/results.md)."""
    with h5py.File(path, "r") as f:
        names = sorted(f["stages"])
        groups = ([results.text(g) for g in f["mesh/group_names"][...]]
                  if "mesh/group_names" in f else [])
        settlement = None
        opening = None
        for k, name in enumerate(names, start=1):
            g = f["stages"][name]
            uy = g["displacement_total"][:, 1]
            i = int(np.argmin(uy))
            if settlement is None or -uy[i] > settlement[0]:
                settlement = (float(-uy[i]), i + 1, k)
            r = g.get("interface")
            if r is not None and "opening_width" in r and len(r["opening_width"]):
                w = r["opening_width"][...]
                j = int(np.argmax(w))
                gi = int(r["opening_group"][j])
                phase = groups[gi - 1] if 0 < gi <= len(groups) else str(gi)
                if opening is None or w[j] > opening[0]:
                    opening = (float(w[j]), phase, k)
        return len(names), settlement, opening


def run_one(run, cfrd, out, running):
    log = os.path.join(out, run.stem + ".log")
    env = dict(os.environ, OPENBLAS_NUM_THREADS="1")
    start = time.monotonic()
    with open(log, "w") as fh:
        try:
            proc = subprocess.Popen([cfrd, "--out", out, run.deck], stdout=fh,
                                    stderr=subprocess.STDOUT, env=env)
        except OSError as exc:
            run.returncode = 127
            run.message = f"cannot start {cfrd}: {exc.strerror}"
            fh.write(run.message + "\n")
            return run
        running.start(proc)
        proc.wait()
        running.end(proc)
    run.wall = time.monotonic() - start
    run.returncode = proc.returncode
    if run.ok:
        # Only a run that succeeded has written (renamed into place) fresh results; a
        # failed one leaves any earlier results untouched, which must not be reported.
        try:
            run.stages, run.max_settlement, run.max_opening = \
                key_results(os.path.join(out, run.stem + ".h5"))
        except (OSError, KeyError) as exc:
            run.message = f"cannot read the results: {exc}"
    else:
        with open(log) as fh:
            lines = [l.strip() for l in fh if l.startswith("cfrd: ") and
                     "warning" not in l]
        run.message = lines[-1][6:] if lines else f"see {log}"
    return run


class BatchRuns(list):
    """The DeckRun of each deck in deck order; `stopped` is the signal that stopped the
    batch (0: none; the decks it kept from starting are "not run")."""
    stopped = 0


def run_batch(decks, cfrd, out, jobs, progress=None):
    """Run the decks, at most `jobs` at a time; returns their BatchRuns. On Stopped (the
    handlers main installs) the decks running get the signal and are waited for; on a
    KeyboardInterrupt they are too, then it is raised again."""
    runs = BatchRuns(DeckRun(d, stem_of(d)) for d in decks)
    running = Running()
    done = 0
    pool = concurrent.futures.ThreadPoolExecutor(max_workers=jobs)
    futures = []
    try:
        # Largest decks first: the last to finish is then a small one (shorter total time).
        order = sorted(runs, key=lambda r: -deck_size(r.deck))
        futures = [pool.submit(run_one, r, cfrd, out, running) for r in order]
        for fut in concurrent.futures.as_completed(futures):
            run = fut.result()
            done += 1
            if progress:
                progress(done, len(runs), run)
    except (Stopped, KeyboardInterrupt) as exc:
        signum = exc.signum if isinstance(exc, Stopped) else signal.SIGINT
        for f in futures:
            f.cancel()
        running.stop(signum)
        # The decks running write their incomplete results before they end.
        pool.shutdown(wait=True)
        if not isinstance(exc, Stopped):
            raise
        runs.stopped = int(signum)
        return runs
    pool.shutdown(wait=True)
    return runs


def deck_size(deck):
    try:
        return os.path.getsize(deck)
    except OSError:
        return 0


def check_decks(decks):
    """Two decks with the same name would overwrite each other's results in one folder."""
    seen = {}
    for d in decks:
        s = stem_of(d)
        if s in seen:
            return f"{seen[s]} and {d} would both write {s}.out and {s}.h5: run them " \
                   f"into different --out folders"
        seen[s] = d
    return None


def fmt_settlement(run):
    if run.max_settlement is None:
        return ""
    v, node, stage = run.max_settlement
    return f"{v:.4f} (node {node}, stage {stage})"


def fmt_opening(run):
    if run.max_opening is None:
        return ""
    v, phase, stage = run.max_opening
    return f"{v:.4f} ({phase}, stage {stage})"


def summary_rows(runs):
    return [[r.deck, r.status, "" if r.stages is None else str(r.stages), f"{r.wall:.2f}",
             fmt_settlement(r), fmt_opening(r), r.message] for r in runs]


def print_summary(runs, out=sys.stdout):
    header = ["deck", "status", "stages", "time s", "max settlement m",
              "max opening m", "message"]
    rows = summary_rows(runs)
    widths = [max(len(h), *(len(r[k]) for r in rows)) for k, h in enumerate(header)]
    right = {2, 3}

    def line(cells):
        return "  ".join(c.rjust(w) if k in right else c.ljust(w)
                         for k, (c, w) in enumerate(zip(cells, widths))).rstrip()
    print(line(header), file=out)
    print("  ".join("-" * w for w in widths), file=out)
    for r in rows:
        print(line(r), file=out)
    failed = sum(not r.ok for r in runs)
    print(f"{len(runs) - failed} of {len(runs)} decks ran, {failed} failed", file=out)


def write_summary_csv(runs, path):
    with open(path, "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["deck", "status", "exit_status", "stages", "wall_time_s",
                    "max_settlement_m", "max_settlement_node", "max_settlement_stage",
                    "max_opening_m", "max_opening_phase", "max_opening_stage", "message"])
        for r in runs:
            s = r.max_settlement or ("", "", "")
            o = r.max_opening or ("", "", "")
            w.writerow([r.deck, r.status, r.returncode, "" if r.stages is None else r.stages,
                        f"{r.wall:.3f}", *s, *o, r.message])


def exit_status(runs):
    return min(sum(not r.ok for r in runs), MAX_COUNT)


def default_jobs():
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:
        return os.cpu_count() or 1


def main(argv=None):
    parser = argparse.ArgumentParser(
        description="Run cfrd decks in parallel, one process per deck, and summarise.")
    parser.add_argument("decks", nargs="*", metavar="DECK")
    parser.add_argument("--cfrd", default="bin/cfrd", help="the program (default bin/cfrd)")
    parser.add_argument("--out", default="batch-results",
                        help="folder for the results and logs (default batch-results)")
    parser.add_argument("--jobs", "-j", type=int, default=default_jobs(),
                        help="decks run at once (default: the cores available)")
    parser.add_argument("--quiet", action="store_true", help="no progress lines")
    try:
        args = parser.parse_args(argv)
    except SystemExit as exc:
        return 0 if exc.code == 0 else BATCH_ERROR
    error = None
    if not args.decks:
        error = "no deck given"
    elif args.jobs < 1:
        error = f"--jobs must be at least 1, found {args.jobs}"
    elif not (os.path.isfile(args.cfrd) and os.access(args.cfrd, os.X_OK)):
        error = f"{args.cfrd}: no such program (make build makes bin/cfrd)"
    elif os.path.exists(args.out) and not os.path.isdir(args.out):
        error = f"--out {args.out}: a file of that name exists; --out names the folder " \
                f"for the results"
    else:
        error = check_decks(args.decks)
    if error:
        print(f"batch: {error}", file=sys.stderr)
        return BATCH_ERROR
    try:
        os.makedirs(args.out, exist_ok=True)
    except OSError as exc:
        print(f"batch: cannot create the folder {args.out}: {exc.strerror}", file=sys.stderr)
        return BATCH_ERROR

    def progress(done, total, run):
        if not args.quiet:
            print(f"[{done}/{total}] {run.deck}: {run.status}, {run.wall:.2f} s"
                  + (f": {run.message}" if run.message else ""), flush=True)
    for signum in (signal.SIGINT, signal.SIGTERM):
        signal.signal(signum, stop_on_signal)
    runs = run_batch(args.decks, args.cfrd, args.out, args.jobs, progress)
    stopped = runs.stopped
    default_signals()     # the runs are over: a signal now ends the batch at once
    print()
    print_summary(runs)
    summary = os.path.join(args.out, "batch-summary.csv")
    write_summary_csv(runs, summary)
    print(f"Results and logs in {args.out}/; this table in {summary}")
    if stopped:
        print(f"batch: stopped by {signal.Signals(stopped).name}: the decks that were "
              f"running keep their completed stages in {args.out}/DECK.incomplete.h5; "
              f"the others are not run", file=sys.stderr)
        return 128 + stopped
    return exit_status(runs)


if __name__ == "__main__":
    sys.exit(main())
