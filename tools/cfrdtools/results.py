"""Reading cfrd's HDF5 results (layout: docs/results.md)."""

import h5py


def open_results(path):
    """The results file, read-only (a context manager, like h5py.File)."""
    return h5py.File(path, "r")


def stage_names(f):
    """The stage groups in order: 'stage_0001', 'stage_0002', ..."""
    return sorted(f["stages"])


def stages(f):
    """The stage groups of an open file, in order."""
    return [f["stages"][name] for name in stage_names(f)]


def stage(f, number):
    """Stage `number` (from 1)."""
    return f[f"stages/stage_{number:04d}"]


def last_stage(f):
    return f["stages"][stage_names(f)[-1]]


def read(f, dataset, number=None):
    """A dataset of stage `number` (the last when None) as a numpy array."""
    group = last_stage(f) if number is None else stage(f, number)
    return group[dataset][...]


def series(f, dataset, index=()):
    """dataset[index] of every stage, in order (e.g. a node's displacement history)."""
    return [g[dataset][index] for g in stages(f)]


def text(value):
    """An HDF5 string attribute (bytes or str) as str."""
    return value.decode() if isinstance(value, bytes) else str(value)
