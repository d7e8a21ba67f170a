#!/usr/bin/env python3
"""A lean results file (cfrd's default) against a full one (--results full), issue 21.

A lean file leaves out what cfrd derives from other datasets (stress_centroid, the mean of
the Gauss-point stresses; principal, from it; displacement_total, displacement plus the
displacements zeroed by the RESETs) and what it stores twice (displacement_xyz and
displacement_total_xyz, the z-padded copies for XDMF), and stores once what repeats (a hard
link: the slab's, the interfaces' and the contact surface's geometry while it stays the same,
the fields of a RESET stage). The same deck is run with `--results full` and with the
default, and the two files read with h5py:

  values     every dataset of the full file at every stage is in the lean file with the
             same type, shape and bytes, or is one of the derived ones and
             tools/cfrdtools/results.py's field() computes it from the lean file to the same
             bytes (the reference is the full file, written by cfrd's own arithmetic);
             nothing else is in the lean file but each RESET stage's u_before_reset, equal
             to its part of state/reals, and mesh/gauss_points (4 for a quadrilateral, 2
             for a joint, repeated over the 4 components); the root and stage
             attributes agree (but the run's identity, times and the `results`
             attribute itself);
  links      displacement_total left out at every stage; the slab geometry (x, y, s) one
             object over the stages where it does not change, and each field of ONCE the
             last stage's object exactly where its values are the last stage's bits (the
             Gauss-point fields at a RESET stage);
  xdmf       the lean DECK.xmf, evaluated here (HDF5 items, HyperSlab, the Functions
             JOIN($0, $1, 0 * $0), of columns or of sums $0 + $1 of columns, and
             (0 + $0 + $1 + $2 + $3) / $4 of the Gauss points of stress_gauss over
             mesh/gauss_points), gives at every step the node vectors and the cell stresses
             (stress_centroid) the full DECK.xmf gives through meshio (an independent XDMF
             reader), bit for bit, and every other attribute of it but principal (full
             only); it names only datasets that exist in the lean file; where VTK is
             installed, its vtkXdmfReader (the XDMF 2 reader of ParaView's "Xdmf Reader")
             reads the same vectors and cell stresses;
  restart    a lean file continued from a middle stage with --results full writes the full
             file's stages (its stored stages are rewritten, not copied: they lack the
             derived datasets), every dataset bit for bit;
  usage      --results with a word other than lean or full, or none: exit 2;
  size       the lean file against the full one (printed, and the lean one must be smaller).

The decks: the x1 contact deck (RESET stages, slab, contact; also with --float32, whose
derived fields are computed from the double copies of the restart state and rounded) and
the x1 Goodman-joint deck (interface stations).

    python3 tools/check_results_lean.py --cfrd bin/cfrd --workdir build/lean
"""

import os
import re
import subprocess
import sys
import xml.etree.ElementTree as ET

import h5py
import meshio
import numpy as np

from cfrdtools import results
from cfrdtools.checks import Checks, fresh, parser
from cfrdtools.runner import ROOT, run

DECKS = (("contact", "inputs/tianshengqiao-x1-contact.dat", ()),
         ("contact-float32", "inputs/tianshengqiao-x1-contact.dat", ("--float32",)),
         ("joint", "inputs/tianshengqiao-x1-joint.dat", ()))
# root attributes that differ between two runs of one deck
RUN_ATTRS = {"run_id", "created", "deck_path", "set_files", "results"}
# what a lean file links to the last stage's dataset when the values are the same bits
ONCE = ("stress_level", "displacement", "reaction", "stress_gauss", "strain_gauss",
        "history_gauss", "creep_gauss", "wetting_gauss") + tuple(
    f"slab/{k}" for k in ("x", "y", "s", "section_s", "section_x", "section_y", "thickness",
                          "tensile_strength")) + ("interface/x", "interface/y", "interface/s",
                                                  "contact/x", "contact/y", "contact/s")
STAGE_TIMES = {"wall_time"}


def walk(f):
    """{path: dataset} of every dataset of an open file, under each of its names (a hard-
    linked dataset under both)."""
    out = {}

    def visit(name, link):
        if isinstance(link, h5py.HardLink) and isinstance(f[name], h5py.Dataset):
            out[name] = f[name]
    f.visititems_links(visit)
    return out


def same_bytes(a, b):
    return a.dtype == b.dtype and a.shape == b.shape and a.tobytes() == b.tobytes()


def attrs_differ(a, b, skip):
    keys = (set(a) | set(b)) - skip
    return sorted(k for k in keys if k not in a or k not in b or
                  np.asarray(a[k]).tobytes() != np.asarray(b[k]).tobytes())


