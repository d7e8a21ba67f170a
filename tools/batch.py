#!/usr/bin/env python3
"""Run many decks at once, one cfrd process per deck on every core (issue 8, section 3;
docs/results.md, "Running many decks").

    python3 tools/batch.py [--cfrd bin/cfrd] [--out DIR] [--jobs N] DECK [DECK ...]
    make batch DECKS="inputs/a.dat inputs/b.dat" [OUT=DIR] [JOBS=N]

Each deck runs as `cfrd --out DIR DECK` (OPENBLAS_NUM_THREADS=1), at most N at a time, what it
prints in DIR/DECK.log; with N at least the cores, also CFRD_WRITE_BEHIND=0 and CFRD_AHEAD=0
(each unless set): every core runs a deck, so none is free to write a deck's stages behind its
analysis or prepare its next stage's system ahead of it (docs/performance.md (ag), (ak)); then a summary is printed and written to DIR/batch-summary.csv.
SIGINT or SIGTERM is passed on to the decks running (they keep their completed stages); the
others are "not run". Exit status: 0 when every deck ran; else the number of failed decks (at
most 100); 101 when the batch could not start (bad arguments, no program, --out naming a
file, two decks that would write the same files: checked before any run); 130 / 143 when
stopped by SIGINT / SIGTERM.
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

import numpy as np

from cfrdtools import results, tables

BATCH_ERROR = 101
MAX_COUNT = 100
STATUS_TEXT = {0: "ok", 1: "failed", 2: "bad input", 130: "stopped (SIGINT)",
               143: "stopped (SIGTERM)"}
SUMMARY_COLUMNS = ["status", "exit_status", "stages", "wall_time_s", "max_settlement_m",
                   "max_settlement_node", "max_settlement_stage", "max_opening_m",
                   "max_opening_phase", "max_opening_stage", "message"]


class Stopped(Exception):
    """SIGINT or SIGTERM arrived (raised in the main thread by the handler)."""

    def __init__(self, signum):
        super().__init__(signal.Signals(signum).name)
        self.signum = signum


def stop_on_signal(signum, frame):
    default_signals()     # a second signal ends the batch at once (the decks have the first)
    raise Stopped(signum)


def default_signals():
    for signum in (signal.SIGINT, signal.SIGTERM):
        signal.signal(signum, signal.SIG_DFL)


class Running:
    """The cfrd processes running, and the signal that stops the batch (0: none)."""

    def __init__(self):
        self.lock, self.procs, self.signum = threading.Lock(), set(), 0

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
        self.deck, self.stem, self.returncode, self.wall = deck, stem, None, 0.0
        self.stages = self.max_settlement = self.max_opening = None  # (m, node | phase, stage)
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

    def read(self, path):
        self.stages, self.max_settlement, self.max_opening = key_results(path)


def stem_of(deck):
    return os.path.splitext(os.path.basename(deck))[0]


def key_results(path):
    """(stages, max settlement (m, node, stage), max opening (m, phase, stage) or None)
    from a cfrd HDF5 file (layout: docs/results.md)."""
    settlement = opening = None
    with results.open_results(path) as f:
        groups, st = results.group_names(f), results.stages(f)
        for k, g in enumerate(st, start=1):
            uy = results.field(g, "displacement_total")[:, 1]
            i = int(np.argmin(uy))
            if settlement is None or -uy[i] > settlement[0]:
                settlement = (float(-uy[i]), i + 1, k)
            r = g.get("interface")
            if r is not None and "opening_width" in r and len(r["opening_width"]):
                w = r["opening_width"][...]
                j = int(np.argmax(w))
                gi = int(r["opening_group"][j])
                if opening is None or w[j] > opening[0]:
                    opening = (float(w[j]), groups[gi - 1] if 0 < gi <= len(groups) else str(gi),
                               k)
        return len(st), settlement, opening


def error_of(lines):
    """cfrd's last message among the lines of its output (warnings aside), or None."""
    errors = [ln.strip()[6:] for ln in lines if ln.startswith("cfrd: ") and "warning" not in ln]
    return errors[-1] if errors else None


def deck_environment(jobs):
    """The environment of each deck's run: one BLAS thread; and with a deck on every core
    (`jobs` at least the cores), the stages written on the run's own thread, not behind it,
    and the next stage's system not prepared ahead (CFRD_WRITE_BEHIND=0, CFRD_AHEAD=0, each
    unless set): no core is free for a second thread."""
    env = dict(os.environ, OPENBLAS_NUM_THREADS="1")
    if jobs >= default_jobs():
        env.setdefault("CFRD_WRITE_BEHIND", "0")
        env.setdefault("CFRD_AHEAD", "0")
    return env


def run_one(run, cfrd, out, running, env):
    log = os.path.join(out, run.stem + ".log")
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
    run.wall, run.returncode = time.monotonic() - start, proc.returncode
    if run.ok:
        # Only a run that succeeded has written (renamed into place) fresh results; a
        # failed one leaves any earlier results untouched, which must not be reported.
        try:
            run.read(os.path.join(out, run.stem + ".h5"))
        except (OSError, KeyError) as exc:
            run.message = f"cannot read the results: {exc}"
    else:
        with open(log) as fh:
            run.message = error_of(fh) or f"see {log}"
    return run


