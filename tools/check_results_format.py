#!/usr/bin/env python3
"""How cfrd stores its results (issue 21; docs/results.md, "Compression and precision"): the
same deck run three times, with `--compress 0` (contiguous doubles, the layout before the
filters), the default (shuffle + deflate level 1) and `--float32`, each file read with h5py:

  lossless   the default file holds the same datasets as the unfiltered one, with the same
             types and shapes, and every value equal bit for bit;
  filters    its datasets of 1024 values or more are chunked through HDF5's shuffle and
             deflate (gzip) filters, the smaller ones and the packed restart state contiguous;
  float32    the --float32 file's real datasets under /stages are IEEE single precision and
             equal to the unfiltered file's doubles rounded to single precision (numpy's
             round-to-nearest), exactly; the mesh, the deck and the integer datasets are
             those of the unfiltered file, and so are the doubles of each stage's restart
             state (the stage's fields kept in double beside them, layout 4, equal to the
             unfiltered doubles bit for bit); its XDMF file, read by meshio, gives the HDF5
             values bit for bit (tools/check_xdmf.py: the XDMF declares Precision 4);
  usage      --compress with a level outside 0-9, not a number, or none: exit 2;
  size       the files' sizes against the unfiltered one (printed, not a test: the issue's
             figures are in docs/performance.md).

    python3 tools/check_results_format.py --cfrd bin/cfrd --workdir build/format
"""

import argparse
import os
import subprocess
import sys

import h5py
import numpy as np

import check_xdmf
from cfrdtools.runner import run

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DECK = os.path.join(ROOT, "inputs", "tianshengqiao-x1-contact.dat")


def datasets(path):
    out = {}
    with h5py.File(path, "r") as f:
        def visit(name, obj):
            if isinstance(obj, h5py.Dataset):
                out[name] = (obj[...], obj.dtype, obj.chunks, obj.compression, obj.shuffle,
                             obj.size)
        f.visititems(visit)
    return out


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--cfrd", required=True)
    ap.add_argument("--workdir", default="build/format")
    a = ap.parse_args(argv)
    failed = 0

    def verdict(name, ok, text):
        nonlocal failed
        failed += 0 if ok else 1
        print(f"{'PASS' if ok else 'FAIL'} format/{name}: {text}")

    files = {}
    for label, options in (("plain", ["--compress", "0"]), ("default", []),
                           ("float32", ["--float32"])):
        out = os.path.join(a.workdir, label)
        os.makedirs(out, exist_ok=True)
        done = run(a.cfrd, DECK, "--out", out, *options, check=False)
        if done.returncode != 0:
            verdict(f"run-{label}", False, f"exit {done.returncode}: {done.stderr[:300]}")
            return 1
        files[label] = os.path.join(out, os.path.basename(DECK)[:-4] + ".h5")
    plain, default, single = (datasets(files[k]) for k in ("plain", "default", "float32"))

    same = [n for n in plain if n in default and plain[n][1] == default[n][1]
            and np.array_equal(plain[n][0], default[n][0], equal_nan=False)
            and plain[n][0].tobytes() == default[n][0].tobytes()]
    verdict("lossless", set(plain) == set(default) and len(same) == len(plain),
            f"{len(same)} of {len(plain)} datasets of the default file (shuffle + deflate 1) "
            "equal to the unfiltered file's, types, shapes and bytes")

    # the packed restart state (stages/*/state/reals, ints) is stored unfiltered whatever its
    # size (layout 4: deflate cost a run 4 %, docs/performance.md (j))
    packed = ("/state/reals", "/state/ints")
    big = [n for n, d in default.items() if d[5] >= 1024 and not n.endswith(packed)]
    filtered = [n for n in big if default[n][3] == "gzip" and default[n][4] and default[n][2]]
    small_plain = all(d[2] is None for n, d in default.items() if d[5] < 1024 or
                      n.endswith(packed))
    unfiltered = all(d[2] is None and d[3] is None for d in plain.values())
    verdict("filters", len(filtered) == len(big) > 0 and small_plain and unfiltered,
            f"{len(filtered)} of {len(big)} datasets of 1024 values or more chunked through "
            "shuffle and gzip, the smaller ones contiguous; --compress 0: none filtered")

    bad = []
    count = 0
    for n, (values, dtype, *_rest) in plain.items():
        s_values, s_dtype = single[n][0], single[n][1]
        if n.startswith("stages/") and dtype.kind == "f" and "/state/" not in n:
            count += 1
            if s_dtype != np.float32 or not np.array_equal(
                    s_values, values.astype(np.float32)):
                bad.append(n)
        elif s_dtype != dtype or s_values.tobytes() != values.tobytes():
            bad.append(n)
    # the restart state keeps the stage's fields in double beside them (layout 4)
    extra = sorted(set(single) - set(plain))
    for n in extra:
        stage, _, field = n.partition("/state/")
        twin = plain.get(f"{stage}/{field}")
        if twin is None or single[n][1] != np.float64 or \
                single[n][0].tobytes() != twin[0].tobytes():
            bad.append(n)
    verdict("float32", not bad and count > 0 and set(plain) <= set(single),
            f"{count} real datasets of the stages in single precision, each equal to the "
            f"double values rounded to single (exact); every other dataset identical; the "
            f"{len(extra)} double copies of the restart state equal the doubles"
            + (f"; differ: {', '.join(bad[:5])}" if bad else ""))
    xmf = files["float32"][:-3] + ".xmf"
    ok = check_xdmf.check(xmf, DECK)
    items = [line for line in open(xmf) if "<DataItem" in line and 'DataType="Float"' in line]
    declared = all(('Precision="8"' in line) == ("/mesh/" in line) for line in items)
    verdict("float32-xdmf", ok and declared and len(items) > 0,
            f"the --float32 run's XDMF file read by meshio gives the HDF5 datasets bit for "
            f"bit; its {len(items)} float items declare Precision 4 for the stages' fields "
            "and 8 for the mesh coordinates")

    for args in (["--compress", "12"], ["--compress", "x"], ["--compress"]):
        done = subprocess.run([a.cfrd, "--out", a.workdir, *args], capture_output=True,
                              text=True)
        verdict("usage " + " ".join(args), done.returncode == 2 and
                "--compress needs a level from 0 (none) to 9" in done.stderr,
                f"exit {done.returncode} (2), {done.stderr.strip().splitlines()[0][:80]!r}")
    size = {k: os.path.getsize(v) for k, v in files.items()}
    print(f"info format/size: unfiltered {size['plain'] / 1e6:.1f} MB, default "
          f"{size['default'] / 1e6:.1f} MB ({size['default'] / size['plain']:.2f}), "
          f"--float32 {size['float32'] / 1e6:.1f} MB ({size['float32'] / size['plain']:.2f})")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