def compare_files(full_path, lean_path):
    """(datasets compared, derived computed, differences, (stages where displacement_total
    is linked, stages before the first RESET, slab geometry objects, link mismatches,
    datasets linked to the last stage's))."""
    bad, n_same, n_derived = [], 0, 0
    with h5py.File(full_path, "r") as full, h5py.File(lean_path, "r") as lean:
        fd, ld = walk(full), walk(lean)
        for path, dset in fd.items():
            if path in ld:
                n_same += 1
                if not same_bytes(dset[...], ld[path][...]):
                    bad.append(path)
                continue
            stage, _, name = path.rpartition("/")
            if name not in results.DERIVED or not stage.startswith("stages/"):
                bad.append(path + " (missing)")
                continue
            n_derived += 1
            if not same_bytes(dset[...], results.field(lean[stage], name)):
                bad.append(path + " (derived)")
        for p in ld:
            if p in fd:
                continue
            stage, _, name = p.rpartition("/")
            # the Gauss-point counts, the lean XDMF file's divisor of stress_centroid: 4
            # for quadrilaterals, 2 for Goodman joints (results.QUAD_KINDS, JOINT_KINDS)
            if p == "mesh/gauss_points":
                kind = lean["mesh/kind"][...]
                ng = np.where(np.isin(kind, results.QUAD_KINDS), 4,
                              np.where(np.isin(kind, results.JOINT_KINDS), 2, 0))
                if not same_bytes(ld[p][...].astype(np.int64),
                                  np.repeat(ng[:, None], 4, axis=1).astype(np.int64)):
                    bad.append(p + " (counts)")
                continue
            # a RESET stage's u_before_reset: its state/reals part, for the XDMF file
            if name != "u_before_reset" or not same_bytes(
                    ld[p][...], results.u_before_reset(lean[stage]).astype(ld[p].dtype)):
                bad.append(p + " (only in lean)")
        bad += ["/ attribute " + k for k in attrs_differ(full.attrs, lean.attrs, RUN_ATTRS)]
        if lean.attrs.get("results") not in ("lean", b"lean") or \
                full.attrs.get("results") not in ("full", b"full"):
            bad.append("root attribute results")
        linked, before_reset, reset_seen, geometry, link_bad = 0, 0, False, set(), []
        previous, repeats = None, 0
        for g in results.stages(lean):
            bad += [f"{g.name} attribute {k}"
                    for k in attrs_differ(full[g.name].attrs, g.attrs, STAGE_TIMES)]
            reset_seen |= results.text(g.attrs["kind"]) == "RESET"
            linked += "displacement_total" not in g
            before_reset += not reset_seen
            if "slab" in g:
                geometry.add(tuple(h5py.h5o.get_info(g["slab"][k].id).addr
                                   for k in ("x", "y", "s")))
            for name in ONCE:
                if name not in g or previous is None or name not in previous:
                    continue
                equal = same_bytes(g[name][...], previous[name][...])
                is_link = g[name] == previous[name]
                repeats += is_link
                if equal != is_link:
                    link_bad.append(f"{g.name}/{name}: linked {is_link}, equal {equal}")
            previous = g
    return n_same, n_derived, bad, (linked, before_reset, len(geometry), link_bad, repeats)


def expression(expr, args):
    """An XDMF Function term as cfrd writes them ($a, numbers, +, *, / and parentheses,
    left to right, * and / before +, as XDMF 2's XdmfExpr.y parses them), evaluated
    element by element in double; a number with an array is applied to every value."""
    tokens = re.findall(r"\$\d+|\d+\.?\d*(?:[eE][-+]?\d+)?|[-+*/()]", expr)
    if "".join(tokens) != expr:
        raise ValueError(f"XDMF Function {expr!r}: not what cfrd writes")
    pos = 0

    def atom():
        nonlocal pos
        token = tokens[pos]
        pos += 1
        if token == "(":
            value = total()
            pos += 1                    # ")"
            return value
        if token.startswith("$"):
            return args[int(token[1:])].ravel()
        return float(token)

    def product():
        nonlocal pos
        value = atom()
        while pos < len(tokens) and tokens[pos] in "*/":
            op, pos = tokens[pos], pos + 1
            right = atom()
            value = value * right if op == "*" else value / right
        return value

    def total():
        nonlocal pos
        value = product()
        while pos < len(tokens) and tokens[pos] == "+":
            pos += 1
            value = value + product()
        return value

    return total()


