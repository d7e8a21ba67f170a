#!/usr/bin/env python3
"""Compare two cfrd result sets quantity by quantity (issue 8, section 4).

    python3 tools/compare.py A B [--rtol R] [--atol A] [--tol QUANTITY=RTOL,ATOL ...]
                             [--worst N] [--quantities Q,Q,...]
    python3 tools/compare.py --reduce RESULTS.h5 OUT.csv[.gz]     (compact reference)

A is the reference, B the candidate. Each may be
  - a cfrd HDF5 results file (DECK.h5),
  - one of cfrd's CSVs (DECK-gauges.csv, -openings.csv, -slab.csv, -interface.csv),
  - a result table typed from a legacy FEADAM/ISBILD listing (docs/results.md, "Result
    tables"): a CSV with a `stage` column, one location column (node, element, gauge, phase
    or section) and component columns such as ux, uy, sxx, syy, sxy, s1, s3, stress_level,
  - a long-form CSV (quantity,stage,location,component,value), as --reduce writes it: the
    compact references of the regression suite in outputs/reference/.

Every value of A must be found in B (a table typed from a listing holds a few values, the
HDF5 file all of them); quantities or components present on one side only are listed and
not compared. A value fails when |b - a| > atol + rtol |a|. ATOL is a number in the
quantity's units, or `Xmax`, X times the largest |a| of that quantity in A (of that
component for `counts`, whose components are different things): a tolerance relative to
the quantity's scale, which does not fail on round-off in values near zero.

Prints the worst differences, ranked by |b - a| over what is allowed, with their quantity,
stage, location (node, element, ...) and component, then one line per quantity.
Exit status 0 when every value agrees, 1 when one does not or is missing, 2 for bad input.
"""

import argparse
import csv
import gzip
import io
import math
import os
import re
import sys

import numpy as np
from cfrdtools.results import text

# quantity -> (location kind, components), in the order of docs/results.md.
QUANTITIES = {
    "displacement": ("node", ("ux", "uy")),
    "displacement_total": ("node", ("ux", "uy")),
    "reaction": ("node", ("rx", "ry")),
    "stress": ("element", ("sxx", "syy", "szz", "sxy")),
    "principal": ("element", ("s1", "s3")),
    "stress_level": ("element", ("level",)),
    "counts": ("stage", ("increments", "factorisations", "iterations", "cutbacks",
                         "near_failure")),
    "loads": ("stage", ("applied_x", "applied_y", "reaction_sum_x", "reaction_sum_y")),
    "residual": ("stage", ("max_residual",)),
    "water_level": ("stage", ("level",)),
    "extremes": ("stage", ("max_settlement", "max_ux", "min_ux")),
    "gauge": ("gauge", ("ux", "settlement")),
    "opening": ("phase", ("width", "depth")),
    "interface": ("station", ("sigma_n", "tau", "du_n", "du_s")),
    "slab": ("section", ("axial", "shear", "moment")),
    "contact": ("slave", ("gap", "slip", "sigma_n", "tau")),
}

# Result tables (typed from legacy listings): column -> (quantity, component).
TABLE_COLUMNS = {
    "node": {"ux": ("displacement", "ux"), "uy": ("displacement", "uy"),
             "ux_total": ("displacement_total", "ux"),
             "uy_total": ("displacement_total", "uy"),
             "rx": ("reaction", "rx"), "ry": ("reaction", "ry")},
    "element": {"sxx": ("stress", "sxx"), "syy": ("stress", "syy"),
                "szz": ("stress", "szz"), "sxy": ("stress", "sxy"),
                "s1": ("principal", "s1"), "s3": ("principal", "s3"),
                "stress_level": ("stress_level", "level")},
    "stage": {c: ("extremes", c) for c in QUANTITIES["extremes"][1]},
    "gauge": {"ux": ("gauge", "ux"), "settlement": ("gauge", "settlement")},
    "phase": {"width": ("opening", "width"), "depth": ("opening", "depth")},
    "section": {"axial": ("slab", "axial"), "shear": ("slab", "shear"),
                "moment": ("slab", "moment")},
}


class InputError(Exception):
    """Bad input: a file that cannot be read or is not a result set (exit status 2)."""


