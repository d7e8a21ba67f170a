#!/usr/bin/env python3
"""cfrd's deflate filter is libdeflate's, its files stay standard (issue 21; docs/performance.md
(u), docs/results.md "Compression and precision").

cfrd registers a filter computed by libdeflate under HDF5's deflate id (src/io/cfrd_h5_deflate.c):
every chunk must still be a zlib stream that any HDF5 reader inflates with zlib. The x1
Tianshengqiao-I contact deck is run with the default (lean, shuffle + deflate 1), with
`--results full --compress 9`, and each with `--compress 0` (unfiltered: the reference), then:

  values     h5py (its own HDF5 library, whose deflate filter is zlib's) reads every dataset of
             the compressed file: the same names, types, shapes and bytes as the unfiltered
             file's;
  pipeline   every filtered dataset declares HDF5's standard pipeline, shuffle (id 2, the
             element size) then deflate (id 1, one value: the --compress level, name
             "deflate"), both optional, as HDF5's H5Pset_shuffle and H5Pset_deflate write it;
  zlib       every chunk read raw (H5Dread_chunk) is inflated by Python's zlib module alone
             (no HDF5 filter involved), unshuffled, and equals the unfiltered file's values of
             that chunk, bit for bit; no chunk is stored with a filter skipped (mask 0);
  libdeflate the chunks are not zlib's own encoding (zlib.compress at the same level of the
             same shuffled bytes): were they all equal, HDF5's zlib filter would have written
             them and libdeflate would not be in use (printed: how many differ);
  restart    `cfrd --restart` from the default file (read back through libdeflate) from
             stage 20: every stage of the continued run equal to the default run's, every
             dataset bit for bit.

    python3 tools/check_deflate.py --cfrd build/debug-bin/cfrd --workdir build/test-work/deflate
"""

import os
import subprocess
import sys
import zlib

import h5py
import numpy as np

from cfrdtools.checks import Checks, fresh, parser
from cfrdtools.runner import ROOT, run
from check_stop import compare_stages

DECK = os.path.join(ROOT, "inputs", "tianshengqiao-x1-contact.dat")
RESTART_STAGE = 20
CASES = (("lean", 1, []), ("full", 9, ["--results", "full"]))


def datasets(path):
    """{name: (dtype, shape, bytes)} of every dataset of the file, read by h5py."""
    out = {}
    with h5py.File(path, "r") as f:
        def visit(name, obj):
            if isinstance(obj, h5py.Dataset):
                values = obj[...]
                out[name] = (values.dtype, values.shape, values.tobytes())
        f.visititems(visit)
    return out


def unshuffle(raw, itemsize):
    """HDF5's shuffle filter undone: byte k of every element is stored in the k-th run."""
    if itemsize == 1 or len(raw) % itemsize:
        return raw
    return np.frombuffer(raw, np.uint8).reshape(itemsize, -1).T.tobytes()


def shuffle(raw, itemsize):
    if itemsize == 1 or len(raw) % itemsize:
        return raw
    return np.frombuffer(raw, np.uint8).reshape(-1, itemsize).T.tobytes()


def chunks(path, plain_path, level):
    """(filtered datasets, chunks, wrong pipelines, chunks differing from the unfiltered
    values, chunks with a filter skipped, chunks whose stream differs from zlib's)."""
    stats = {"datasets": 0, "chunks": 0, "pipeline": [], "values": [], "mask": [],
             "not_zlib": 0}
    with h5py.File(path, "r") as f, h5py.File(plain_path, "r") as plain:
        def visit(name, obj):
            if not isinstance(obj, h5py.Dataset) or obj.chunks is None:
                return
            plist = obj.id.get_create_plist()
            filters = [plist.get_filter(i) for i in range(plist.get_nfilters())]
            size = obj.dtype.itemsize
            if filters != [(2, 1, (size,), b"shuffle"), (1, 1, (level,), b"deflate")]:
                stats["pipeline"].append(f"{name} {filters}")
                return
            stats["datasets"] += 1
            reference = plain[name][...]
            for i in range(obj.id.get_num_chunks()):
                info = obj.id.get_chunk_info(i)
                mask, stream = obj.id.read_direct_chunk(info.chunk_offset)
                stats["chunks"] += 1
                if mask != 0 or info.filter_mask != 0:
                    stats["mask"].append(f"{name} chunk {info.chunk_offset}")
                    continue
                shuffled = zlib.decompress(stream)
                values = np.frombuffer(unshuffle(shuffled, size), obj.dtype)
                values = values.reshape(obj.chunks)
                where = tuple(slice(o, min(o + c, n)) for o, c, n in
                              zip(info.chunk_offset, obj.chunks, obj.shape))
                inside = values[tuple(slice(0, s.stop - s.start) for s in where)]
                if inside.tobytes() != reference[where].tobytes():
                    stats["values"].append(f"{name} chunk {info.chunk_offset}")
                if zlib.compress(shuffled, level) != stream:
                    stats["not_zlib"] += 1
        f.visititems(visit)
    return stats


