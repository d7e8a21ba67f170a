#!/usr/bin/env python3
"""How cfrd stores its results (issue 21; docs/results.md, "Compression and precision" and
"XDMF"), read back by programs other than cfrd.

The same deck run three times, with `--compress 0` (contiguous doubles, the layout before the
filters), the default (shuffle + deflate level 1) and `--float32`, each file read with h5py,
all three with `--results full` (every dataset; a lean file, the default, against a full one:
tools/check_results_lean.py):

  lossless   the default file holds the same datasets as the unfiltered one, with the same
             types and shapes, and every value equal bit for bit;
  filters    its datasets of 1024 values or more are chunked through HDF5's shuffle and
             deflate (gzip) filters, the smaller ones and the packed restart state contiguous;
  btree-k    the default file's superblock is of version 1 (HDF5 1.8's format: every HDF5
             program reads it, and a killed run's file opens without h5clear) with the
             indexed-storage internal node K of 2, read off the file's bytes (the HDF5 File
             Format Specification 3.0, section II.A): each chunked dataset's first B-tree
             node takes at most 256 bytes, where HDF5's default K of 32 gives 2-3 kB
             (docs/performance.md (am));
  float32    the --float32 file's real datasets under /stages are IEEE single precision and
             equal to the unfiltered file's doubles rounded to single precision (numpy's
             round-to-nearest), exactly; the mesh, the deck and the integer datasets are
             those of the unfiltered file, and so are the doubles of each stage's restart
             state (the stage's fields kept in double beside them, layout 4, equal to the
             unfiltered doubles bit for bit); its XDMF file, read by meshio, gives the HDF5
             values bit for bit (the --xdmf checks below; the XDMF declares Precision 4);
  usage      --compress with a level outside 0-9, not a number, or none: exit 2;
  size       the files' sizes against the unfiltered one (printed, not a test: the issue's
             figures are in docs/performance.md).

--xdmf: cfrd's DECK.xmf (of a run with --results full; meshio reads no XDMF Function, which
a lean file's XDMF uses: tools/check_results_lean.py) read with an independent XDMF reader (meshio's TimeSeriesReader, the
reader ParaView-style time series are checked with) against the HDF5 datasets, exactly:

  steps   one time step per stage: as many as the deck's STAGES cards (counted here from the
          deck text), at times 1, 2, ..., N;
  mesh    the points are /mesh/coordinates, one block of quads whose connectivity is
          /mesh/connectivity - 1 (XDMF numbers from 0), as many cells as the mesh;
  fields  at every step, the node vectors displacement and displacement_total are the stage's
          (nnode, 2) datasets padded with z = 0, and the cell fields stress_centroid,
          principal, stress_level, active, material equal theirs.

    python3 tools/check_results_format.py --cfrd bin/cfrd --workdir build/format
    python3 tools/check_results_format.py --xdmf --cfrd CFRD --workdir DIR   (what make test
                                                   runs: the Goodman-joint Tianshengqiao-I deck)
    python3 tools/check_results_format.py --xdmf RESULTS.xmf DECK            (an existing run)
"""

import os
import pathlib
import struct
import subprocess
import sys

import h5py
import meshio
import numpy as np

from cfrdtools.checks import Checks, parser
from cfrdtools.decks import groups
from cfrdtools.runner import ROOT, run

DECK = os.path.join(ROOT, "inputs", "tianshengqiao-x1-contact.dat")
XDMF_DECK = "inputs/tianshengqiao-x1-joint.dat"