class Block:
    """The values of one quantity at one stage: ids (node numbers, gauge names, ...) and a
    (len(ids), len(components)) array, NaN where a component is not given."""

    def __init__(self, ids, components, values):
        self.ids = list(ids)
        self.components = list(components)
        self.values = np.asarray(values, dtype=float).reshape(len(self.ids),
                                                              len(self.components))


class ResultSet:
    """Blocks keyed by (quantity, stage), with the stage names for messages."""

    def __init__(self, path):
        self.path = path
        self.blocks = {}
        self.stage_names = {}
        # quantity -> components the source holds, also where a reader skipped them
        self.available = {}
        self._pending = {}          # values added one at a time, until finish()

    def add(self, quantity, stage, ids, components, values):
        self.blocks[(quantity, int(stage))] = Block(ids, components, values)
        self.available.setdefault(quantity, set()).update(components)

    def add_values(self, quantity, stage, loc, component, value):
        """One value at a time (CSV readers); merged into blocks by finish()."""
        by_loc = self._pending.setdefault((quantity, int(stage)), {})
        by_loc.setdefault(loc, {})[component] = value

    def finish(self):
        pending, self._pending = self._pending, {}
        for (quantity, stage), by_loc in pending.items():
            comps = [c for c in QUANTITIES[quantity][1]
                     if any(c in v for v in by_loc.values())]
            ids = sorted(by_loc, key=sort_key)
            values = [[by_loc[i].get(c, math.nan) for c in comps] for i in ids]
            self.add(quantity, stage, ids, comps, values)
        return self


def sort_key(loc):
    return (0, loc, "") if isinstance(loc, int) else (1, 0, str(loc))


def location_text(quantity, loc):
    kind = QUANTITIES[quantity][0]
    return "-" if kind == "stage" else f"{kind} {loc}"


# ------------------------------------------------------------------------------ readers

