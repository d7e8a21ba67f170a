#!/usr/bin/env python3
"""A run stopped by SIGTERM or SIGINT loses no completed stage (issue 18, part 4 (b)).

    python3 tools/check_stop.py --cfrd build/debug-bin/cfrd --workdir build/test-work/stop

1. A complete run of DECK (default inputs/tianshengqiao-x2.dat, 45 stages) into the work
   folder: these are the earlier results, and the reference for the stopped runs.
2. The same deck again into the same folder, sent SIGTERM once its second stage is written
   (its progress line follows the stage's flush): exit status 143; a message naming SIGTERM
   and the last completed stage; DECK.incomplete.h5 with complete = 0, the failure, at least
   one stage, and every dataset and every attribute but the timings of each stage it holds
   equal to the complete run's to 0 difference (the same computation); DECK.incomplete.xmf;
   no .part file; the earlier results byte-identical.
3. The deck and a second one, sent SIGINT in the same way: exit status 130, the same checks
   of its stages, and the second deck is named as not run and writes nothing.

Prints one PASS/FAIL line per check; exit status 1 if any failed.
"""

import argparse
import glob
import hashlib
import os
import shutil
import signal
import subprocess
import sys
import time

import h5py
import numpy as np

failures = 0


def verdict(ok, name, detail):
    global failures
    failures += not ok
    print(f"{'PASS' if ok else 'FAIL'} {name}: {detail}", flush=True)


def digests(folder, stem):
    """sha256 of the result files of `stem` in `folder` (not the incomplete ones)."""
    out = {}
    for path in sorted(glob.glob(os.path.join(folder, stem + "*"))):
        if ".incomplete" in path or path.endswith((".part", ".log")):
            continue
        with open(path, "rb") as fh:
            out[os.path.basename(path)] = hashlib.sha256(fh.read()).hexdigest()
    return out


def stop_after_stage(cmd, log, signum, stage=2, timeout=300.0):
    """Start `cmd`, send `signum` once its progress line for `stage` is in `log`; return
    (exit status, log text, whether the signal was sent before the run ended)."""
    with open(log, "w") as fh:
        proc = subprocess.Popen(cmd, stdout=fh, stderr=subprocess.STDOUT)
    marker = f"stage {stage}/"
    sent = False
    end = time.monotonic() + timeout
    while time.monotonic() < end and proc.poll() is None:
        with open(log) as fh:
            if marker in fh.read():
                proc.send_signal(signum)
                sent = True
                break
        time.sleep(0.01)
    if not sent and proc.poll() is None:
        proc.kill()
    status = proc.wait()
    with open(log) as fh:
        return status, fh.read(), sent


def is_timing(name):
    return name == "wall_time" or name.startswith("t_")


def compare_stages(incomplete, complete):
    """(stages held, list of differences) between the stages of `incomplete` and the same
    stages of `complete`: every dataset exactly, every attribute but the timings."""
    differences = []
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
                        diff = np.max(np.abs(x - y)) if x.shape == y.shape and \
                            x.dtype.kind == "f" else "shape"
                        differences.append(f"{name}/{path} differs ({diff})")
                check_attributes(f"{name}/{path}", obj.attrs, other.attrs)

            def check_attributes(where, x, y):
                for key in x:
                    if is_timing(key):
                        continue
                    if key not in y or not np.array_equal(x[key], y[key]):
                        differences.append(f"{where} attribute {key} differs")
            check_attributes(name, a.attrs, b.attrs)
            a.visititems(visit)
        return names, dict(part.attrs), differences


