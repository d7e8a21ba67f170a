#!/usr/bin/env python3
"""Checks of tools/compare.py (issue 8, section 4), run by make test:

  identical      a results file against a copy of itself agrees (exit 0);
  perturbed      a copy with one value changed (a displacement, a stress component, a gauge
                 settlement of the CSV) differs (exit 1), the report naming exactly that
                 quantity, stage, location and component, and nothing else;
  missing        a reference with a stage the other file lacks differs (exit 1);
  reduced        --reduce's long form agrees with its file to its 12 digits (rtol 1e-11);
  closed form    test/compare/column-closed-form.csv, the confined column's settlement typed
                 as a result table, agrees with inputs/column.dat to rtol 1e-9 (bilinear quads
                 are exact at its nodes); the table with one value mistyped differs there;
  legacy listing the listing of `cfrd --legacy-listing` agrees with the HDF5 file both ways to
                 its printed digits (rtol 5e-6, stress levels 5e-5) and with the closed form;
                 a copy with one stress changed is reported at that element and stage;
  regression     tools/regression.py fails on a reference with one value changed by 1e-6 of
                 itself, naming that quantity, node, stage and component;
  bad input      a table with a word for a number is rejected with file, line, column (exit 2).

    python3 tools/check_compare.py --cfrd CFRD --workdir DIR
"""

import csv
import gzip
import os
import re
import shutil
import subprocess
import sys

import h5py
import numpy as np

from cfrdtools.checks import Checks, fresh, parser
from cfrdtools.runner import tool

check = Checks("compare")


def beyond_rows(report):
    """(quantity, component, where, stage) of each line under 'differences beyond'."""
    rows, lines = [], iter(report.splitlines())
    for line in lines:
        if line.startswith("differences beyond tolerance"):
            break
    for line in lines:
        m = re.match(r"\s+[0-9.e+inf-]+\s+(\S+)\s+(\S+)\s+(\S+ \S+)\s+\S+\s+\S+\s+\S+\s+"
                     r"stage (\d+)", line)
        if m:
            rows.append((m.group(1), m.group(2), m.group(3), int(m.group(4))))
        elif not (line.startswith("  ") and "ratio" in line):
            break
    return rows


def last_line(report):
    return report.strip().splitlines()[-1]


def perturbed(name, ref, copy, expected, *options):
    status, report = tool("compare.py", ref, copy, *options)
    rows = beyond_rows(report)
    ok = status == 1 and rows == [expected]
    check(name, ok, f"exit {status} (expected 1), reported {rows} (expected [{expected}])"
          + ("" if ok else "\n" + report))


def edited(path, copy, edit):
    """A copy of a text file with edit(lines) applied; returns the copy."""
    lines = open(path).read().split("\n")
    edit(lines)
    open(copy, "w").write("\n".join(lines))
    return copy