def evaluate(item, folder):
    """The values of an XDMF DataItem: HDF (file:path), XML text, HyperSlab, Function
    (JOIN of $k and c * $k; $k + $l, what cfrd writes)."""
    kind = item.get("ItemType", "Uniform")
    dims = tuple(int(d) for d in item.get("Dimensions").split())
    if kind == "HyperSlab":
        sel, data = (evaluate(c, folder) for c in item.findall("DataItem"))
        start, stride, count = (sel[k].astype(int) for k in range(3))
        index = tuple(slice(a, a + s * c, s) for a, s, c in zip(start, stride, count))
        return data[index].reshape(dims)
    if kind == "Function":
        args = [evaluate(c, folder) for c in item.findall("DataItem")]
        expr = item.get("Function").replace(" ", "")
        if expr.startswith("JOIN(") and expr.endswith(")"):
            parts = [expression(term, args) for term in expr[5:-1].split(",")]
            return np.stack(parts, axis=1).reshape(dims)
        return expression(expr, args).reshape(dims)
    if item.get("Format", "XML") == "XML":
        return np.array(item.text.split(), float).reshape(dims)
    name, _, path = item.text.strip().partition(":")
    with h5py.File(os.path.join(folder, name), "r") as f:
        values = f[path][...]
    return values.reshape(dims)


def check_xdmf(check, label, full_xmf, lean_xmf, lean_h5):
    folder = os.path.dirname(lean_xmf)
    grids = ET.parse(lean_xmf).getroot().findall("./Domain/Grid/Grid")
    bad, missing, compared = [], set(), 0
    with h5py.File(lean_h5, "r") as h5, meshio.xdmf.TimeSeriesReader(full_xmf) as reader:
        reader.read_points_cells()
        named = [it.text.strip().partition(":")[2] for it in
                 ET.parse(lean_xmf).getroot().iter("DataItem") if it.get("Format") == "HDF"]
        missing = {p for p in named if p not in h5}
        for k, grid in enumerate(grids):
            _, point_data, cell_data = reader.read_data(k)
            for att in grid.findall("Attribute"):
                name = att.get("Name")
                value = evaluate(att.find("DataItem"), folder)
                if att.get("AttributeType") == "Vector":
                    value[:, 2] += 0.0      # z: 0 * $0 is -0.0 where $0 < 0, meshio's +0.0
                ref = point_data[name] if att.get("Center") == "Node" else cell_data[name][0]
                compared += 1
                if not same_bytes(value.astype(ref.dtype), ref) or value.dtype != ref.dtype:
                    bad.append(f"{name} at step {k}")
        lean_names = {a.get("Name") for a in grids[0].findall("Attribute")}
        only_full = set(point_data) | set(cell_data)
        only_full -= lean_names
    return check(f"{label}/xdmf", not bad and not missing and len(grids) == reader.num_steps
                 and only_full == {"principal"},
                 f"{len(grids)} steps, {compared} attribute values of the lean XDMF equal to "
                 f"the full XDMF's read by meshio, bit for bit; left out: "
                 f"{', '.join(sorted(only_full))}"
                 + (f"; differ: {', '.join(bad[:4])}" if bad else "")
                 + (f"; missing in the HDF5 file: {sorted(missing)[:3]}" if missing else ""))


def check_vtk(check, label, lean_xmf, lean_h5):
    """The lean XDMF file through VTK's vtkXdmfReader (the XDMF 2 reader ParaView's "Xdmf
    Reader" is), when VTK is installed (it is not a dependency of cfrd: pip install vtk):
    the node vectors at every step are the HDF5 datasets padded with z = 0, and the cell
    stresses field()'s stress_centroid, bit for bit."""
    try:
        from vtkmodules.util.numpy_support import vtk_to_numpy
        from vtkmodules.vtkCommonExecutionModel import vtkStreamingDemandDrivenPipeline
        from vtkmodules.vtkIOXdmf2 import vtkXdmfReader
    except ImportError:
        print(f"info lean/{label}/vtk: VTK not installed, the lean XDMF was not read by VTK")
        return
    reader = vtkXdmfReader()
    reader.SetFileName(lean_xmf)
    reader.UpdateInformation()
    times = reader.GetOutputInformation(0).Get(vtkStreamingDemandDrivenPipeline.TIME_STEPS())
    bad = []
    with h5py.File(lean_h5, "r") as h5:
        groups = results.stages(h5)
        for k, t in enumerate(times or ()):
            reader.UpdateTimeStep(t)
            out = reader.GetOutputDataObject(0)
            if out.IsA("vtkMultiBlockDataSet"):
                out = out.GetBlock(0)
            for name in ("displacement", "displacement_total"):
                v = vtk_to_numpy(out.GetPointData().GetArray(name))
                u = results.field(groups[k], name)
                if not (v.shape == (u.shape[0], 3) and np.array_equal(v[:, :2], u)
                        and not v[:, 2].any()):
                    bad.append(f"{name} at step {k}")
            # vtkXdmfReader makes a cell Matrix one tuple of nelem x 4 components (the
            # full file's stress_centroid too): its values in order are compared
            c = out.GetCellData().GetArray("stress_centroid")
            c = None if c is None else vtk_to_numpy(c)
            ref = results.field(groups[k], "stress_centroid")
            if c is None or c.size != ref.size or \
                    c.ravel().tobytes() != ref.ravel().tobytes():
                bad.append(f"stress_centroid at step {k}")
    check(f"{label}/vtk", times is not None and len(times) == len(groups) and not bad,
          f"{len(times or ())} steps read by VTK's vtkXdmfReader: displacement and "
          "displacement_total (u_before_reset + displacement) padded with z = 0 and "
          "stress_centroid (its nelem x 4 values in order) equal to "
          "cfrdtools.results.field()'s, bit for bit"
          + (f"; differ: {', '.join(bad[:4])}" if bad else ""))