def check_case(check, cfrd, work, label, level, options):
    paths = {}
    for mode, extra in (("plain", ["--compress", "0"]), ("deflate", ["--compress", str(level)])):
        out = os.path.join(work, label, mode)
        os.makedirs(out)
        done = run(cfrd, DECK, "--out", out, *options, *extra, check=False)
        if done.returncode != 0:
            check(f"{label}/run-{mode}", False, f"exit {done.returncode}: {done.stderr[-300:]}")
            return None
        paths[mode] = os.path.join(out, os.path.basename(DECK)[:-4] + ".h5")
    plain, packed = datasets(paths["plain"]), datasets(paths["deflate"])
    bad = sorted(n for n in plain if packed.get(n) != plain[n])
    bad += sorted(set(packed) - set(plain))
    check(f"{label}/values", not bad and plain,
          f"{len(plain) - len(bad)} of {len(plain)} datasets read by h5py (HDF5 "
          f"{h5py.version.hdf5_version}) from the --compress {level} file equal to the "
          f"--compress 0 file's: types, shapes, bytes" + (f"; differ: {bad[:4]}" if bad else ""))
    stats = chunks(paths["deflate"], paths["plain"], level)
    check(f"{label}/pipeline", not stats["pipeline"] and stats["datasets"] > 0,
          f"{stats['datasets']} filtered datasets, each shuffle (2) + deflate (1, level "
          f"{level}), optional" + (f"; other: {stats['pipeline'][:3]}" if stats["pipeline"]
                                   else ""))
    check(f"{label}/zlib", not stats["values"] and not stats["mask"] and stats["chunks"] > 0,
          f"{stats['chunks']} chunks inflated by Python's zlib {zlib.ZLIB_RUNTIME_VERSION} "
          "and unshuffled equal the unfiltered values bit for bit, none with a filter skipped"
          + (f"; differ: {stats['values'][:3]}" if stats["values"] else "")
          + (f"; filter skipped: {stats['mask'][:3]}" if stats["mask"] else ""))
    check(f"{label}/libdeflate", stats["not_zlib"] > 0,
          f"{stats['not_zlib']} of {stats['chunks']} chunks are not zlib's own encoding "
          f"at level {level} (libdeflate's)")
    size = {k: os.path.getsize(v) for k, v in paths.items()}
    print(f"info deflate/{label}/size: --compress 0 {size['plain'] / 1e6:.2f} MB, --compress "
          f"{level} {size['deflate'] / 1e6:.2f} MB ({size['deflate'] / size['plain']:.3f})")
    return paths["deflate"]


def main(argv=None):
    args = parser(__doc__, cfrd=True, workdir="build/deflate").parse_args(argv)
    check = Checks("deflate")
    work = fresh(args.workdir)
    written = {}
    for label, level, options in CASES:
        written[label] = check.guard(f"{label}/run", check_case, check, args.cfrd, work,
                                     label, level, options)
    if written.get("lean"):
        out = os.path.join(work, "restart")
        os.makedirs(out)
        done = subprocess.run([args.cfrd, "--quiet", "--restart", written["lean"],
                               "--from-stage", str(RESTART_STAGE), "--out", out],
                              capture_output=True, text=True)
        restarted = os.path.join(out, os.path.basename(written["lean"]))
        if done.returncode != 0 or not os.path.exists(restarted):
            check("restart", False, f"exit {done.returncode}: {done.stderr[-300:]}")
        else:
            names, _, differences = compare_stages(restarted, written["lean"])
            check("restart", not differences and len(names) > RESTART_STAGE,
                  f"continued from stage {RESTART_STAGE} of the libdeflate file: {len(names)} "
                  "stages equal to the uninterrupted run's, every dataset bit for bit"
                  + (f"; differ: {differences[:4]}" if differences else ""))
    return check.status


if __name__ == "__main__":
    sys.exit(main())