def check_stopped(name, status, expected, text, sent, folder, stem, reference, before,
                  signame):
    incomplete = os.path.join(folder, stem + ".incomplete.h5")
    verdict(sent and status == expected, f"{name}/exit-status",
            f"exit {status} (expected {expected}, 128 + {signame}); signal sent while "
            f"running: {sent}")
    last = [l for l in text.splitlines() if f"stopped by {signame}" in l]
    verdict(bool(last) and "last completed stage: " in last[0], f"{name}/message",
            last[0] if last else f"no 'stopped by {signame}' line: {text[-300:]!r}")
    if not os.path.exists(incomplete):
        verdict(False, f"{name}/incomplete-h5", f"no {incomplete}")
        return
    names, attrs, differences = compare_stages(incomplete, reference)
    n = int(attrs.get("stages_completed", -1))
    failure = attrs.get("failure", b"")
    failure = failure.decode() if isinstance(failure, bytes) else str(failure)
    told = f"last completed stage: {n}/" in (last[0] if last else "")
    verdict(attrs.get("complete") == 0 and n >= 1 and len(names) == n and told and
            f"stopped by {signame}" in failure and
            os.path.exists(os.path.join(folder, stem + ".incomplete.xmf")),
            f"{name}/incomplete-h5", f"complete = {attrs.get('complete')}, "
            f"stages_completed = {n} ({len(names)} stage groups, the message says "
            f"{'the same' if told else 'otherwise'}), failure '{failure}'")
    verdict(n >= 1 and not differences, f"{name}/stages-equal-complete-run",
            f"{len(names)} stages against the complete run: every dataset and attribute "
            f"(timings aside) to 0 difference" if not differences else
            "; ".join(differences[:5]))
    parts = glob.glob(os.path.join(folder, "*.part"))
    verdict(not parts, f"{name}/no-part-files", f"left: {parts}" if parts else "none left")
    after = digests(folder, stem)
    verdict(before == after and before, f"{name}/earlier-results-untouched",
            f"{len(before)} files of the complete run byte-identical" if before == after
            else f"changed: {sorted(k for k in before if before[k] != after.get(k))}")


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--cfrd", default="build/debug-bin/cfrd")
    parser.add_argument("--workdir", default="build/test-work/stop")
    parser.add_argument("--deck", default="inputs/tianshengqiao-x2.dat")
    args = parser.parse_args()
    shutil.rmtree(args.workdir, ignore_errors=True)
    os.makedirs(args.workdir)
    stem = os.path.splitext(os.path.basename(args.deck))[0]
    folder = os.path.join(args.workdir, "results")
    os.makedirs(folder)

    # 1. The complete run: earlier results and reference.
    run = subprocess.run([args.cfrd, "--quiet", "--out", folder, args.deck],
                         capture_output=True, text=True)
    reference_folder = os.path.join(args.workdir, "reference")
    os.makedirs(reference_folder)
    reference = os.path.join(reference_folder, stem + ".h5")
    if run.returncode != 0:
        verdict(False, "stop/complete-run", f"exit {run.returncode}: {run.stderr[-300:]}")
        return 1
    shutil.copy(os.path.join(folder, stem + ".h5"), reference)
    before = digests(folder, stem)

    # 2. SIGTERM (Slurm's time limit).
    status, text, sent = stop_after_stage(
        [args.cfrd, "--out", folder, args.deck], os.path.join(args.workdir, "sigterm.log"),
        signal.SIGTERM)
    check_stopped("stop/sigterm", status, 143, text, sent, folder, stem, reference, before,
                  "SIGTERM")

    # 3. SIGINT (Ctrl-C) with a second deck after it: that one is not run.
    second = "inputs/example.dat"
    status, text, sent = stop_after_stage(
        [args.cfrd, "--out", folder, args.deck, second],
        os.path.join(args.workdir, "sigint.log"), signal.SIGINT)
    check_stopped("stop/sigint", status, 130, text, sent, folder, stem, reference, before,
                  "SIGINT")
    written = glob.glob(os.path.join(folder, "example*"))
    verdict(f"not run: {second}" in text and not written, "stop/sigint/next-deck-not-run",
            f"'not run: {second}' printed: {f'not run: {second}' in text}; its files: "
            f"{written or 'none'}")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
