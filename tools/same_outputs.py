#!/usr/bin/env python3
"""Are two cfrd programs' outputs the same? Each deck is run by both (--out into two
folders); then every file of the result set is compared:

- the listing (.out, .lst) and the CSVs byte for byte, after the lines that name the run
  (run id, creation time) or report times (TOTAL ANALYSIS TIME, the solver's seconds) are
  left out of both;
- the HDF5 file: the same groups, datasets (names, shapes, types, every value's bits) and
  attributes, except the run's identity and the times (run_id, created, wall_time, t_*,
  deck_path, set_files, compiler, version);
- the XDMF file byte for byte.

    python3 tools/same_outputs.py --before OLD/cfrd --after bin/cfrd [--workdir DIR]
                                  [--flags "--compress 0"] DECK [DECK ...]

One PASS/FAIL line per deck and file; exit 1 when anything differs. Written for the fixed
costs of issue 21 (docs/performance.md (r)): a change of speed only must leave every byte of
the results as it was.
"""

import argparse
import os
import re
import subprocess
import sys

import h5py
import numpy as np

VOLATILE_ATTRS = {"run_id", "created", "wall_time", "deck_path", "set_files", "compiler",
                  "version"}
VOLATILE_LINE = re.compile(r"RUN ID|RUN OF |run_id|TOTAL ANALYSIS TIME| s$|created")


def run(cfrd, deck, out, flags):
    os.makedirs(out, exist_ok=True)
    done = subprocess.run([cfrd, "--quiet", "--out", out] + flags + [deck],
                          capture_output=True, text=True)
    if done.returncode != 0:
        raise RuntimeError(f"{cfrd} {deck}: exit {done.returncode}: {done.stderr[-300:]}")


def text_lines(path):
    with open(path, "rb") as f:
        return [ln for ln in f.read().split(b"\n")
                if not VOLATILE_LINE.search(ln.decode("latin-1"))]


def volatile_attr(name):
    return name in VOLATILE_ATTRS or name.startswith("t_")


def h5_differences(a, b):
    out = []

    def attrs(x, y, where):
        ka = {k for k in x.attrs if not volatile_attr(k)}
        kb = {k for k in y.attrs if not volatile_attr(k)}
        if ka != kb:
            out.append(f"{where}: attributes {sorted(ka ^ kb)}")
        for k in ka & kb:
            va, vb = np.asarray(x.attrs[k]), np.asarray(y.attrs[k])
            if va.dtype != vb.dtype or va.shape != vb.shape or va.tobytes() != vb.tobytes():
                out.append(f"{where}@{k}: {va!r} / {vb!r}")

    def walk(x, y, where):
        attrs(x, y, where or "/")
        if isinstance(x, h5py.Dataset):
            if not isinstance(y, h5py.Dataset):
                out.append(f"{where}: dataset / group")
            elif x.shape != y.shape or x.dtype != y.dtype:
                out.append(f"{where}: {x.shape} {x.dtype} / {y.shape} {y.dtype}")
            elif np.asarray(x[()]).tobytes() != np.asarray(y[()]).tobytes():
                out.append(f"{where}: values differ")
            return
        if set(x.keys()) != set(y.keys()):
            out.append(f"{where}/: members {sorted(set(x.keys()) ^ set(y.keys()))}")
        for k in sorted(set(x.keys()) & set(y.keys())):
            walk(x[k], y[k], f"{where}/{k}")

    with h5py.File(a, "r") as fa, h5py.File(b, "r") as fb:
        walk(fa, fb, "")
    return out


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--before", required=True)
    ap.add_argument("--after", required=True)
    ap.add_argument("--workdir", default="build/same-outputs")
    ap.add_argument("--flags", default="", help="options given to both runs")
    ap.add_argument("decks", nargs="+")
    args = ap.parse_args(argv)
    flags, failed = args.flags.split(), False
    for deck in args.decks:
        stem = os.path.splitext(os.path.basename(deck))[0]
        dirs = [os.path.join(args.workdir, side, stem) for side in ("before", "after")]
        for cfrd, out in zip((args.before, args.after), dirs):
            run(cfrd, os.path.abspath(deck), out, flags)
        names = sorted(set(os.listdir(dirs[0])) | set(os.listdir(dirs[1])))
        for name in names:
            if name.endswith(".lock"):
                continue
            a, b = (os.path.join(d, name) for d in dirs)
            if not (os.path.exists(a) and os.path.exists(b)):
                why = "written by one program only"
            elif name.endswith(".h5"):
                diff = h5_differences(a, b)
                why = "; ".join(diff[:4]) + (f" (+{len(diff) - 4})" if len(diff) > 4 else "")
            else:
                la, lb = text_lines(a), text_lines(b)
                why = "" if la == lb else next(
                    (f"line {i + 1} differs" for i, (x, y) in enumerate(zip(la, lb)) if x != y),
                    f"{len(la)} / {len(lb)} lines")
            print(f"{'FAIL' if why else 'PASS'} same_outputs {stem} {name}"
                  + (f": {why}" if why else ""))
            failed |= bool(why)
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