def check_xdmf(check, xmf, deck):
    """The XDMF file against its HDF5 file and the deck (--xdmf above); True when all agree."""
    cards = dict(groups(pathlib.Path(deck).read_text())).get("STAGES", [])
    # (1 without STAGES: the LOADS stage)
    nstage = sum(ln[:10].strip().upper() in ("FILL", "LOAD", "RESET", "WATER")
                 for ln in cards) or 1
    with h5py.File(pathlib.Path(xmf).with_suffix(".h5"), "r") as h5, \
            meshio.xdmf.TimeSeriesReader(xmf) as reader:
        points, cells = reader.read_points_cells()
        xy, conn = h5["mesh/coordinates"][...], h5["mesh/connectivity"][...]
        ok = check("steps", reader.num_steps == nstage == len(h5["stages"]),
                   f"{reader.num_steps} time steps read, {nstage} stage cards in {deck}, "
                   f"{len(h5['stages'])} stage groups in the HDF5 file (equal)")
        quads = [c for c in cells if c.type == "quad"]
        ok &= check("mesh", len(cells) == 1 and len(quads) == 1 and np.array_equal(
            quads[0].data, conn - 1) and np.array_equal(points, xy), f"{points.shape[0]} "
            f"points, {quads[0].data.shape[0] if quads else 0} quads read; HDF5 mesh "
            f"{xy.shape[0]} nodes, {conn.shape[0]} elements (connectivity - 1, exact)")
        bad, times = [], []
        node_fields = ("displacement", "displacement_total")
        cell_fields = ("stress_centroid", "principal", "stress_level", "active")
        for k in range(reader.num_steps):
            t, point_data, cell_data = reader.read_data(k)
            times.append(t)
            g = h5["stages"][f"stage_{k + 1:04d}"]
            bad += [f"{name} at step {k}" for name in node_fields if not (
                point_data[name].shape == (xy.shape[0], 3) and np.array_equal(
                    point_data[name][:, :2], g[name][...]) and not point_data[name][:, 2].any())]
            bad += [f"{name} at step {k}" for name in cell_fields
                    if not np.array_equal(cell_data[name][0], g[name][...])]
            if not np.array_equal(cell_data["material"][0], h5["mesh/material"][...]):
                bad.append(f"material at step {k}")
        ok &= check("times", times == [float(s) for s in range(1, nstage + 1)],
                    f"times {times[0]:g} .. {times[-1]:g} (the stage numbers)")
        fields = ", ".join(node_fields + cell_fields)
        return ok & check("fields", not bad, f"{reader.num_steps} steps x ({fields}, material) "
                          f"equal to the HDF5 datasets bit for bit"
                          + (f"; differ: {', '.join(bad[:5])}" if bad else ""))


def datasets(path):
    out = {}
    with h5py.File(path, "r") as f:
        def visit(name, obj):
            if isinstance(obj, h5py.Dataset):
                out[name] = (obj[...], obj.dtype, obj.chunks, obj.compression, obj.shuffle,
                             obj.size)
        f.visititems(visit)
    return out


def superblock(path):
    """(version, indexed-storage internal node K) of an HDF5 file's superblock of version 1
    (the HDF5 File Format Specification 3.0, section II.A: the version at byte 8, the K
    after the signature, four version bytes, the sizes, the group Ks and the consistency
    flags, at byte 24); K None for another version."""
    with open(path, "rb") as fh:
        head = fh.read(26)
    version = head[8]
    return version, (struct.unpack_from("<H", head, 24)[0] if version == 1 else None)