class BatchRuns(list):
    """The DeckRun of each deck in deck order; `stopped` is the signal that stopped the
    batch (0: none; the decks it kept from starting are "not run")."""
    stopped = 0


def run_batch(decks, cfrd, out, jobs, progress=None):
    """Run the decks, at most `jobs` at a time; returns their BatchRuns. On Stopped (the
    handlers main installs) the decks running get the signal and are waited for; on a
    KeyboardInterrupt they are too, then it is raised again."""
    runs, running, done = BatchRuns(DeckRun(d, stem_of(d)) for d in decks), Running(), 0
    pool, futures = concurrent.futures.ThreadPoolExecutor(max_workers=jobs), []
    try:
        # Largest decks first: the last to finish is then a small one (shorter total time).
        env = deck_environment(jobs)
        futures = [pool.submit(run_one, r, cfrd, out, running, env) for r in
                   sorted(runs, key=lambda r: -(os.path.getsize(r.deck)
                                                if os.path.exists(r.deck) else 0))]
        for fut in concurrent.futures.as_completed(futures):
            done += 1
            if progress:
                progress(done, len(runs), fut.result())
    except (Stopped, KeyboardInterrupt) as exc:
        signum = exc.signum if isinstance(exc, Stopped) else signal.SIGINT
        for f in futures:
            f.cancel()
        running.stop(signum)
        pool.shutdown(wait=True)    # the decks running write their incomplete results
        if not isinstance(exc, Stopped):
            raise
        runs.stopped = int(signum)
        return runs
    pool.shutdown(wait=True)
    return runs


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


def print_summary(runs, out=sys.stdout):
    def where(value, unit):
        return "" if value is None else f"{value[0]:.4f} ({unit}{value[1]}, stage {value[2]})"
    rows = [[r.deck, r.status, "" if r.stages is None else str(r.stages), f"{r.wall:.2f}",
             where(r.max_settlement, "node "), where(r.max_opening, ""), r.message]
            for r in runs]
    print(tables.aligned(["deck", "status", "stages", "time s", "max settlement m",
                          "max opening m", "message"], rows, right={2, 3}), file=out)
    failed = sum(not r.ok for r in runs)
    print(f"{len(runs) - failed} of {len(runs)} decks ran, {failed} failed", file=out)


def summary_row(r):
    """The values of SUMMARY_COLUMNS for a DeckRun."""
    return [r.status, r.returncode, "" if r.stages is None else r.stages, f"{r.wall:.3f}",
            *(r.max_settlement or ("", "", "")), *(r.max_opening or ("", "", "")), r.message]


def write_summary_csv(runs, path):
    with open(path, "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["deck"] + SUMMARY_COLUMNS)
        w.writerows([r.deck] + summary_row(r) for r in runs)


def default_jobs():
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:
        return os.cpu_count() or 1


def main(argv=None):
    ap = argparse.ArgumentParser(
        description="Run cfrd decks in parallel, one process per deck, and summarise.")
    ap.add_argument("decks", nargs="*", metavar="DECK")
    ap.add_argument("--cfrd", default="bin/cfrd", help="the program (default bin/cfrd)")
    ap.add_argument("--out", default="batch-results",
                    help="folder for the results and logs (default batch-results)")
    ap.add_argument("--jobs", "-j", type=int, default=default_jobs(),
                    help="decks run at once (default: the cores available)")
    ap.add_argument("--quiet", action="store_true", help="no progress lines")
    try:
        args = ap.parse_args(argv)
    except SystemExit as exc:
        return 0 if exc.code == 0 else BATCH_ERROR
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
    try:
        if not error:
            os.makedirs(args.out, exist_ok=True)
    except OSError as exc:
        error = f"cannot create the folder {args.out}: {exc.strerror}"
    if error:
        print(f"batch: {error}", file=sys.stderr)
        return BATCH_ERROR

    def progress(done, total, run):
        if not args.quiet:
            print(f"[{done}/{total}] {run.deck}: {run.status}, {run.wall:.2f} s"
                  + (f": {run.message}" if run.message else ""), flush=True)
    for signum in (signal.SIGINT, signal.SIGTERM):
        signal.signal(signum, stop_on_signal)
    runs = run_batch(args.decks, args.cfrd, args.out, args.jobs, progress)
    default_signals()     # the runs are over: a signal now ends the batch at once
    print()
    print_summary(runs)
    summary = os.path.join(args.out, "batch-summary.csv")
    write_summary_csv(runs, summary)
    print(f"Results and logs in {args.out}/; this table in {summary}")
    if runs.stopped:
        print(f"batch: stopped by {signal.Signals(runs.stopped).name}: the decks that were "
              f"running keep their completed stages in {args.out}/DECK.incomplete.h5; "
              f"the others are not run", file=sys.stderr)
        return 128 + runs.stopped
    return min(sum(not r.ok for r in runs), MAX_COUNT)


if __name__ == "__main__":
    sys.exit(main())