def read_h5(path, wanted=None):
    """A cfrd HDF5 file. `wanted`, a set of (quantity, stage), limits what is read."""
    import h5py
    rs = ResultSet(path)
    try:
        f = h5py.File(path, "r")
    except OSError as exc:
        raise InputError(f"{path}: not an HDF5 file ({exc})")
    with f:
        if "stages" not in f or "mesh" not in f:
            raise InputError(f"{path}: not a cfrd results file (no /stages or /mesh)")
        conn = f["mesh/connectivity"][...]
        group_names = [text(g) for g in f["mesh/group_names"][...]] \
            if "mesh/group_names" in f else []
        gauges = []
        if "gauges/names" in f:
            gauges = list(zip([text(n).strip() for n in f["gauges/names"][...]],
                              f["gauges/nodes"][...]))
        iface_elements = f["mesh/interface_elements"][...] \
            if "mesh/interface_elements" in f else None
        names = sorted(k for k in f["stages"] if re.fullmatch(r"stage_\d+", k))
        for name in names:
            s = int(name.split("_")[1])
            g = f["stages"][name]
            rs.stage_names[s] = text(g.attrs.get("name", "")).strip()

            def want(q, comps=None):
                """Whether to read q at this stage; notes that the file holds it."""
                rs.available.setdefault(q, set()).update(comps or QUANTITIES[q][1])
                return wanted is None or (q, s) in wanted
            active = g["active"][...].astype(bool) if "active" in g else \
                np.ones(len(conn), bool)
            elements = np.flatnonzero(active)
            nodes = np.unique(conn[active]) if active.any() else np.zeros(0, int)
            node_ids = [int(n) for n in nodes]
            for q, dset in (("displacement", "displacement"),
                            ("displacement_total", "displacement_total")):
                if dset in g and want(q):
                    rs.add(q, s, node_ids, ("ux", "uy"), g[dset][...][nodes - 1])
            if "reaction" in g and want("reaction"):
                r = g["reaction"][...]
                rows = np.flatnonzero(np.any(r != 0.0, axis=1))
                rs.add("reaction", s, [int(i) + 1 for i in rows], ("rx", "ry"), r[rows])
            element_ids = [int(e) + 1 for e in elements]
            if "stress_centroid" in g and want("stress"):
                rs.add("stress", s, element_ids, QUANTITIES["stress"][1],
                       g["stress_centroid"][...][elements])
            # The angle of sigma1 is left out: it is undefined where sigma1 = sigma3.
            if "principal" in g and want("principal"):
                rs.add("principal", s, element_ids, ("s1", "s3"),
                       g["principal"][...][elements, :2])
            if "stress_level" in g and want("stress_level"):
                rs.add("stress_level", s, element_ids, ("level",),
                       g["stress_level"][...][elements])
            a = g.attrs
            comps = [c for c in QUANTITIES["counts"][1] if c in a]
            if comps and want("counts", comps):
                rs.add("counts", s, ["-"], comps, [[float(a[c]) for c in comps]])
            if "applied_load" in a and want("loads"):
                comps, vals = [], []
                for c, attr in (("applied", "applied_load"), ("reaction_sum", "reaction_sum")):
                    if attr in a:
                        comps += [c + "_x", c + "_y"]
                        vals += [float(v) for v in a[attr][:2]]
                rs.add("loads", s, ["-"], comps, [vals])
            if "max_residual" in a and want("residual"):
                rs.add("residual", s, ["-"], ["max_residual"], [[float(a["max_residual"])]])
            # Absent while the reservoir is empty.
            if "water_level" in a and want("water_level"):
                rs.add("water_level", s, ["-"], ["level"], [[float(a["water_level"])]])
            if "displacement_total" in g:
                get_extremes = want("extremes") and len(nodes) > 0
                get_gauges = bool(gauges) and want("gauge")
                if get_extremes or get_gauges:
                    u = g["displacement_total"][...]
                if get_extremes:
                    un = u[nodes - 1]
                    rs.add("extremes", s, ["-"], QUANTITIES["extremes"][1],
                           [[-un[:, 1].min(), un[:, 0].max(), un[:, 0].min()]])
                if get_gauges:
                    rs.add("gauge", s, [n for n, _ in gauges], ("ux", "settlement"),
                           [[u[k - 1, 0], -u[k - 1, 1]] for _, k in gauges])
            if "interface" in g and iface_elements is not None:
                r = g["interface"]
                if "opening_width" in r and want("opening"):
                    ids = [group_names[k - 1] if 0 < k <= len(group_names) else str(k)
                           for k in r["opening_group"][...]]
                    rs.add("opening", s, ids, ("width", "depth"),
                           np.column_stack([r["opening_width"][...], r["opening_depth"][...]]))
                if "sigma_n" in r and want("interface"):
                    on = r["active"][...].astype(bool) if "active" in r else \
                        np.ones(len(iface_elements), bool)
                    ids, vals = [], []
                    cols = [r[c][...] for c in ("sigma_n", "tau", "du_n", "du_s")]
                    for i in np.flatnonzero(on):
                        for p in range(cols[0].shape[1]):
                            ids.append(f"{int(iface_elements[i])}/{p + 1}")
                            vals.append([c[i, p] for c in cols])
                    rs.add("interface", s, ids, QUANTITIES["interface"][1], vals)
            if "contact" in g:
                r = g["contact"]
                if "opening_width" in r and want("opening"):
                    ids = [group_names[k - 1] if 0 < k <= len(group_names) else str(k)
                           for k in r["opening_group"][...]]
                    rs.add("opening", s, ids, ("width", "depth"),
                           np.column_stack([r["opening_width"][...], r["opening_depth"][...]]))
                if "gap" in r and want("contact"):
                    on = r["placed"][...].astype(bool)
                    nodes = r["node"][...][on]
                    if len(nodes):
                        rs.add("contact", s, [int(k) for k in nodes],
                               QUANTITIES["contact"][1],
                               np.column_stack([r[c][...][on] for c in
                                                QUANTITIES["contact"][1]]))
            if "slab" in g and "axial" in g["slab"] and want("slab"):
                r = g["slab"]
                n = len(r["axial"])
                if n:
                    rs.add("slab", s, list(range(1, n + 1)), ("axial", "shear", "moment"),
                           np.column_stack([r["axial"][...], r["shear"][...],
                                            r["moment"][...]]))
    return rs


def open_text(path):
    try:
        if path.endswith(".gz"):
            return io.TextIOWrapper(gzip.open(path, "rb"), encoding="utf-8")
        return open(path, encoding="utf-8")
    except OSError as exc:
        raise InputError(f"{path}: cannot read ({exc.strerror})")


