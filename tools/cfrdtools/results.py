"""Reading cfrd's results: the HDF5 file (layout: docs/results.md) and its CSVs."""

import csv

import h5py
import numpy as np


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


def scalar(value):
    """An attribute stored as a number or a one-element array, as a float."""
    return float(np.ravel(value)[0])


def total(attrs, key):
    """The sum of attribute `key` over several attribute sets (0 where one lacks it)."""
    return sum(scalar(a.get(key, 0)) for a in attrs)


def summary(f, solver=()):
    """What the analysis did: the number of stages, their increments, factorisations and
    Newton iterations summed, the largest max_residual, the analysis wall time and the
    solver attributes named, summed over the stages (docs/results.md)."""
    st = stages(f)
    out = {key: sum(int(g.attrs[key]) for g in st)
           for key in ("increments", "factorisations", "iterations")}
    out.update({key: total([g["solver"].attrs for g in st], key) for key in solver})
    out.update(stages=len(st), analysis=scalar(f["run"].attrs["wall_time"]),
               resid=max(float(g.attrs["max_residual"]) for g in st))
    return out


def gauges(f):
    """(names, 0-based nodes) of the gauges."""
    return [text(n).strip() for n in f["gauges/names"][...]], f["gauges/nodes"][...] - 1


def group_names(f):
    return [text(g).strip() for g in f["mesh/group_names"][...]] if "mesh/group_names" in f \
        else []


def openings(path):
    """{slab phase: (largest width, largest depth)} over the stages of DECK-openings.csv (its
    '# cfrd run_id' comment line skipped)."""
    out = {}
    with open(path, newline="") as fh:
        for row in csv.DictReader(line for line in fh if not line.startswith("#")):
            w, d = out.get(row["group"].strip(), (-np.inf, -np.inf))
            out[row["group"].strip()] = (max(w, float(row["width_m"])),
                                         max(d, float(row["depth_m"])))
    return out
