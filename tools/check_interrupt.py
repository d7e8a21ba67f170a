#!/usr/bin/env python3
"""A run stopped by SIGTERM (Slurm at a job's time limit) or SIGINT (Ctrl-C) loses nothing
(issue 18): it stops at the end of the stage it is in, with exit status 143 or 130, keeps the
completed stages as DECK.incomplete.h5 (each equal, bit for bit, to the same stage of an
uninterrupted run), leaves no temporary (.part) file and leaves earlier results untouched.

  python3 tools/check_interrupt.py --cfrd build/debug-bin/cfrd --workdir DIR   (PASS/FAIL)
"""
import argparse
import os
import shutil
import signal
import subprocess
import sys

import h5py
import numpy as np

DECK = "inputs/tianshengqiao-x1.dat"
FIELDS = ("displacement", "displacement_total", "stress_gauss", "strain_gauss", "reaction")


def interrupted_run(cfrd, folder, signum, after):
    """Run DECK in folder, send signum once `after` stages have been reported."""
    os.makedirs(folder, exist_ok=True)
    deck = os.path.join(folder, "dam.dat")
    shutil.copy(DECK, deck)
    with open(os.path.join(folder, "dam.out"), "w") as f:
        f.write("an earlier listing\n")
    proc = subprocess.Popen([cfrd, deck], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                            text=True)
    seen = 0
    for line in proc.stdout:
        if line.strip().startswith("stage "):
            seen += 1
            if seen == after:
                proc.send_signal(signum)
                break
    proc.stdout.read()
    err = proc.stderr.read()
    return proc.wait(), err


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--cfrd", required=True)
    ap.add_argument("--workdir", default="build/interrupt")
    a = ap.parse_args(argv)
    shutil.rmtree(a.workdir, ignore_errors=True)
    full = os.path.join(a.workdir, "full")
    os.makedirs(full)
    shutil.copy(DECK, os.path.join(full, "dam.dat"))
    subprocess.run([a.cfrd, "--quiet", os.path.join(full, "dam.dat")], check=True)
    ok_all = True
    for signum, status_wanted in ((signal.SIGTERM, 143), (signal.SIGINT, 130)):
        name = signal.Signals(signum).name
        folder = os.path.join(a.workdir, name.lower())
        status, err = interrupted_run(a.cfrd, folder, signum, after=3)
        kept = os.path.join(folder, "dam.incomplete.h5")
        parts = [f for f in os.listdir(folder) if f.endswith(".part")]
        earlier = open(os.path.join(folder, "dam.out")).read() == "an earlier listing\n"
        same, stages = False, 0
        if os.path.exists(kept):
            with h5py.File(kept, "r") as h, h5py.File(os.path.join(full, "dam.h5"), "r") as g:
                names = sorted(h["stages"])
                stages = len(names)
                same = stages >= 3 and h.attrs["complete"] == 0 and all(
                    np.array_equal(h["stages"][k][d][...], g["stages"][k][d][...])
                    for k in names for d in FIELDS)
        ok = status == status_wanted and same and not parts and earlier
        ok_all &= ok
        print(f"{'PASS' if ok else 'FAIL'} interrupt/{name}: exit {status} (expected"
              f" {status_wanted}); {stages} completed stages in dam.incomplete.h5, bit-identical"
              f" to the uninterrupted run's: {same}; .part files left: {parts or 'none'};"
              f" earlier listing untouched: {earlier}; message: {err.strip()[-80:]}")
    return 0 if ok_all else 1


if __name__ == "__main__":
    sys.exit(main())