def number(path, line, column, field):
    try:
        return float(field)
    except ValueError:
        raise InputError(f"{path}:{line}: column {column}: expected a number, "
                         f"found '{field}'")


def read_csv_rows(path):
    """(line number, row) pairs of a CSV, '#' comment lines and blank lines skipped."""
    with open_text(path) as fh:
        lines = fh.read().splitlines()
    rows = []
    for number_, row in zip(range(1, len(lines) + 1), csv.reader(lines)):
        if not row or not "".join(row).strip() or row[0].lstrip().startswith("#"):
            continue
        rows.append((number_, [c.strip() for c in row]))
    if not rows:
        raise InputError(f"{path}: no header line")
    return rows


def read_csv(path):
    rows = read_csv_rows(path)
    header_line, header = rows[0]
    body = rows[1:]
    rs = ResultSet(path)
    cols = {name: k for k, name in enumerate(header)}

    def field(line, row, name):
        k = cols[name]
        if k >= len(row):
            raise InputError(f"{path}:{line}: column {name} missing (short row)")
        return row[k]

    def stage_of(line, row):
        value = field(line, row, "stage")
        if not re.fullmatch(r"\d+", value):
            raise InputError(f"{path}:{line}: column stage: expected a stage number, "
                             f"found '{value}'")
        s = int(value)
        if "label" in cols:
            rs.stage_names[s] = field(line, row, "label")
        return s

    if header[:5] == ["quantity", "stage", "location", "component", "value"]:
        for line, row in body:
            q, comp = row[0], row[3]
            if q not in QUANTITIES or comp not in QUANTITIES[q][1]:
                raise InputError(f"{path}:{line}: unknown quantity/component '{q}/{comp}'")
            s = stage_of(line, row)
            loc = row[2].split(" ", 1)[-1] if row[2] != "-" else "-"
            if QUANTITIES[q][0] in ("node", "element", "section", "slave"):
                loc = int(loc)
            rs.add_values(q, s, loc, comp, number(path, line, "value", row[4]))
        return rs.finish()
    if "stage" not in cols:
        raise InputError(f"{path}:{header_line}: no 'stage' column: not a result table")
    gauge_cols = [(k, m.group(1), m.group(2)) for k, name in enumerate(header)
                  for m in [re.fullmatch(r"(.+)_(ux|settlement)_m", name)] if m]
    if gauge_cols:                                            # DECK-gauges.csv
        for line, row in body:
            s = stage_of(line, row)
            for k, name, comp in gauge_cols:
                rs.add_values("gauge", s, name, comp, number(path, line, header[k], row[k]))
        return rs.finish()
    if "width_m" in cols and "group" in cols:                 # DECK-openings.csv
        for line, row in body:
            s = stage_of(line, row)
            for comp in ("width", "depth"):
                rs.add_values("opening", s, field(line, row, "group"), comp,
                              number(path, line, comp + "_m", field(line, row, comp + "_m")))
        return rs.finish()
    if "N_kN_per_m" in cols and "section" in cols:            # DECK-slab.csv
        for line, row in body:
            s = stage_of(line, row)
            sec = int(field(line, row, "section"))
            for comp, name in (("axial", "N_kN_per_m"), ("shear", "V_kN_per_m"),
                               ("moment", "M_kNm_per_m")):
                rs.add_values("slab", s, sec, comp, number(path, line, name,
                                                          field(line, row, name)))
        return rs.finish()
    if "sigma_n_kPa" in cols and "point" in cols:             # DECK-interface.csv
        for line, row in body:
            s = stage_of(line, row)
            loc = f"{field(line, row, 'element')}/{field(line, row, 'point')}"
            for comp, name in (("sigma_n", "sigma_n_kPa"), ("tau", "tau_kPa"),
                               ("du_n", "du_n_m"), ("du_s", "du_s_m")):
                rs.add_values("interface", s, loc, comp, number(path, line, name,
                                                               field(line, row, name)))
        return rs.finish()
    # A result table: stage, one location column, component columns.
    kinds = [k for k in ("node", "element", "gauge", "phase", "section") if k in cols]
    kind = kinds[0] if len(kinds) == 1 else ("stage" if not kinds else None)
    if kind is None:
        raise InputError(f"{path}:{header_line}: more than one location column "
                         f"({', '.join(kinds)}): one table per location kind")
    known = TABLE_COLUMNS[kind]
    comp_cols = []
    for k, name in enumerate(header):
        if name in ("stage", kind, "label"):
            continue
        if name not in known:
            raise InputError(f"{path}:{header_line}: column {k + 1} '{name}': not a "
                             f"{kind} component (expected one of {', '.join(known)})")
        comp_cols.append((k, name) + known[name])
    for line, row in body:
        s = stage_of(line, row)
        loc = "-" if kind == "stage" else field(line, row, kind)
        if kind in ("node", "element", "section"):
            if not re.fullmatch(r"\d+", loc):
                raise InputError(f"{path}:{line}: column {kind}: expected a number, "
                                 f"found '{loc}'")
            loc = int(loc)
        for k, name, q, comp in comp_cols:
            if k < len(row) and row[k] != "":
                rs.add_values(q, s, loc, comp, number(path, line, name, row[k]))
    return rs.finish()