def main():
    args = parser(__doc__, cfrd=True, workdir=True).parse_args()
    work = fresh(args.workdir)
    for deck in ("inputs/column.dat", "inputs/tianshengqiao-x1.dat"):
        proc = subprocess.run([args.cfrd, "--quiet", "--legacy-listing", "--results", "full",
                               "--out", work, deck],
                              capture_output=True, text=True)
        if proc.returncode != 0:
            check("setup", False, f"{deck}: cfrd exit {proc.returncode}: {proc.stderr[-300:]}")
            return 1
    x1, column = os.path.join(work, "tianshengqiao-x1.h5"), os.path.join(work, "column.h5")
    same = shutil.copyfile(x1, os.path.join(work, "same.h5"))
    status, report = tool("compare.py", x1, same, "--rtol", "0", "--atol", "0")
    check("identical", status == 0 and last_line(report).startswith("AGREE"),
          f"x1 results against a copy, rtol 0 atol 0: exit {status}, {last_line(report)}")
    # perturbed: one displacement, then one stress component, in copies of the file.
    with h5py.File(x1, "r") as f:
        u = f["stages/stage_0023/displacement_total"][...]
        gauges = set(f["gauges/nodes"][...])
    node = 300
    assert node not in gauges and node - 1 not in (np.argmin(u[:, 1]), np.argmax(u[:, 0]),
                                                    np.argmin(u[:, 0]))
    for name, dataset, index, change, expected in (
            ("perturbed-displacement", "stages/stage_0023/displacement_total", (node - 1, 1),
             lambda v: v + 1e-6, ("displacement_total", "uy", f"node {node}", 23)),
            ("perturbed-stress", "stages/stage_0040/stress_centroid", (199, 3),
             lambda v: v * 1.001, ("stress", "sxy", "element 200", 40))):
        copy = shutil.copyfile(x1, os.path.join(work, name + ".h5"))
        with h5py.File(copy, "r+") as f:
            f[dataset][index] = change(f[dataset][index])
        perturbed(name, x1, copy, expected, "--rtol", "1e-9")
    # perturbed CSV: one gauge settlement of the reference gauge table.
    gauges_csv = "outputs/tianshengqiao-x1-gauges.csv"
    with open(gauges_csv, newline="") as fh:
        rows = list(csv.reader(fh))
    head = next(i for i, r in enumerate(rows) if r and not r[0].startswith("#"))  # run id
    col = rows[head].index("C3-H4_settlement_m")
    row = next(r for r in rows[head + 1:] if r[0] == "30")
    row[col] = f"{float(row[col]) + 1e-4:.9E}"
    copy_csv = os.path.join(work, "perturbed-gauges.csv")
    with open(copy_csv, "w", newline="") as fh:
        csv.writer(fh).writerows(rows)
    perturbed("perturbed-gauge-csv", gauges_csv, copy_csv, ("gauge", "settlement",
                                                            "gauge C3-H4", 30), "--rtol", "1e-9")
    # missing: the reference has a stage more than the compared file.
    reduced = os.path.join(work, "x1-reduced.csv.gz")
    tool("compare.py", "--reduce", x1, reduced)
    with_extra = os.path.join(work, "extra-stage.csv")
    open(with_extra, "w").write("stage,node,ux,uy\n46,1,0,0\n")
    status, report = tool("compare.py", with_extra, x1)
    ok = status == 1 and "missing in B: displacement ux at node 1, stage 46" in report
    check("missing-stage", ok, f"a table with stage 46 against the 45-stage x1 file: exit "
          f"{status} (expected 1)" + ("" if ok else "\n" + report))
    # reduced: the long form agrees with its source.
    status, report = tool("compare.py", reduced, x1, "--rtol", "1e-11", "--atol", "1e-11max")
    check("reduced", status == 0, f"--reduce of x1 against x1, rtol 1e-11: exit {status}, "
          f"{last_line(report)}, {os.path.getsize(reduced)} bytes")
    # closed form typed as a table, then one value mistyped (its last two digits swapped).
    table = "test/compare/column-closed-form.csv"
    status, report = tool("compare.py", table, column, "--rtol", "1e-9", "--atol", "1e-15")
    check("closed-form-table", status == 0, f"{table} against inputs/column.dat, rtol 1e-9: "
          f"exit {status}, {last_line(report)}")

    def typo(lines):
        k = next(i for i, ln in enumerate(lines) if ln.startswith("1,15,"))
        value = lines[k].split(",")[3]
        lines[k] = "1,15,0," + value[:-2] + value[-1] + value[-2]
        assert lines[k] != "1,15,0," + value
    perturbed("mistyped-table", edited(table, os.path.join(work, "column-typo.csv"), typo),
              column, ("displacement", "uy", "node 15", 1), "--rtol", "1e-9", "--atol", "1e-15")
    # The legacy-style listing holds what the HDF5 file holds, to its printed digits (6
    # significant: rtol 5e-6; stress levels 4 decimals: 5e-5), both ways round: every placed
    # node and active element at every stage (x1 has no joints, which it leaves out).
    lst = os.path.join(work, "tianshengqiao-x1.lst")
    printed = ["--rtol", "5e-6", "--tol", "stress_level=0,5e-5"]
    status, report = tool("compare.py", lst, x1, *printed)
    status2, report2 = tool("compare.py", x1, lst, *printed, "--quantities",
                            "displacement_total,stress,principal,stress_level")
    check("legacy-listing", status == 0 and status2 == 0, f"x1 .lst against .h5: "
          f"{last_line(report)}; .h5 against .lst: {last_line(report2)}")
    # The listing prints displacements since placement: the same table, so named.
    total = os.path.join(work, "column-closed-form-total.csv")
    open(total, "w").write(open(table).read().replace("stage,node,ux,uy",
                                                      "stage,node,ux_total,uy_total"))
    status, report = tool("compare.py", total, os.path.join(work, "column.lst"), "--rtol", "5e-6")
    check("legacy-listing-closed-form", status == 0, f"{table} against column.lst, rtol 5e-6 "
          f"(its 6 printed digits): exit {status}, {last_line(report)}")

    def stress(text):
        start = text.index(next(ln for ln in text if ln.startswith("1STAGE   30 ")))
        start = next(i for i in range(start, len(text))
                     if text[i].strip() == "ELEMENT STRESSES AT CENTROIDS")
        k = next(i for i in range(start, len(text)) if text[i].startswith("     250 "))
        text[k] = text[k][:26] + f"{float(text[k][26:39]) * 1.01:13.5E}" + text[k][39:]
    perturbed("perturbed-legacy-listing", lst, edited(lst, os.path.join(work, "perturbed.lst"),
                                                      stress),
              ("stress", "syy", "element 250", 30), "--rtol", "5e-6")
    # The regression suite fails on a reference with one value changed, and says where.
    refdir = os.path.join(work, "references")
    os.makedirs(refdir)
    with gzip.open("outputs/reference/example.csv.gz", "rt") as fh:
        lines = fh.read().splitlines()
    k = next(i for i, ln in enumerate(lines) if ln.startswith("displacement_total,1,node 7,uy,"))
    value = float(lines[k].rsplit(",", 1)[1])
    lines[k] = f"displacement_total,1,node 7,uy,{value * (1 + 1e-6):.12g}"
    with gzip.open(os.path.join(refdir, "example.csv.gz"), "wt") as fh:
        fh.write("\n".join(lines) + "\n")
    status, out = tool("regression.py", "--cfrd", args.cfrd, "--workdir",
                       os.path.join(work, "regression"), "--references", refdir,
                       "inputs/example.dat")
    out = out.strip()
    expected = "FAIL regression/example: 1 of 79 values beyond the elastic tolerances; " \
        "worst displacement_total uy at node 7, stage 1"
    check("regression-detects-change", status == 1 and out.startswith(expected),
          f"example's reference with uy of node 7 changed by 1e-6 of itself: exit {status} "
          f"(expected 1): {out[:200]}")
    bad = os.path.join(work, "bad.csv")
    open(bad, "w").write("# typed from a listing\nstage,node,ux,uy\n1,3,0,-7.05E-03\n"
                         "1,4,0,minus\n")
    status, report = tool("compare.py", bad, column)
    check("bad-input", status == 2 and f"{bad}:4: column uy: expected a number, found 'minus'"
          in report, f"exit {status} (expected 2), message: {report.strip()}")
    return check.status


if __name__ == "__main__":
    sys.exit(main())