def main(argv=None):
    args = parser(__doc__, cfrd=True, workdir="build/lean").parse_args(argv)
    check = Checks("lean")
    work = fresh(args.workdir)
    for label, deck, options in DECKS:
        paths = {}
        for mode in ("full", "lean"):
            out = os.path.join(work, label, mode)
            os.makedirs(out)
            extra = ("--results", "full") if mode == "full" else ()
            done = run(args.cfrd, os.path.join(ROOT, deck), "--out", out, *extra, *options,
                       check=False)
            if done.returncode != 0:
                check(f"{label}/run-{mode}", False, f"exit {done.returncode}: "
                      f"{done.stderr[-300:]}")
                return 1
            paths[mode] = os.path.join(out, os.path.basename(deck)[:-4])
        n_same, n_derived, bad, (linked, before, geometry, link_bad, repeats) = \
            compare_files(paths["full"] + ".h5", paths["lean"] + ".h5")
        check(f"{label}/values", not bad and n_derived > 0,
              f"{n_same} datasets equal to the full file's bytes, {n_derived} derived ones "
              "computed by cfrdtools.results.field() to the same bytes"
              + (f"; differ: {', '.join(bad[:5])}" if bad else ""))
        nstage = len(results.stage_names(h5py.File(paths["lean"] + ".h5", "r")))
        check(f"{label}/links", linked == nstage and 0 < before < nstage and
              geometry in (0, 1) and not link_bad,
              f"displacement_total left out at all {linked} stages ({before} before the first "
              f"RESET); the slab geometry {geometry} object(s) for all stages; {repeats} "
              "datasets linked to the last stage's, every one whose values are the last "
              "stage's bits and no other"
              + (f"; wrong: {', '.join(link_bad[:4])}" if link_bad else ""))
        if not options:
            check_xdmf(check, label, paths["full"] + ".xmf", paths["lean"] + ".xmf",
                       paths["lean"] + ".h5")
            check_vtk(check, label, paths["lean"] + ".xmf", paths["lean"] + ".h5")
        size = {k: os.path.getsize(v + ".h5") for k, v in paths.items()}
        check(f"{label}/size", size["lean"] < size["full"],
              f"lean {size['lean'] / 1e6:.2f} MB, full {size['full'] / 1e6:.2f} MB "
              f"({size['lean'] / size['full']:.2f})")
        if label == "contact":
            out = os.path.join(work, label, "restart")
            os.makedirs(out)
            done = subprocess.run([args.cfrd, "--quiet", "--restart", paths["lean"] + ".h5",
                                   "--from-stage", "20", "--results", "full", "--out", out],
                                  capture_output=True, text=True)
            restarted = os.path.join(out, os.path.basename(paths["lean"]) + ".h5")
            if done.returncode != 0 or not os.path.exists(restarted):
                check(f"{label}/restart", False, f"exit {done.returncode}: "
                      f"{done.stderr[-300:]}")
            else:
                n_same, _, bad, _ = compare_files(paths["full"] + ".h5", restarted)
                bad = [b for b in bad if "attribute" not in b]
                check(f"{label}/restart", not bad, f"the lean file continued from stage 20 "
                      f"with --results full: {n_same} datasets equal to the full run's"
                      + (f"; differ: {', '.join(bad[:5])}" if bad else ""))
    for extra in (["--results", "fat"], ["--results"]):
        done = subprocess.run([args.cfrd, "--out", work, *extra], capture_output=True,
                              text=True)
        check("usage " + " ".join(extra), done.returncode == 2 and
              "--results needs lean or full" in done.stderr,
              f"exit {done.returncode} (2), {done.stderr.strip().splitlines()[0][:60]!r}")
    return check.status


if __name__ == "__main__":
    sys.exit(main())
