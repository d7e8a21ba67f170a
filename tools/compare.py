#!/usr/bin/env python3
"""Compare two cfrd result sets quantity by quantity (issue 8, section 4).

    python3 tools/compare.py A B [--rtol R] [--atol A] [--tol QUANTITY=RTOL,ATOL ...]
                             [--worst N] [--quantities Q,Q,...]
    python3 tools/compare.py --reduce RESULTS.h5 OUT.csv[.gz]     (compact reference)

A is the reference, B the candidate; each a cfrd HDF5 file, one of its CSVs (-gauges,
-openings, -slab, -interface), a legacy-style listing (.lst), a result table typed from a
listing (a CSV with a `stage` column, one location column and component columns) or the
long form (quantity,stage,location,component,value) that --reduce writes (docs/results.md,
"Comparing results"). Every value of A must be found in B; a value fails when
|b - a| > atol + rtol |a|, ATOL a number or `Xmax`, X times the largest |a| of the quantity
in A (of the component, for `counts`). Prints the worst differences, then a line per
quantity. Exit status 0 when every value agrees, 1 when one does not or is missing, 2 for
bad input.
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

from cfrdtools.results import DERIVED, open_results, text
from cfrdtools.results import field as stage_field

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
    "element": {**{c: ("stress", c) for c in QUANTITIES["stress"][1]},
                "s1": ("principal", "s1"), "s3": ("principal", "s3"),
                "stress_level": ("stress_level", "level")},
    "stage": {c: ("extremes", c) for c in QUANTITIES["extremes"][1]},
    "gauge": {"ux": ("gauge", "ux"), "settlement": ("gauge", "settlement")},
    "phase": {"width": ("opening", "width"), "depth": ("opening", "depth")},
    "section": {c: ("slab", c) for c in QUANTITIES["slab"][1]},
}
# cfrd's CSVs: a column that tells the file -> (location column, quantity,
# [(component, column)]).
CFRD_CSVS = {
    "width_m": ("group", "opening", [("width", "width_m"), ("depth", "depth_m")]),
    "N_kN_per_m": ("section", "slab", [("axial", "N_kN_per_m"), ("shear", "V_kN_per_m"),
                                       ("moment", "M_kNm_per_m")]),
    "sigma_n_kPa": ("point", "interface", [("sigma_n", "sigma_n_kPa"), ("tau", "tau_kPa"),
                                           ("du_n", "du_n_m"), ("du_s", "du_s_m")]),
}


class InputError(Exception):
    """Bad input: a file that cannot be read or is not a result set (exit status 2)."""


class Block:
    """The values of one quantity at one stage: ids (node numbers, gauge names, ...) and a
    (len(ids), len(components)) array, NaN where a component is not given."""

    def __init__(self, ids, components, values):
        self.ids, self.components = list(ids), list(components)
        self.values = np.asarray(values, dtype=float).reshape(len(self.ids),
                                                              len(self.components))


class ResultSet:
    """Blocks keyed by (quantity, stage), with the stage names for messages; `available`:
    quantity -> components the source holds, also where a reader skipped them."""

    def __init__(self, path):
        self.path, self.blocks, self.stage_names, self.available = path, {}, {}, {}
        self._pending = {}          # values added one at a time, until finish()

    def add(self, quantity, stage, ids, components, values):
        self.blocks[(quantity, int(stage))] = Block(ids, components, values)
        self.available.setdefault(quantity, set()).update(components)

    def add_values(self, quantity, stage, loc, component, value):
        """One value at a time (CSV readers); merged into blocks by finish()."""
        self._pending.setdefault((quantity, int(stage)), {}).setdefault(loc, {})[component] \
            = value

    def finish(self):
        pending, self._pending = self._pending, {}
        for (quantity, stage), by_loc in pending.items():
            comps = [c for c in QUANTITIES[quantity][1] if any(c in v for v in by_loc.values())]
            ids = sorted(by_loc, key=sort_key)
            self.add(quantity, stage, ids, comps,
                     [[by_loc[i].get(c, math.nan) for c in comps] for i in ids])
        return self


def sort_key(loc):
    return (0, loc, "") if isinstance(loc, int) else (1, 0, str(loc))


def location_text(quantity, loc):
    kind = QUANTITIES[quantity][0]
    return "-" if kind == "stage" else f"{kind} {loc}"


def read_h5(path, wanted=None):
    """A cfrd HDF5 file. `wanted`, a set of (quantity, stage), limits what is read."""
    rs = ResultSet(path)
    try:
        f = open_results(path)
    except OSError as exc:
        raise InputError(f"{path}: not an HDF5 file ({exc})")
    with f:
        if "stages" not in f or "mesh" not in f:
            raise InputError(f"{path}: not a cfrd results file (no /stages or /mesh)")
        conn = f["mesh/connectivity"][...]
        group_names = [text(g) for g in f["mesh/group_names"][...]] \
            if "mesh/group_names" in f else []
        gauges = list(zip([text(n).strip() for n in f["gauges/names"][...]],
                          f["gauges/nodes"][...])) if "gauges/names" in f else []
        iface_elements = f["mesh/interface_elements"][...] \
            if "mesh/interface_elements" in f else None
        for name in sorted(k for k in f["stages"] if re.fullmatch(r"stage_\d+", k)):
            s, g = int(name.split("_")[1]), f["stages"][name]
            a = g.attrs
            rs.stage_names[s] = text(a.get("name", "")).strip()

            def want(q, comps=None):
                """Whether to read q at this stage; notes that the file holds it."""
                rs.available.setdefault(q, set()).update(comps or QUANTITIES[q][1])
                return wanted is None or (q, s) in wanted
            active = g["active"][...].astype(bool) if "active" in g else np.ones(len(conn), bool)
            elements = np.flatnonzero(active)
            nodes = np.unique(conn[active]) if active.any() else np.zeros(0, int)
            # (the angle of sigma1 is left out: it is undefined where sigma1 = sigma3)
            for q, dset, rows, ids, cols in (
                    ("displacement", "displacement", nodes - 1, nodes, slice(None)),
                    ("displacement_total", "displacement_total", nodes - 1, nodes, slice(None)),
                    ("stress", "stress_centroid", elements, elements + 1, slice(None)),
                    ("principal", "principal", elements, elements + 1, slice(0, 2)),
                    ("stress_level", "stress_level", elements, elements + 1, slice(None))):
                if (dset in g or dset in DERIVED) and want(q):
                    v = stage_field(g, dset)[rows]     # a lean file's derived fields computed
                    rs.add(q, s, [int(i) for i in ids], QUANTITIES[q][1],
                           v[..., cols] if v.ndim > 1 else v)
            if "reaction" in g and want("reaction"):
                r = g["reaction"][...]
                rows = np.flatnonzero(np.any(r != 0.0, axis=1))
                rs.add("reaction", s, [int(i) + 1 for i in rows], ("rx", "ry"), r[rows])
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
            for q, attr in (("residual", "max_residual"), ("water_level", "water_level")):
                if attr in a and want(q):    # (no water level while the reservoir is empty)
                    rs.add(q, s, ["-"], QUANTITIES[q][1], [[float(a[attr])]])
            if "displacement_total" in g or "displacement" in g:    # (lean: computed)
                get_extremes = want("extremes") and len(nodes) > 0
                get_gauges = bool(gauges) and want("gauge")
                u = stage_field(g, "displacement_total") if get_extremes or get_gauges \
                    else None
                if get_extremes:
                    un = u[nodes - 1]
                    rs.add("extremes", s, ["-"], QUANTITIES["extremes"][1],
                           [[-un[:, 1].min(), un[:, 0].max(), un[:, 0].min()]])
                if get_gauges:
                    rs.add("gauge", s, [n for n, _ in gauges], ("ux", "settlement"),
                           [[u[k - 1, 0], -u[k - 1, 1]] for _, k in gauges])
            for where in ("interface", "contact"):
                if where not in g or (where == "interface" and iface_elements is None):
                    continue
                r = g[where]
                if "opening_width" in r and want("opening"):
                    ids = [group_names[k - 1] if 0 < k <= len(group_names) else str(k)
                           for k in r["opening_group"][...]]
                    rs.add("opening", s, ids, ("width", "depth"),
                           np.column_stack([r["opening_width"][...], r["opening_depth"][...]]))
                if where == "interface" and "sigma_n" in r and want("interface"):
                    on = r["active"][...].astype(bool) if "active" in r else \
                        np.ones(len(iface_elements), bool)
                    cols = [r[c][...] for c in QUANTITIES["interface"][1]]
                    pts = [(i, p) for i in np.flatnonzero(on) for p in range(cols[0].shape[1])]
                    rs.add("interface", s, [f"{int(iface_elements[i])}/{p + 1}" for i, p in pts],
                           QUANTITIES["interface"][1], [[c[i, p] for c in cols] for i, p in pts])
                if where == "contact" and "gap" in r and want("contact"):
                    on = r["placed"][...].astype(bool)
                    if on.any():
                        rs.add("contact", s, [int(k) for k in r["node"][...][on]],
                               QUANTITIES["contact"][1], np.column_stack(
                                   [r[c][...][on] for c in QUANTITIES["contact"][1]]))
            if "slab" in g and "axial" in g["slab"] and want("slab") and len(g["slab/axial"]):
                r = g["slab"]
                rs.add("slab", s, list(range(1, len(r["axial"]) + 1)), QUANTITIES["slab"][1],
                       np.column_stack([r[c][...] for c in QUANTITIES["slab"][1]]))
    return rs


def open_text(path):
    try:
        if path.endswith(".gz"):
            return io.TextIOWrapper(gzip.open(path, "rb"), encoding="utf-8")
        return open(path, encoding="utf-8")
    except OSError as exc:
        raise InputError(f"{path}: cannot read ({exc.strerror})")


def number(where, field, name):
    try:
        return float(field)
    except ValueError:
        raise InputError(f"{where}: column {name}: expected a number, found '{field}'")


def read_csv(path):
    with open_text(path) as fh:
        lines = fh.read().splitlines()
    rows = [(n, [c.strip() for c in row]) for n, row in enumerate(csv.reader(lines), 1)
            if row and "".join(row).strip() and not row[0].lstrip().startswith("#")]
    if not rows:
        raise InputError(f"{path}: no header line")
    (header_line, header), body = rows[0], rows[1:]
    rs = ResultSet(path)
    cols = {name: k for k, name in enumerate(header)}

    def field(line, row, name):
        if cols[name] >= len(row):
            raise InputError(f"{path}:{line}: column {name} missing (short row)")
        return row[cols[name]]

    def stage_of(line, row):
        value = field(line, row, "stage")
        if not re.fullmatch(r"\d+", value):
            raise InputError(f"{path}:{line}: column stage: expected a stage number, "
                             f"found '{value}'")
        if "label" in cols:
            rs.stage_names[int(value)] = field(line, row, "label")
        return int(value)

    def num(line, name, value):
        return number(f"{path}:{line}", value, name)
    if header[:5] == ["quantity", "stage", "location", "component", "value"]:
        for line, row in body:
            q, comp = row[0], row[3]
            if q not in QUANTITIES or comp not in QUANTITIES[q][1]:
                raise InputError(f"{path}:{line}: unknown quantity/component '{q}/{comp}'")
            loc = row[2].split(" ", 1)[-1] if row[2] != "-" else "-"
            if QUANTITIES[q][0] in ("node", "element", "section", "slave"):
                loc = int(loc)
            rs.add_values(q, stage_of(line, row), loc, comp, num(line, "value", row[4]))
        return rs.finish()
    if "stage" not in cols:
        raise InputError(f"{path}:{header_line}: no 'stage' column: not a result table")
    gauge_cols = [(k, m.group(1), m.group(2)) for k, name in enumerate(header)
                  for m in [re.fullmatch(r"(.+)_(ux|settlement)_m", name)] if m]
    if gauge_cols:                                            # DECK-gauges.csv
        for line, row in body:
            s = stage_of(line, row)
            for k, name, comp in gauge_cols:
                rs.add_values("gauge", s, name, comp, num(line, header[k], row[k]))
        return rs.finish()
    for key, (where, q, comps) in CFRD_CSVS.items():          # -openings, -slab, -interface
        if key in cols and where in cols:
            for line, row in body:
                s = stage_of(line, row)
                loc = int(field(line, row, "section")) if q == "slab" else field(
                    line, row, "group") if q == "opening" else \
                    f"{field(line, row, 'element')}/{field(line, row, 'point')}"
                for comp, name in comps:
                    rs.add_values(q, s, loc, comp, num(line, name, field(line, row, name)))
            return rs.finish()
    # A result table: stage, one location column, component columns.
    kinds = [k for k in ("node", "element", "gauge", "phase", "section") if k in cols]
    kind = kinds[0] if len(kinds) == 1 else ("stage" if not kinds else None)
    if kind is None:
        raise InputError(f"{path}:{header_line}: more than one location column "
                         f"({', '.join(kinds)}): one table per location kind")
    known, comp_cols = TABLE_COLUMNS[kind], []
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
                rs.add_values(q, s, loc, comp, num(line, name, row[k]))
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
    # (name, first column 0-based, width) of each field, as write_legacy_listing writes them
    fields = {"node": [("node", 0, 8), ("ux", 34, 13), ("uy", 47, 13)],
              "element": [("element", 0, 8), ("sxx", 13, 13), ("syy", 26, 13),
                          ("szz", 39, 13), ("sxy", 52, 13), ("s1", 65, 13), ("s3", 78, 13),
                          ("level", 99, 9)]}
    tables = {"NODAL POINT DISPLACEMENTS": "node", "ELEMENT STRESSES AT CENTROIDS": "element"}
    stage = table = None
    for n, line in enumerate(lines, start=1):
        m = re.match(r"1STAGE\s*(\d+)\s+(.*)$", line)
        if m:
            stage, table = int(m.group(1)), None
            rs.stage_names[stage] = m.group(2).strip()
            continue
        if not line.strip() or line.strip() in tables:
            table = tables.get(line.strip())        # a table ends at a blank line
            continue
        if table is None or line.lstrip().startswith(("NODE", "ELEM")):
            continue                    # stage lines, column headers
        values = {}
        for name, first, width in fields[table]:
            field = line[first:first + width].strip()
            where = f"{path}:{n}:{first + 1}-{first + width}"
            if name in ("node", "element"):
                if not field.isdigit():
                    raise InputError(f"{where}: {name} number expected, found '{field}'")
                loc = int(field)
            else:
                try:
                    values[name] = float(field)
                except ValueError:
                    raise InputError(f"{where}: field {name}: expected a number, "
                                     f"found '{field}'")
        if stage is None:
            raise InputError(f"{path}:{n}: a table row before the first STAGE line")
        pairs = [("displacement_total", c, c) for c in ("ux", "uy")] if table == "node" else \
            [("stress", c, c) for c in ("sxx", "syy", "szz", "sxy")] + \
            [("principal", c, c) for c in ("s1", "s3")] + [("stress_level", "level", "level")]
        for q, c, name in pairs:
            rs.add_values(q, stage, loc, c, values[name])
    return rs.finish()


def read_result_set(path, wanted=None):
    if not os.path.isfile(path):
        raise InputError(f"{path}: no such file")
    if path.endswith(".h5"):
        return read_h5(path, wanted)
    return read_legacy_listing(path) if path.endswith(".lst") else read_csv(path)


def parse_tolerance(text_, where):
    """'RTOL,ATOL' -> (rtol, atol, atol_is_scaled)."""
    parts = text_.split(",")
    if len(parts) != 2:
        raise InputError(f"{where}: expected RTOL,ATOL, found '{text_}'")
    try:
        scaled = parts[1].endswith("max")
        rtol, atol = float(parts[0]), float(parts[1][:-3] if scaled else parts[1])
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
    per_q, skipped = {}, set()
    common = [q for q in QUANTITIES if q in a.available and q in b.available
              and (not quantities or q in quantities)]
    for q in common:
        rtol, atol, scaled = tolerances.get(q, default)
        keys = sorted(k for k in a.blocks if k[0] == q)
        comps = [c for c in QUANTITIES[q][1]
                 if c in b.available[q] and any(c in a.blocks[k].components for k in keys)]
        for k in keys:
            skipped.update((q, c) for c in a.blocks[k].components if c not in comps)
        # Scale of the quantity in A: over all its components, but per component for the
        # counts (increments, iterations, ... are different things).
        scale = {}
        for c in comps:
            v = np.concatenate([a.blocks[k].values[:, a.blocks[k].components.index(c)]
                                for k in keys if c in a.blocks[k].components])
            v = v[np.isfinite(v)]
            scale[c] = float(np.abs(v).max()) if v.size else 0.0
        if q != "counts":
            scale = {c: max(scale.values(), default=0.0) for c in comps}
        stats = per_q.setdefault(q, {"count": 0, "fail": 0, "max_abs": 0.0, "max_rel": 0.0,
                                     "max_scaled": 0.0, "rtol": rtol, "atol": atol,
                                     "scaled": scaled, "scale": max(scale.values(), default=0.0)})
        for key in keys:
            blk_a, blk_b = a.blocks[key], b.blocks.get(key)
            index_b = {} if blk_b is None else {i: n for n, i in enumerate(blk_b.ids)}
            for c in (c for c in comps if c in blk_a.components):
                col_a = blk_a.values[:, blk_a.components.index(c)]
                col_b = blk_b.values[:, blk_b.components.index(c)] \
                    if blk_b is not None and c in blk_b.components else None
                found = []
                for n, i in enumerate(blk_a.ids):
                    if not math.isfinite(col_a[n]):
                        continue
                    m = index_b.get(i)
                    if m is None or col_b is None or not math.isfinite(col_b[m]):
                        missing.append((q, key[1], i, c))
                    else:
                        found.append((n, m))
                if not found:
                    continue
                na, nb = (np.array(x) for x in zip(*found))
                va, vb = col_a[na], col_b[nb]
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
                    stats["max_scaled"] = max(stats["max_scaled"], float(diff.max()) / scale[c])
                # Keep the worst few of each column for the ranking.
                rows += [(float(ratio[w]), q, key[1], blk_a.ids[na[w]], c, float(va[w]),
                          float(vb[w]), float(allowed[w]))
                         for w in np.argsort(-ratio, kind="stable")[:50]]
    rows.sort(key=lambda r: -r[0])
    return {"rows": rows, "missing": missing, "per_q": per_q,
            "only_a": sorted(set(a.available) - set(b.available)),
            "only_b": sorted(set(b.available) - set(a.available)), "skipped": sorted(skipped),
            "compared": sum(s["count"] for s in per_q.values())}


def stage_text(rs, stage):
    name = rs.stage_names.get(stage, "")
    return f"stage {stage}" + (f" ({name})" if name else "")


def print_report(report, a, b, worst, out=sys.stdout):
    def say(line):
        print(line, file=out)
    per_q = report["per_q"]
    failed = sum(s["fail"] for s in per_q.values())
    say(f"A (reference): {a.path}")
    say(f"B (compared):  {b.path}")
    bad = [r for r in report["rows"] if r[0] > 1]
    shown = bad[:worst] if bad else report["rows"][:worst]
    if shown:
        say(f"{'differences beyond tolerance, worst first' if bad else 'worst differences'} "
            f"(|B-A| / allowed, allowed = atol + rtol |A|):")
        say(f"  {'ratio':>9}  {'quantity':<18} {'component':<14} {'where':<16} "
            f"{'A':>16} {'B':>16} {'|B-A|':>10}  stage")
        for ratio, q, stage, loc, c, va, vb, allowed in shown:
            say(f"  {ratio:9.2e}  {q:<18} {c:<14} {location_text(q, loc):<16} "
                f"{va:16.9e} {vb:16.9e} {abs(vb - va):10.3e}  {stage_text(a, stage)}")
    for q, stage, loc, c in report["missing"][:worst]:
        say(f"  missing in B: {q} {c} at {location_text(q, loc)}, {stage_text(a, stage)}")
    if len(report["missing"]) > worst:
        say(f"  ... and {len(report['missing']) - worst} more missing")
    say("per quantity:")
    for q, s in per_q.items():
        atol = f"{s['atol']:g}*max|A| = {s['atol'] * s['scale']:.3g}" if s["scaled"] \
            else f"{s['atol']:g}"
        say(f"  {q:<18} {s['count']:8d} values, {s['fail']:6d} beyond, max |B-A| "
            f"{s['max_abs']:.2e}, /|A| {s['max_rel']:.2e}, /max|A| {s['max_scaled']:.2e} "
            f"(rtol {s['rtol']:g}, atol {atol})")
    for side in ("a", "b"):
        if report["only_" + side]:
            say(f"  only in {side.upper()} (not compared): {', '.join(report['only_' + side])}")
    if report["skipped"]:
        say("  components of A not in B (not compared): "
            + ", ".join(f"{q}/{c}" for q, c in report["skipped"]))
    ok = failed == 0 and not report["missing"] and report["compared"] > 0
    verdict = "AGREE" if ok else "DIFFER"
    say(f"{verdict}: nothing in common to compare" if report["compared"] == 0 else
        f"{verdict}: {report['compared']} values compared, {failed} beyond tolerance, "
        f"{len(report['missing'])} missing in B")
    return ok


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
        if (q not in per_stage and full_stages == "last" and s != last) or q == "principal" \
                or (quantities and q not in quantities):
            continue                    # principal: derived from the stresses
        blk = rs.blocks[(q, s)]
        tot = rs.blocks.get(("displacement_total", s))
        if q == "displacement" and tot is not None and tot.ids == blk.ids and \
                np.array_equal(tot.values, blk.values):
            continue
        lines += [f"{q},{s},{location_text(q, loc)},{c},{v:.12g}" for i, loc in enumerate(blk.ids)
                  for j, c in enumerate(blk.components) for v in [blk.values[i, j]]
                  if math.isfinite(v)]
    data = ("\n".join(lines) + "\n").encode()
    tmp = out + ".part"
    with open(tmp, "wb") as raw:
        if out.endswith(".gz"):
            # mtime 0: the same results give the same bytes (no spurious git changes).
            with gzip.GzipFile(fileobj=raw, mode="wb", mtime=0, filename="") as fh:
                fh.write(data)
        else:
            raw.write(data)
    os.replace(tmp, out)
    return len(lines) - 1 - len(header)


def main(argv=None):
    ap = argparse.ArgumentParser(description="Compare two cfrd result sets quantity by "
                                 "quantity.", epilog="Details: docs/results.md, section "
                                 "'Comparing results'.")
    ap.add_argument("a", help="reference: .h5, .csv, .csv.gz or .lst")
    ap.add_argument("b", help="compared result set (with --reduce: the output file)")
    ap.add_argument("--rtol", type=float, default=1e-9, help="relative tolerance (default 1e-9)")
    ap.add_argument("--atol", default="0", help="absolute tolerance: a number or Xmax (default 0)")
    ap.add_argument("--tol", action="append", default=[], metavar="QUANTITY=RTOL,ATOL",
                    help="tolerance of one quantity (repeatable)")
    ap.add_argument("--quantities", help="compare only these (comma-separated)")
    ap.add_argument("--worst", type=int, default=10, help="lines of differences shown")
    ap.add_argument("--reduce", action="store_true",
                    help="write the compact long-form reference of A (an .h5) to B")
    ap.add_argument("--all-stages", action="store_true",
                    help="with --reduce: fields at every stage, not only the last")
    args = ap.parse_args(argv)
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
        quantities = args.quantities.split(",") if args.quantities else None
        bad = [q for q in quantities or () if q not in QUANTITIES]
        if bad:
            raise InputError(f"--quantities: unknown {', '.join(bad)}")
        a = read_result_set(args.a)
        # Read from B only what A has (a full HDF5 file holds far more than a reference).
        b = read_result_set(args.b, set(a.blocks) if args.b.endswith(".h5") else None)
    except InputError as exc:
        print(f"compare: {exc}", file=sys.stderr)
        return 2
    return 0 if print_report(compare(a, b, tolerances, default, quantities), a, b,
                             args.worst) else 1


if __name__ == "__main__":
    sys.exit(main())
