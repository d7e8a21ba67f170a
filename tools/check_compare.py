#!/usr/bin/env python3
"""Checks of tools/compare.py (issue 8, section 4), run by make test:

  identical      a results file compared with a copy of itself agrees (exit 0);
  perturbed      a copy with one value changed (a displacement at one node and stage, a
                 stress component of one element, a gauge settlement in the CSV) differs
                 (exit 1), and the report names exactly that quantity, stage, node or
                 element or gauge, and component, and nothing else;
  missing        a reference with a stage the other file lacks differs (exit 1);
  reduced        the compact long-form reference written by --reduce agrees with the file
                 it was made from (to its 12 digits: rtol 1e-11);
  closed form    test/compare/column-closed-form.csv, the confined column's settlement
                 typed as a result table, agrees with a run of inputs/column.dat to
                 rtol 1e-9 (bilinear quads are exact at its nodes); the same table with one
                 value mistyped differs at that node;
  legacy listing the listing of `cfrd --legacy-listing` agrees with the HDF5 file both ways
                 to its printed digits (rtol 5e-6, stress levels 5e-5) and with the closed
                 form; a copy with one stress changed is reported at that element and stage;
  regression     tools/regression.py fails on a reference with one value changed by 1e-6
                 of itself, naming that quantity, node, stage and component;
  bad input      a table with a word for a number is rejected with its file, line and
                 column (exit 2).

    python3 tools/check_compare.py --cfrd CFRD --workdir DIR

Prints one PASS/FAIL line per check; exit status 1 if any failed.
"""

import argparse
import csv
import gzip
import os
import re
import shutil
import subprocess
import sys

import h5py
import numpy as np

TOOLS = os.path.dirname(os.path.abspath(__file__))
COMPARE = os.path.join(TOOLS, "compare.py")
failures = 0


def verdict(ok, name, detail):
    global failures
    print(f"{'PASS' if ok else 'FAIL'} compare/{name}: {detail}")
    failures += not ok


def run_compare(*args):
    proc = subprocess.run([sys.executable, COMPARE, *args], capture_output=True, text=True)
    return proc.returncode, proc.stdout + proc.stderr


def beyond_rows(report):
    """(quantity, component, where, stage) of each line under 'differences beyond'."""
    rows, inside = [], False
    for line in report.splitlines():
        if line.startswith("differences beyond tolerance"):
            inside = True
            continue
        if inside:
            m = re.match(r"\s+[0-9.e+inf-]+\s+(\S+)\s+(\S+)\s+(\S+ \S+)\s+\S+\s+\S+\s+\S+\s+"
                         r"stage (\d+)", line)
            if not m:
                if line.startswith("  ") and "ratio" in line:
                    continue
                break
            rows.append((m.group(1), m.group(2), m.group(3), int(m.group(4))))
    return rows