def read_legacy_listing(path):
    """A legacy-style listing written by `cfrd --legacy-listing` (DECK.lst): per stage the
    nodal point displacements (since placement) and the element stresses, principal
    stresses and stress levels, in the fixed columns of docs/results.md."""
    rs = ResultSet(path)
    with open_text(path) as fh:
        lines = fh.read().splitlines()
    if not lines or "LEGACY-STYLE LISTING" not in lines[0]:
        raise InputError(f"{path}:1: not a legacy-style listing of cfrd (no "
                         f"'LEGACY-STYLE LISTING' banner)")
    stage, table = None, None
    # (first column, width) of each field, 0-based, as write_legacy_listing writes them
    node_fields = [("node", 0, 8), ("ux", 34, 13), ("uy", 47, 13)]
    element_fields = [("element", 0, 8), ("sxx", 13, 13), ("syy", 26, 13), ("szz", 39, 13),
                      ("sxy", 52, 13), ("s1", 65, 13), ("s3", 78, 13), ("level", 99, 9)]
    for number, line in enumerate(lines, start=1):
        m = re.match(r"1STAGE\s*(\d+)\s+(.*)$", line)
        if m:
            stage, table = int(m.group(1)), None
            rs.stage_names[stage] = m.group(2).strip()
            continue
        if line.strip() == "NODAL POINT DISPLACEMENTS":
            table = "node"
            continue
        if line.strip() == "ELEMENT STRESSES AT CENTROIDS":
            table = "element"
            continue
        if not line.strip():
            table = None                # a table ends at a blank line
            continue
        if table is None or line.lstrip().startswith(("NODE", "ELEM")):
            continue                    # stage lines, column headers
        fields = node_fields if table == "node" else element_fields
        values = {}
        for name, first, width in fields:
            text_ = line[first:first + width].strip()
            if name in ("node", "element"):
                if not text_.isdigit():
                    raise InputError(f"{path}:{number}:{first + 1}-{first + width}: "
                                     f"{name} number expected, found '{text_}'")
                loc = int(text_)
            else:
                values[name] = number_at(path, number, first, width, name, text_)
        if stage is None:
            raise InputError(f"{path}:{number}: a table row before the first STAGE line")
        if table == "node":
            for c in ("ux", "uy"):
                rs.add_values("displacement_total", stage, loc, c, values[c])
        else:
            for c in ("sxx", "syy", "szz", "sxy"):
                rs.add_values("stress", stage, loc, c, values[c])
            for c in ("s1", "s3"):
                rs.add_values("principal", stage, loc, c, values[c])
            rs.add_values("stress_level", stage, loc, "level", values["level"])
    return rs.finish()


def number_at(path, line, first, width, name, field):
    try:
        return float(field)
    except ValueError:
        raise InputError(f"{path}:{line}:{first + 1}-{first + width}: field {name}: "
                         f"expected a number, found '{field}'")


def read_result_set(path, wanted=None):
    if not os.path.isfile(path):
        raise InputError(f"{path}: no such file")
    if path.endswith(".h5"):
        return read_h5(path, wanted)
    if path.endswith(".lst"):
        return read_legacy_listing(path)
    return read_csv(path)


# ------------------------------------------------------------------------------ comparing

