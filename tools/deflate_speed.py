#!/usr/bin/env python3
"""The deflate filter's own cost, zlib against libdeflate, on a cfrd results file (issue 21;
docs/performance.md (u)): every filtered chunk of the file is read raw, inflated (Python's
zlib) back to the shuffled bytes HDF5 hands the deflate filter, and compressed again at the
same level by zlib (Python's zlib module) and by libdeflate (libdeflate.so.0 through
ctypes), `--rounds` times; printed: the bytes in and out and the CPU time (process time,
the least of the rounds) of each. A measurement, not a test (no timed tests: the figures
belong in docs/performance.md).

    python3 tools/deflate_speed.py RESULTS.h5 [--level 1] [--rounds 3]
"""

import argparse
import ctypes
import sys
import time
import zlib

import h5py


def shuffled_chunks(path):
    """The input of the deflate filter for every filtered chunk of the file."""
    out = []
    with h5py.File(path, "r") as f:
        def visit(_name, obj):
            if isinstance(obj, h5py.Dataset) and obj.chunks is not None and obj.compression:
                for i in range(obj.id.get_num_chunks()):
                    info = obj.id.get_chunk_info(i)
                    mask, raw = obj.id.read_direct_chunk(info.chunk_offset)
                    if mask == 0:
                        out.append(zlib.decompress(raw))
        f.visititems(visit)
    return out


def libdeflate_compressor(level):
    lib = ctypes.CDLL("libdeflate.so.0")
    lib.libdeflate_alloc_compressor.restype = ctypes.c_void_p
    lib.libdeflate_zlib_compress_bound.restype = ctypes.c_size_t
    lib.libdeflate_zlib_compress_bound.argtypes = [ctypes.c_void_p, ctypes.c_size_t]
    lib.libdeflate_zlib_compress.restype = ctypes.c_size_t
    lib.libdeflate_zlib_compress.argtypes = [ctypes.c_void_p, ctypes.c_char_p,
                                             ctypes.c_size_t, ctypes.c_void_p, ctypes.c_size_t]
    handle = lib.libdeflate_alloc_compressor(level)

    def compress(data):
        bound = lib.libdeflate_zlib_compress_bound(handle, len(data))
        out = ctypes.create_string_buffer(bound)
        n = lib.libdeflate_zlib_compress(handle, data, len(data), out, bound)
        if n == 0:
            raise RuntimeError("libdeflate_zlib_compress failed")
        return n
    return compress


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("results")
    ap.add_argument("--level", type=int, default=1)
    ap.add_argument("--rounds", type=int, default=3)
    args = ap.parse_args(argv)
    chunks = shuffled_chunks(args.results)
    size_in = sum(map(len, chunks))
    if not chunks:
        print(f"{args.results}: no chunk through the deflate filter (--compress 0?)")
        return 1
    coders = {"zlib " + zlib.ZLIB_RUNTIME_VERSION: lambda c: len(zlib.compress(c, args.level)),
              "libdeflate": libdeflate_compressor(args.level)}
    print(f"{args.results}: {len(chunks)} chunks, {size_in / 1e6:.1f} MB through the filter, "
          f"level {args.level}")
    for name, coder in coders.items():
        best, size_out = float("inf"), 0
        for _ in range(args.rounds):
            t0 = time.process_time()
            size_out = sum(coder(c) for c in chunks)
            best = min(best, time.process_time() - t0)
        print(f"  {name:12s} {size_out / 1e6:8.2f} MB  {best:7.3f} s CPU  "
              f"{size_in / 1e6 / best:6.0f} MB/s")
    return 0


if __name__ == "__main__":
    sys.exit(main())