def check_perturbed(name, ref, copy, expected, *options):
    status, report = run_compare(ref, copy, *options)
    rows = beyond_rows(report)
    ok = status == 1 and rows == [expected]
    verdict(ok, name, f"exit {status} (expected 1), reported {rows} (expected [{expected}])"
            + ("" if ok else "\n" + report))


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--cfrd", required=True)
    parser.add_argument("--workdir", required=True)
    args = parser.parse_args()
    work = args.workdir
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    for deck in ("inputs/column.dat", "inputs/tianshengqiao-x1.dat"):
        proc = subprocess.run([args.cfrd, "--quiet", "--legacy-listing", "--out", work, deck],
                              capture_output=True, text=True)
        if proc.returncode != 0:
            verdict(False, "setup", f"{deck}: cfrd exit {proc.returncode}: {proc.stderr[-300:]}")
            return 1
    x1 = os.path.join(work, "tianshengqiao-x1.h5")

    # identical
    same = os.path.join(work, "same.h5")
    shutil.copyfile(x1, same)
    status, report = run_compare(x1, same, "--rtol", "0", "--atol", "0")
    last = report.strip().splitlines()[-1]
    verdict(status == 0 and last.startswith("AGREE"), "identical",
            f"x1 results against a copy, rtol 0 atol 0: exit {status}, {last}")

    # perturbed: one displacement, then one stress component, in copies of the file.
    with h5py.File(x1, "r") as f:
        u = f["stages/stage_0023/displacement_total"][...]
        gauges = set(f["gauges/nodes"][...])
    node = 300
    assert node not in gauges and node - 1 not in (np.argmin(u[:, 1]), np.argmax(u[:, 0]),
                                                    np.argmin(u[:, 0]))
    one = os.path.join(work, "perturbed-displacement.h5")
    shutil.copyfile(x1, one)
    with h5py.File(one, "r+") as f:
        f["stages/stage_0023/displacement_total"][node - 1, 1] += 1e-6
    check_perturbed("perturbed-displacement", x1, one,
                    ("displacement_total", "uy", f"node {node}", 23), "--rtol", "1e-9")
    two = os.path.join(work, "perturbed-stress.h5")
    shutil.copyfile(x1, two)
    with h5py.File(two, "r+") as f:
        f["stages/stage_0040/stress_centroid"][199, 3] *= 1.001
    check_perturbed("perturbed-stress", x1, two, ("stress", "sxy", "element 200", 40),
                    "--rtol", "1e-9")

    # perturbed CSV: one gauge settlement of the reference gauge table.
    gauges_csv = "outputs/tianshengqiao-x1-gauges.csv"
    with open(gauges_csv, newline="") as fh:
        rows = list(csv.reader(fh))
    col = rows[0].index("C3-H4_settlement_m")
    row = next(r for r in rows if r[0] == "30")
    row[col] = f"{float(row[col]) + 1e-4:.9E}"
    copy_csv = os.path.join(work, "perturbed-gauges.csv")
    with open(copy_csv, "w", newline="") as fh:
        csv.writer(fh).writerows(rows)
    check_perturbed("perturbed-gauge-csv", gauges_csv, copy_csv,
                    ("gauge", "settlement", "gauge C3-H4", 30), "--rtol", "1e-9")

    # missing: the reference has a stage more than the compared file.
    reduced = os.path.join(work, "x1-reduced.csv.gz")
    status, report = run_compare("--reduce", x1, reduced)
    with_extra = os.path.join(work, "extra-stage.csv")
    with open(with_extra, "w") as fh:
        fh.write("stage,node,ux,uy\n46,1,0,0\n")
    status, report = run_compare(with_extra, x1)
    ok = status == 1 and "missing in B: displacement ux at node 1, stage 46" in report
    verdict(ok, "missing-stage", f"a table with stage 46 against the 45-stage x1 file: exit "
            f"{status} (expected 1)" + ("" if ok else "\n" + report))

    # reduced: the long form agrees with its source.
    status, report = run_compare(reduced, x1, "--rtol", "1e-11", "--atol", "1e-11max")
    last = report.strip().splitlines()[-1]
    verdict(status == 0, "reduced", f"--reduce of x1 against x1, rtol 1e-11: exit {status}, "
            f"{last}, {os.path.getsize(reduced)} bytes")

    # closed form typed as a table, then one value mistyped.
    table = "test/compare/column-closed-form.csv"
    column = os.path.join(work, "column.h5")
    status, report = run_compare(table, column, "--rtol", "1e-9", "--atol", "1e-15")
    last = report.strip().splitlines()[-1]
    verdict(status == 0, "closed-form-table", f"{table} against inputs/column.dat, rtol "
            f"1e-9: exit {status}, {last}")
    typo = os.path.join(work, "column-typo.csv")
    lines = open(table).read().splitlines()
    k = next(i for i, l in enumerate(lines) if l.startswith("1,15,"))
    value = lines[k].split(",")[3]
    lines[k] = "1,15,0," + value[:-2] + value[-1] + value[-2]   # the last two digits swapped
    assert lines[k] != "1,15,0," + value
    open(typo, "w").write("\n".join(lines) + "\n")
    check_perturbed("mistyped-table", typo, column, ("displacement", "uy", "node 15", 1),
                    "--rtol", "1e-9", "--atol", "1e-15")

    # The legacy-style listing holds what the HDF5 file holds, to its printed digits
    # (6 significant: rtol 5e-6; stress levels 4 decimals: 5e-5), both ways round: every
    # placed node and active element at every stage (x1 has no joints, which it leaves out).
    lst = os.path.join(work, "tianshengqiao-x1.lst")
    printed = ["--rtol", "5e-6", "--tol", "stress_level=0,5e-5"]
    status, report = run_compare(lst, x1, *printed)
    last = report.strip().splitlines()[-1]
    status2, report2 = run_compare(x1, lst, *printed, "--quantities",
                                   "displacement_total,stress,principal,stress_level")
    last2 = report2.strip().splitlines()[-1]
    verdict(status == 0 and status2 == 0, "legacy-listing",
            f"x1 .lst against .h5: {last}; .h5 against .lst: {last2}")
    # The listing prints displacements since placement: the same table, so named.
    total = os.path.join(work, "column-closed-form-total.csv")
    open(total, "w").write(open(table).read().replace("stage,node,ux,uy",
                                                      "stage,node,ux_total,uy_total"))
    status, report = run_compare(total, os.path.join(work, "column.lst"), "--rtol", "5e-6")
    verdict(status == 0, "legacy-listing-closed-form", f"{table} against column.lst, rtol "
            f"5e-6 (its 6 printed digits): exit {status}, {report.strip().splitlines()[-1]}")
    text = open(lst).read().split("\n")
    start = text.index(next(l for l in text if l.startswith("1STAGE   30 ")))
    start = next(i for i in range(start, len(text))
                 if text[i].strip() == "ELEMENT STRESSES AT CENTROIDS")
    k = next(i for i in range(start, len(text)) if text[i].startswith("     250 "))
    text[k] = text[k][:26] + f"{float(text[k][26:39]) * 1.01:13.5E}" + text[k][39:]
    bad_lst = os.path.join(work, "perturbed.lst")
    open(bad_lst, "w").write("\n".join(text))
    check_perturbed("perturbed-legacy-listing", lst, bad_lst,
                    ("stress", "syy", "element 250", 30), "--rtol", "5e-6")

    # The regression suite fails on a reference with one value changed, and says where.
    refdir = os.path.join(work, "references")
    os.makedirs(refdir)
    with gzip.open("outputs/reference/example.csv.gz", "rt") as fh:
        lines = fh.read().splitlines()
    k = next(i for i, l in enumerate(lines)
             if l.startswith("displacement_total,1,node 7,uy,"))
    value = float(lines[k].rsplit(",", 1)[1])
    lines[k] = f"displacement_total,1,node 7,uy,{value * (1 + 1e-6):.12g}"
    with gzip.open(os.path.join(refdir, "example.csv.gz"), "wt") as fh:
        fh.write("\n".join(lines) + "\n")
    proc = subprocess.run([sys.executable, os.path.join(TOOLS, "regression.py"), "--cfrd",
                           args.cfrd, "--workdir", os.path.join(work, "regression"),
                           "--references", refdir, "inputs/example.dat"],
                          capture_output=True, text=True)
    out = proc.stdout.strip()
    expected = "FAIL regression/example: 1 of 79 values beyond the elastic tolerances; " \
        "worst displacement_total uy at node 7, stage 1"
    verdict(proc.returncode == 1 and out.startswith(expected), "regression-detects-change",
            f"example's reference with uy of node 7 changed by 1e-6 of itself: exit "
            f"{proc.returncode} (expected 1): {out[:200]}")

    # bad input
    bad = os.path.join(work, "bad.csv")
    open(bad, "w").write("# typed from a listing\nstage,node,ux,uy\n1,3,0,-7.05E-03\n"
                         "1,4,0,minus\n")
    status, report = run_compare(bad, column)
    expected = f"{bad}:4: column uy: expected a number, found 'minus'"
    verdict(status == 2 and expected in report, "bad-input",
            f"exit {status} (expected 2), message: {report.strip()}")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
