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


# --- Derived fields (issue 21): a lean results file (the default; cfrd --results) leaves
# out what cfrd derives from other datasets: stress_centroid (the mean of the Gauss-point
# stresses), principal (from it), displacement_total (the displacements zeroed by the RESETs,
# kept in each RESET stage's state/reals, plus displacement) and the z-padded copies
# displacement_xyz / displacement_total_xyz. field() gives them back bit for bit: the same
# operations in the same order as cfrd's stage driver (record) and
# src/materials/cfrd_principal.f90, hypot and atan2 from the C library cfrd calls (numpy's
# own may be vectorised differently). tools/check_results_lean.py compares them with a file
# written with --results full at every stage.

DERIVED = ("stress_centroid", "principal", "displacement_total", "displacement_xyz",
           "displacement_total_xyz")
# element kinds (src/model/cfrd_model.f90): quadrilaterals have 4 Gauss points and 4
# stress components, Goodman joints 2 and 2 (no principal stresses)
QUAD_KINDS = (1, 4)
JOINT_KINDS = (2, 3)
DEG = 57.295779513082320877        # cfrd_principal's deg, to the last digit

_LIBM = None


def _libm():
    global _LIBM
    if _LIBM is None:
        import ctypes
        import ctypes.util
        lib = ctypes.CDLL(ctypes.util.find_library("m"))
        for fn in (lib.hypot, lib.atan2):
            fn.restype = ctypes.c_double
            fn.argtypes = [ctypes.c_double, ctypes.c_double]
        _LIBM = (np.frompyfunc(lib.hypot, 2, 1), np.frompyfunc(lib.atan2, 2, 1))
    return _LIBM


def _double(group, name):
    """The stage's dataset `name` in double: its copy in state/ after --float32, else it."""
    return group[f"state/{name}"][...] if f"state/{name}" in group else group[name][...]


def centroid_stress(group, kind):
    """(nelem, 4): the mean of the element's Gauss-point stresses, summed from zero in
    Gauss-point order and divided by their number (cfrd's sum(...)/ng)."""
    sg = _double(group, "stress_gauss")
    kind = np.asarray(kind)
    unknown = set(np.unique(kind)) - set(QUAD_KINDS) - set(JOINT_KINDS)
    if unknown:
        raise ValueError(f"element kinds {sorted(unknown)} unknown to cfrdtools.results")
    c = np.zeros((sg.shape[0], 4))
    q = np.isin(kind, QUAD_KINDS)
    s = sg[q]
    c[q] = ((((0.0 + s[:, 0]) + s[:, 1]) + s[:, 2]) + s[:, 3]) / 4.0
    j = np.isin(kind, JOINT_KINDS)
    s = sg[j]
    c[j] = ((0.0 + s[:, 0]) + s[:, 1]) / 2.0
    return c


def principal_stresses(c, kind):
    """(nelem, 3): sigma1, sigma3 and the angle of sigma1 (deg) of the centroid stresses
    `c` of the quadrilaterals (zero for joints), as cfrd_principal computes them."""
    hypot, atan2 = _libm()
    p = np.zeros((c.shape[0], 3))
    q = np.isin(np.asarray(kind), QUAD_KINDS)
    sxx, syy, sxy = c[q, 0], c[q, 1], c[q, 3]
    centre = 0.5 * (sxx + syy)
    radius = hypot(0.5 * (sxx - syy), sxy).astype(np.float64)
    angle = (0.5 * atan2(2.0 * sxy, sxx - syy).astype(np.float64)) * DEG
    p[q, 0] = centre + radius
    p[q, 1] = centre - radius
    p[q, 2] = np.where(radius > 0.0, angle, 0.0)
    return p


def u_before_reset(group):
    """(nnode, 2): the displacements zeroed by the RESETs up to this stage, as cfrd's
    restart reads them (cfrd_h5_state: read_u_before_reset): from the packed state of the
    last stage up to it whose state/ints(7) says state/reals holds them (a RESET stage),
    zero before the first."""
    stages = group.parent
    number = int(group.name.rsplit("_", 1)[1])
    for k in range(number, 0, -1):
        state = stages[f"stage_{k:04d}/state"]
        ints = state["ints"][...]
        if ints[6] == 1:
            nnode = int(ints[0])
            return state["reals"][2 * nnode:4 * nnode].reshape(nnode, 2)
    return np.zeros((int(group["state/ints"][0]), 2))


def field(group, name):
    """Dataset `name` of stage group `group` as a numpy array: read when the file has it,
    else (a lean file) computed bit for bit from what it has, for the DERIVED names."""
    if name in group:
        return group[name][...]
    if name not in DERIVED:
        raise KeyError(f"{group.name}/{name}: not in the file and not derived")
    stored = group["displacement"].dtype
    if name.endswith("_xyz"):
        u = field(group, name[:-4])
        return np.concatenate([u, np.zeros((u.shape[0], 1), u.dtype)], axis=1)
    if name == "displacement_total":      # cfrd: u_before_reset + u
        return (u_before_reset(group) + _double(group, "displacement")).astype(stored)
    kind = group.file["mesh/kind"][...]
    c = centroid_stress(group, kind)
    if name == "stress_centroid":
        return c.astype(stored)
    return principal_stresses(c, kind).astype(stored)