def parse_tolerance(text_, where):
    """'RTOL,ATOL' -> (rtol, atol, atol_is_scaled)."""
    parts = text_.split(",")
    if len(parts) != 2:
        raise InputError(f"{where}: expected RTOL,ATOL, found '{text_}'")
    try:
        rtol = float(parts[0])
        scaled = parts[1].endswith("max")
        atol = float(parts[1][:-3] if scaled else parts[1])
    except ValueError:
        raise InputError(f"{where}: expected RTOL,ATOL (ATOL a number or Xmax), "
                         f"found '{text_}'")
    if rtol < 0 or atol < 0:
        raise InputError(f"{where}: tolerances must not be negative, found '{text_}'")
    return rtol, atol, scaled


def compare(a, b, tolerances, default, quantities=None):
    """Compare result set b against the reference a. Returns a report dict."""
    rows = []            # (ratio, quantity, stage, loc, comp, va, vb, allowed)
    missing = []         # (quantity, stage, loc, comp)
    per_q = {}
    only_a = sorted(set(a.available) - set(b.available))
    only_b = sorted(set(b.available) - set(a.available))
    common = [q for q in QUANTITIES if q in a.available and q in b.available]
    if quantities:
        common = [q for q in common if q in quantities]
    skipped_components = set()
    b_components = {q: b.available[q] for q in common}
    for q in common:
        rtol, atol, scaled = tolerances.get(q, default)
        keys = sorted(k for k in a.blocks if k[0] == q)
        comps = [c for c in QUANTITIES[q][1]
                 if c in b_components[q] and any(c in a.blocks[k].components for k in keys)]
        for k in keys:
            skipped_components.update((q, c) for c in a.blocks[k].components
                                      if c not in comps)
        # Scale of the quantity in A: over all its components, but per component for the
        # counts (increments, iterations, ... are different things).
        scale = {}
        for c in comps:
            m = 0.0
            for k in keys:
                blk = a.blocks[k]
                if c in blk.components:
                    v = blk.values[:, blk.components.index(c)]
                    v = v[np.isfinite(v)]
                    if v.size:
                        m = max(m, float(np.abs(v).max()))
            scale[c] = m
        if q != "counts":
            scale = {c: max(scale.values(), default=0.0) for c in comps}
        stats = per_q.setdefault(q, {"count": 0, "fail": 0, "max_abs": 0.0, "max_rel": 0.0,
                                     "max_scaled": 0.0,
                                     "rtol": rtol, "atol": atol, "scaled": scaled,
                                     "scale": max(scale.values(), default=0.0)})
        for key in keys:
            blk_a = a.blocks[key]
            blk_b = b.blocks.get(key)
            stage = key[1]
            index_b = {} if blk_b is None else {i: n for n, i in enumerate(blk_b.ids)}
            for c in comps:
                if c not in blk_a.components:
                    continue
                col_a = blk_a.values[:, blk_a.components.index(c)]
                col_b_all = None
                if blk_b is not None and c in blk_b.components:
                    col_b_all = blk_b.values[:, blk_b.components.index(c)]
                take = [(n, index_b.get(i)) for n, i in enumerate(blk_a.ids)
                        if math.isfinite(col_a[n])]
                for n, m in take:
                    if m is None or col_b_all is None or not math.isfinite(col_b_all[m]):
                        missing.append((q, stage, blk_a.ids[n], c))
                found = [(n, m) for n, m in take
                         if m is not None and col_b_all is not None
                         and math.isfinite(col_b_all[m])]
                if not found:
                    continue
                na = np.array([n for n, _ in found])
                nb = np.array([m for _, m in found])
                va, vb = col_a[na], col_b_all[nb]
                diff = np.abs(vb - va)
                allowed = (atol * scale[c] if scaled else atol) + rtol * np.abs(va)
                with np.errstate(divide="ignore", invalid="ignore"):
                    ratio = np.where(allowed > 0, diff / np.where(allowed > 0, allowed, 1),
                                     np.where(diff > 0, np.inf, 0.0))
                    rel = np.where(np.abs(va) > 0, diff / np.abs(va),
                                   np.where(diff > 0, np.inf, 0.0))
                stats["count"] += len(va)
                stats["fail"] += int(np.count_nonzero(ratio > 1))
                stats["max_abs"] = max(stats["max_abs"], float(diff.max()))
                stats["max_rel"] = max(stats["max_rel"], float(rel.max()))
                if scale[c] > 0:
                    stats["max_scaled"] = max(stats["max_scaled"],
                                              float(diff.max()) / scale[c])
                # Keep the worst few of each column for the ranking.
                worst = np.argsort(-ratio, kind="stable")[:50]
                for w in worst:
                    rows.append((float(ratio[w]), q, stage, blk_a.ids[na[w]], c,
                                 float(va[w]), float(vb[w]), float(allowed[w])))
    rows.sort(key=lambda r: -r[0])
    return {"rows": rows, "missing": missing, "per_q": per_q, "only_a": only_a,
            "only_b": only_b, "skipped": sorted(skipped_components),
            "compared": sum(s["count"] for s in per_q.values())}


