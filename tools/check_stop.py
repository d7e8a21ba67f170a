#!/usr/bin/env python3
"""A run stopped by SIGTERM or SIGINT loses no completed stage (issue 18, part 4 (b)).

    python3 tools/check_stop.py --cfrd build/debug-bin/cfrd --workdir build/test-work/stop

1. A complete run of DECK (default inputs/tianshengqiao-x2.dat, 45 stages) into the work
   folder: the earlier results, and the reference for the stopped runs.
2. The same deck again into the same folder, sent SIGTERM once its second stage is written:
   exit status 143; a message naming SIGTERM and the last completed stage; DECK.incomplete.h5
   with complete = 0, the failure, at least one stage, every dataset and attribute but the
   timings of each stage equal to the complete run's (0 difference); DECK.incomplete.xmf; no
   .part file; the earlier results byte-identical.
3. The deck and a second one, sent SIGINT in the same way: exit status 130, the same checks,
   and the second deck named as not run, writing nothing.
"""

import glob
import hashlib
import os
import shutil
import signal
import subprocess
import sys

import h5py
import numpy as np

from cfrdtools.checks import Checks, fresh, parser
from cfrdtools.results import text
from cfrdtools.runner import signal_when

check = Checks("stop")


def digests(folder, stem):
    """sha256 of the result files of `stem` in `folder` (not the incomplete ones)."""
    return {os.path.basename(p): hashlib.sha256(open(p, "rb").read()).hexdigest()
            for p in sorted(glob.glob(os.path.join(folder, stem + "*")))
            if ".incomplete" not in p and not p.endswith((".part", ".log"))}


def stop_after_stage(cmd, log, signum, stage=2, timeout=300.0):
    """Start `cmd`, its output into `log`, send `signum` once its progress line for `stage`
    is there; return (exit status, log text, whether the signal was sent before the run
    ended)."""
    return signal_when(cmd, log, f"stage {stage}/", signum, log, timeout)


def compare_stages(incomplete, complete):
    """(stage names, file attributes, differences) between the stages of `incomplete` and
    the same stages of `complete`: every dataset exactly, every attribute but timings and
    symbolic_ahead (how many analyses a second thread made: where the work ran, docs/
    performance.md (ak), not what it gave)."""
    differences = []

    def attributes(where, x, y):
        differences.extend(f"{where} attribute {key} differs" for key in x
                           if not (key in ("wall_time", "symbolic_ahead") or
                                   key.startswith("t_"))
                           and (key not in y or not np.array_equal(x[key], y[key])))
    with h5py.File(incomplete, "r") as part, h5py.File(complete, "r") as full:
        names = sorted(part["stages"])
        for name in names:
            a, b = part["stages"][name], full["stages"][name]

            def visit(path, obj):
                other = b.get(path)
                if other is None:
                    differences.append(f"{name}/{path} missing in the complete run")
                    return
                if isinstance(obj, h5py.Dataset):
                    x, y = obj[...], other[...]
                    if x.shape != y.shape or not np.array_equal(x, y):
                        differences.append(f"{name}/{path} differs (" + (
                            str(np.max(np.abs(x - y))) if x.shape == y.shape and
                            x.dtype.kind == "f" else "shape") + ")")
                attributes(f"{name}/{path}", obj.attrs, other.attrs)
            attributes(name, a.attrs, b.attrs)
            a.visititems(visit)
        return names, dict(part.attrs), differences


def check_stopped(name, status, expected, log, sent, folder, stem, reference, before, signame):
    check(f"{name}/exit-status", sent and status == expected, f"exit {status} (expected "
          f"{expected}, 128 + {signame}); signal sent while running: {sent}")
    last = [ln for ln in log.splitlines() if f"stopped by {signame}" in ln]
    check(f"{name}/message", last and "last completed stage: " in last[0],
          last[0] if last else f"no 'stopped by {signame}' line: {log[-300:]!r}")
    incomplete = os.path.join(folder, stem + ".incomplete.h5")
    if not os.path.exists(incomplete):
        check(f"{name}/incomplete-h5", False, f"no {incomplete}")
        return
    names, attrs, differences = compare_stages(incomplete, reference)
    n = int(attrs.get("stages_completed", -1))
    failure = text(attrs.get("failure", b""))
    told = f"last completed stage: {n}/" in (last[0] if last else "")
    check(f"{name}/incomplete-h5", attrs.get("complete") == 0 and n >= 1 and len(names) == n
          and told and f"stopped by {signame}" in failure and os.path.exists(
              os.path.join(folder, stem + ".incomplete.xmf")),
          f"complete = {attrs.get('complete')}, stages_completed = {n} ({len(names)} stage "
          f"groups, the message says {'the same' if told else 'otherwise'}), failure "
          f"'{failure}'")
    check(f"{name}/stages-equal-complete-run", n >= 1 and not differences,
          f"{len(names)} stages against the complete run: every dataset and attribute "
          f"(timings aside) to 0 difference" if not differences else "; ".join(differences[:5]))
    parts = glob.glob(os.path.join(folder, "*.part"))
    check(f"{name}/no-part-files", not parts, f"left: {parts}" if parts else "none left")
    after = digests(folder, stem)
    check(f"{name}/earlier-results-untouched", before == after and before,
          f"{len(before)} files of the complete run byte-identical" if before == after else
          f"changed: {sorted(k for k in before if before[k] != after.get(k))}")


def main():
    ap = parser(__doc__, cfrd="build/debug-bin/cfrd", workdir="build/test-work/stop")
    ap.add_argument("--deck", default="inputs/tianshengqiao-x2.dat")
    args = ap.parse_args()
    fresh(args.workdir)
    stem = os.path.splitext(os.path.basename(args.deck))[0]
    folder, refdir = (fresh(os.path.join(args.workdir, d)) for d in ("results", "reference"))
    # 1. The complete run: earlier results and reference.
    run = subprocess.run([args.cfrd, "--quiet", "--out", folder, args.deck], capture_output=True,
                         text=True)
    if run.returncode != 0:
        check("complete-run", False, f"exit {run.returncode}: {run.stderr[-300:]}")
        return 1
    reference = shutil.copy(os.path.join(folder, stem + ".h5"), os.path.join(refdir, stem + ".h5"))
    before = digests(folder, stem)
    # 2. SIGTERM (Slurm's time limit); 3. SIGINT (Ctrl-C) with a second deck after it: that
    # one is not run.
    second = "inputs/example.dat"
    for signum, decks, expected in ((signal.SIGTERM, [args.deck], 143),
                                    (signal.SIGINT, [args.deck, second], 130)):
        name = signum.name.lower()
        status, log, sent = stop_after_stage([args.cfrd, "--out", folder, *decks], os.path.join(
            args.workdir, f"{name}.log"), signum)
        check_stopped(name, status, expected, log, sent, folder, stem, reference, before,
                      signum.name)
    written = glob.glob(os.path.join(folder, "example*"))
    check("sigint/next-deck-not-run", f"not run: {second}" in log and not written,
          f"'not run: {second}' printed: {f'not run: {second}' in log}; its files: "
          f"{written or 'none'}")
    return check.status


if __name__ == "__main__":
    sys.exit(main())