def check_format(check, cfrd, workdir):
    files = {}
    for label, options in (("plain", ["--compress", "0"]), ("default", []),
                           ("float32", ["--float32"])):
        out = os.path.join(workdir, label)
        os.makedirs(out, exist_ok=True)
        done = run(cfrd, DECK, "--out", out, "--results", "full", *options, check=False)
        if done.returncode != 0:
            return check(f"run-{label}", False, f"exit {done.returncode}: {done.stderr[:300]}")
        files[label] = os.path.join(out, os.path.basename(DECK)[:-4] + ".h5")
    plain, default, single = (datasets(files[k]) for k in ("plain", "default", "float32"))

    same = [n for n in plain if n in default and plain[n][1] == default[n][1]
            and np.array_equal(plain[n][0], default[n][0], equal_nan=False)
            and plain[n][0].tobytes() == default[n][0].tobytes()]
    check("lossless", set(plain) == set(default) and len(same) == len(plain),
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
    check("filters", len(filtered) == len(big) > 0 and small_plain and unfiltered,
          f"{len(filtered)} of {len(big)} datasets of 1024 values or more chunked through "
          "shuffle and gzip, the smaller ones contiguous; --compress 0: none filtered")

    version, istore_k = superblock(files["default"])
    node = 24 + (2 * istore_k + 1) * (8 + 8 * 4) + 2 * istore_k * 8 if istore_k else 0
    check("btree-k", version == 1 and istore_k == 2,
          f"superblock version {version} (1: the format of HDF5 1.8, no consistency flags "
          f"that would lock a killed run's file), indexed-storage K {istore_k} (2): a rank-3 "
          f"chunked dataset's B-tree node {node} bytes, 3136 at HDF5's default K of 32")

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
    check("float32", not bad and count > 0 and set(plain) <= set(single),
          f"{count} real datasets of the stages in single precision, each equal to the "
          f"double values rounded to single (exact); every other dataset identical; the "
          f"{len(extra)} double copies of the restart state equal the doubles"
          + (f"; differ: {', '.join(bad[:5])}" if bad else ""))
    xmf = files["float32"][:-3] + ".xmf"
    ok = check_xdmf(Checks("format/float32-xdmf", quiet=True), xmf, DECK)
    items = [line for line in open(xmf) if "<DataItem" in line and 'DataType="Float"' in line]
    declared = all(('Precision="8"' in line) == ("/mesh/" in line) for line in items)
    check("float32-xdmf", ok and declared and len(items) > 0,
          f"the --float32 run's XDMF file read by meshio gives the HDF5 datasets bit for "
          f"bit; its {len(items)} float items declare Precision 4 for the stages' fields "
          "and 8 for the mesh coordinates")

    for args in (["--compress", "12"], ["--compress", "x"], ["--compress"]):
        done = subprocess.run([cfrd, "--out", workdir, *args], capture_output=True, text=True)
        check("usage " + " ".join(args), done.returncode == 2 and
              "--compress needs a level from 0 (none) to 9" in done.stderr,
              f"exit {done.returncode} (2), {done.stderr.strip().splitlines()[0][:80]!r}")
    size = {k: os.path.getsize(v) for k, v in files.items()}
    print(f"info format/size: unfiltered {size['plain'] / 1e6:.1f} MB, default "
          f"{size['default'] / 1e6:.1f} MB ({size['default'] / size['plain']:.2f}), "
          f"--float32 {size['float32'] / 1e6:.1f} MB ({size['float32'] / size['plain']:.2f})")


def main(argv=None):
    ap = parser(__doc__, cfrd="", workdir="build/format")
    ap.add_argument("--xdmf", action="store_true", help="the XDMF checks alone")
    ap.add_argument("xmf", nargs="?")
    ap.add_argument("deck", nargs="?")
    args = ap.parse_args(argv)
    if not args.xdmf:
        if not args.cfrd:
            ap.error("--cfrd is required")
        check = Checks("format")
        check_format(check, args.cfrd, args.workdir)
        return check.status
    check = Checks("xdmf")
    if args.xmf and args.deck:
        xmf, deck = args.xmf, args.deck
    elif args.cfrd:
        os.makedirs(args.workdir, exist_ok=True)
        done = run(args.cfrd, XDMF_DECK, "--out", args.workdir, "--results", "full",
                   check=False)
        if done.returncode != 0:
            check("run", False, f"{args.cfrd} {XDMF_DECK}: exit {done.returncode}: "
                  f"{done.stderr[-300:]}")
            return 1
        xmf, deck = os.path.join(args.workdir, pathlib.Path(XDMF_DECK).stem + ".xmf"), XDMF_DECK
    else:
        ap.error("--xdmf: give RESULTS.xmf DECK, or --cfrd CFRD")
    check_xdmf(check, xmf, deck)
    return check.status


if __name__ == "__main__":
    sys.exit(main())