def stage_text(rs, stage):
    name = rs.stage_names.get(stage, "")
    return f"stage {stage}" + (f" ({name})" if name else "")


def print_report(report, a, b, worst, out=sys.stdout):
    per_q = report["per_q"]
    failed = sum(s["fail"] for s in per_q.values())
    print(f"A (reference): {a.path}", file=out)
    print(f"B (compared):  {b.path}", file=out)
    bad = [r for r in report["rows"] if r[0] > 1]
    shown = report["rows"][:worst] if not bad else bad[:worst]
    title = "worst differences" if not bad else "differences beyond tolerance, worst first"
    if shown:
        print(f"{title} (|B-A| / allowed, allowed = atol + rtol |A|):", file=out)
        print(f"  {'ratio':>9}  {'quantity':<18} {'component':<14} {'where':<16} "
              f"{'A':>16} {'B':>16} {'|B-A|':>10}  stage", file=out)
        for ratio, q, stage, loc, c, va, vb, allowed in shown:
            print(f"  {ratio:9.2e}  {q:<18} {c:<14} {location_text(q, loc):<16} "
                  f"{va:16.9e} {vb:16.9e} {abs(vb - va):10.3e}  {stage_text(a, stage)}",
                  file=out)
    for q, stage, loc, c in report["missing"][:worst]:
        print(f"  missing in B: {q} {c} at {location_text(q, loc)}, {stage_text(a, stage)}",
              file=out)
    if len(report["missing"]) > worst:
        print(f"  ... and {len(report['missing']) - worst} more missing", file=out)
    print("per quantity:", file=out)
    for q, s in per_q.items():
        atol = f"{s['atol']:g}*max|A| = {s['atol'] * s['scale']:.3g}" if s["scaled"] \
            else f"{s['atol']:g}"
        print(f"  {q:<18} {s['count']:8d} values, {s['fail']:6d} beyond, max |B-A| "
              f"{s['max_abs']:.2e}, /|A| {s['max_rel']:.2e}, /max|A| {s['max_scaled']:.2e} "
              f"(rtol {s['rtol']:g}, atol {atol})", file=out)
    if report["only_a"]:
        print(f"  only in A (not compared): {', '.join(report['only_a'])}", file=out)
    if report["only_b"]:
        print(f"  only in B (not compared): {', '.join(report['only_b'])}", file=out)
    if report["skipped"]:
        print("  components of A not in B (not compared): "
              + ", ".join(f"{q}/{c}" for q, c in report["skipped"]), file=out)
    ok = failed == 0 and not report["missing"] and report["compared"] > 0
    verdict = "AGREE" if ok else "DIFFER"
    if report["compared"] == 0:
        print(f"{verdict}: nothing in common to compare", file=out)
    else:
        print(f"{verdict}: {report['compared']} values compared, {failed} beyond tolerance, "
              f"{len(report['missing'])} missing in B", file=out)
    return ok


# ------------------------------------------------------------------------------ reducing

def reduce_results(path, out, full_stages="last", header=(), quantities=None):
    """Write the compact long-form reference of a cfrd HDF5 file: at every stage the stage
    figures, extremes, gauges and openings; at the last stage (or every stage with
    full_stages='all') the fields too. `displacement` is left out where it equals
    `displacement_total` (decks without RESET). quantities: only these (default all)."""
    rs = read_h5(path)
    last = max(s for _, s in rs.blocks)
    per_stage = ("counts", "loads", "residual", "water_level", "extremes", "gauge",
                 "opening", "contact")
    lines = [f"# {h}" for h in header] + ["quantity,stage,location,component,value"]
    for (q, s) in sorted(rs.blocks, key=lambda k: (k[1], list(QUANTITIES).index(k[0]))):
        if q not in per_stage and full_stages == "last" and s != last:
            continue
        if q == "principal" or (quantities and q not in quantities):
            continue                    # derived from the stresses, or not asked for
        blk = rs.blocks[(q, s)]
        if q == "displacement":
            tot = rs.blocks.get(("displacement_total", s))
            if tot is not None and tot.ids == blk.ids and np.array_equal(tot.values,
                                                                        blk.values):
                continue
        for i, loc in enumerate(blk.ids):
            where = location_text(q, loc)
            for j, c in enumerate(blk.components):
                v = blk.values[i, j]
                if math.isfinite(v):
                    lines.append(f"{q},{s},{where},{c},{v:.12g}")
    data = ("\n".join(lines) + "\n").encode()
    tmp = out + ".part"
    if out.endswith(".gz"):
        # mtime 0: the same results give the same bytes (no spurious git changes).
        with open(tmp, "wb") as raw, gzip.GzipFile(fileobj=raw, mode="wb", mtime=0,
                                                   filename="") as fh:
            fh.write(data)
    else:
        with open(tmp, "wb") as fh:
            fh.write(data)
    os.replace(tmp, out)
    return len(lines) - 1 - len(header)


def main(argv=None):
    parser = argparse.ArgumentParser(
        description="Compare two cfrd result sets quantity by quantity.",
        epilog="Details: docs/results.md, section 'Comparing results'.")
    parser.add_argument("a", help="reference: .h5, .csv, .csv.gz or .lst")
    parser.add_argument("b", help="compared result set (with --reduce: the output file)")
    parser.add_argument("--rtol", type=float, default=1e-9,
                        help="relative tolerance (default 1e-9)")
    parser.add_argument("--atol", default="0",
                        help="absolute tolerance: a number or Xmax (default 0)")
    parser.add_argument("--tol", action="append", default=[], metavar="QUANTITY=RTOL,ATOL",
                        help="tolerance of one quantity (repeatable)")
    parser.add_argument("--quantities", help="compare only these (comma-separated)")
    parser.add_argument("--worst", type=int, default=10, help="lines of differences shown")
    parser.add_argument("--reduce", action="store_true",
                        help="write the compact long-form reference of A (an .h5) to B")
    parser.add_argument("--all-stages", action="store_true",
                        help="with --reduce: fields at every stage, not only the last")
    args = parser.parse_args(argv)
    try:
        if args.reduce:
            if not args.a.endswith(".h5"):
                raise InputError(f"{args.a}: --reduce reads a cfrd .h5 file")
            n = reduce_results(args.a, args.b, "all" if args.all_stages else "last")
            print(f"{args.b}: {n} values of {args.a}")
            return 0
        default = parse_tolerance(f"{args.rtol},{args.atol}", "--rtol/--atol")
        tolerances = {}
        for spec in args.tol:
            q, sep, value = spec.partition("=")
            if not sep or q not in QUANTITIES:
                raise InputError(f"--tol {spec}: expected QUANTITY=RTOL,ATOL with QUANTITY "
                                 f"one of {', '.join(QUANTITIES)}")
            tolerances[q] = parse_tolerance(value, f"--tol {spec}")
        quantities = None
        if args.quantities:
            quantities = args.quantities.split(",")
            bad = [q for q in quantities if q not in QUANTITIES]
            if bad:
                raise InputError(f"--quantities: unknown {', '.join(bad)}")
        a = read_result_set(args.a)
        # Read from B only what A has (a full HDF5 file holds far more than a reference).
        wanted = set(a.blocks) if args.b.endswith(".h5") else None
        b = read_result_set(args.b, wanted) if wanted is not None else \
            read_result_set(args.b)
    except InputError as exc:
        print(f"compare: {exc}", file=sys.stderr)
        return 2
    report = compare(a, b, tolerances, default, quantities)
    return 0 if print_report(report, a, b, args.worst) else 1


if __name__ == "__main__":
    sys.exit(main())
