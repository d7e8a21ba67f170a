#!/usr/bin/env python3
"""Checks of the batch runner, the parametric studies and their Slurm job arrays (issue 8,
section 3), run by make test:

  batch      three good decks and a bad one: the bad one fails with its message in its log,
             the others run (listing, HDF5, log), exit status 1 (the failed decks); the
             column's settlement is gamma H^2 / (2M) (1e-9), the triaxial test has 11
             stages; three bad decks: exit 3; two decks of one name (also from two folders,
             both named, nothing run) or --out naming a file: 101; a missing --out is made;
  stop       SIGTERM to a batch of two decks run one at a time once the first has written a
             stage: exit 143, the first "stopped (SIGTERM)" with its stages in
             DECK.incomplete.h5 and no .part file, the second "not run", the summary written
             (tools/check_stop.py checks the stages);
  parallel   --jobs 2 runs two decks at once (a stand-in program waits for the other deck to
             start, and fails after 30 s alone); --jobs 1 never two;
  study      test/study/column.dat over four cases of E and NU: each settlement
             gamma H^2 / (2M) (1e-9); a template expanded with its source deck's values is that
             deck but its comments (the column, and inputs/studies/tianshengqiao-joint.dat);
             a value wider than its field, a column that is no placeholder, a missing column
             and a value that is no number: exit 2, the message naming file, line, columns;
  slurm      the --slurm script passes `bash -n`, has a task per case and its output folder,
             refuses to run outside Slurm, and run as Slurm runs its tasks gives the results
             that --collect turns into the same closed-form table (make slurm-check runs it
             on a real cluster).

    python3 tools/check_batch.py --cfrd CFRD --workdir DIR
"""

import csv
import glob
import os
import shutil
import signal
import subprocess
import sys

import h5py

from cfrdtools.checks import Checks, fresh, parser
from cfrdtools.runner import TOOLS, signal_when, tool

GAMMA, HEIGHT = 20.0, 10.0          # inputs/column.dat
check = Checks()


def settlement_error(row):
    """Relative error of a summary row's settlement against gamma H^2 / (2M)."""
    e, nu = float(row["E"]) if "E" in row else 20000.0, float(row["NU"]) if "NU" in row else 0.3
    expected = GAMMA * HEIGHT ** 2 / (2 * e * (1 - nu) / ((1 + nu) * (1 - 2 * nu)))
    return abs(float(row["max_settlement_m"]) - expected) / expected if row["status"] == "ok" \
        else float("inf"), expected


def read_rows(path):
    if not os.path.isfile(path):
        return []
    with open(path, newline="") as fh:
        return list(csv.DictReader(fh))


def check_batch(cfrd, work):
    out = os.path.join(work, "batch")
    decks = ["inputs/column.dat", "test/bad_decks/13-negative-modulus.dat", "inputs/example.dat",
             "inputs/triaxial-iiib.dat"]
    status, text = tool("batch.py", "--cfrd", cfrd, "--out", out, *decks)
    rows = {r["deck"]: r for r in read_rows(os.path.join(out, "batch-summary.csv"))}
    statuses = [rows.get(d, {}).get("status") for d in decks]
    files_ok = all(os.path.isfile(os.path.join(out, s + x)) for s in ("column", "example",
                                                                      "triaxial-iiib")
                   for x in (".out", ".h5", ".log"))
    log = os.path.join(out, "13-negative-modulus.log")
    logged = os.path.isfile(log) and "field E of MATERIALS 1" in open(log).read()
    ok = status == 1 and statuses == ["ok", "bad input", "ok", "ok"] and files_ok and logged \
        and not os.path.exists(log[:-4] + ".h5")
    if not check("batch/one-bad-deck", ok, f"exit {status} (expected 1: one failed), statuses "
                 f"{statuses}, listing/HDF5/log of each good deck: {files_ok}, the bad deck's "
                 f"message in its log: {logged}" + ("" if ok else text)):
        return
    column = rows["inputs/column.dat"]
    err, expected = settlement_error(column)
    stages = rows["inputs/triaxial-iiib.dat"]["stages"]
    check("batch/summary", err <= 1e-9 and column["max_settlement_node"] in ("21", "22")
          and stages == "11", f"column max settlement {float(column['max_settlement_m']):.12g} "
          f"m at node {column['max_settlement_node']} vs gamma H^2/(2M) = {expected:.12g} (rel. "
          f"error {err:.1e}, tol 1e-9); triaxial stages {stages} (expected 11)")
    status, text = tool("batch.py", "--quiet", "--cfrd", cfrd, "--out", os.path.join(
        work, "batch3"), *(f"test/bad_decks/{d}.dat" for d in (
            "13-negative-modulus", "14-poisson-half", "07-no-end")), "inputs/example.dat")
    check("batch/exit-status-counts", status == 3,
          f"three bad decks and a good one: exit {status} (expected 3)")
    status, text = tool("batch.py", "--cfrd", cfrd, "--out", os.path.join(work, "batch-dup"),
                        "inputs/example.dat", "test/study/../../inputs/example.dat")
    check("batch/same-name", status == 101 and "would both write example.out" in text,
          f"two decks named example: exit {status} (expected 101): {text.strip()}")
    decks = [os.path.join(work, "names", f, "col.dat") for f in ("a", "b")]
    for deck in decks:
        os.makedirs(os.path.dirname(deck))
        shutil.copy("inputs/example.dat", deck)
    same = os.path.join(work, "names", "same")
    status, text = tool("batch.py", "--cfrd", cfrd, "--out", same, *decks)
    check("batch/same-name-two-folders", status == 101 and not os.path.exists(same) and
          f"{decks[0]} and {decks[1]} would both write" in text, f"col.dat from two folders into"
          f" one --out: exit {status} (expected 101), nothing run: {not os.path.exists(same)}: "
          f"{text.strip()}")
    a_file = os.path.join(work, "names", "a-file")
    open(a_file, "w").close()
    status, text = tool("batch.py", "--cfrd", cfrd, "--out", a_file, decks[0])
    check("batch/out-is-a-file", status == 101 and "a file of that name exists" in text,
          f"--out naming a file: exit {status} (expected 101): {text.strip()[-200:]}")
    deep = os.path.join(work, "names", "new", "deep")
    status, text = tool("batch.py", "--quiet", "--cfrd", cfrd, "--out", deep, decks[0])
    made = os.path.exists(os.path.join(deep, "col.h5"))
    check("batch/out-creates-folder", status == 0 and made and os.path.getsize(
        os.path.join(deep, "col.h5")) > 0, f"a missing --out folder: exit {status}, col.h5 in "
          f"it: {made}")


def check_stop(cfrd, work):
    """SIGTERM to the batch once its first deck has written a stage."""
    out = os.path.join(work, "stop")
    first, second = "inputs/tianshengqiao-x2.dat", "inputs/example.dat"
    status, text, sent = signal_when(
        [sys.executable, os.path.join(TOOLS, "batch.py"), "--cfrd", cfrd, "--jobs", "1", "--out",
         out, first, second], os.path.join(out, "tianshengqiao-x2.log"), "stage 2/",
        signal.SIGTERM, os.path.join(work, "stop.txt"))
    rows = {r["deck"]: r for r in read_rows(os.path.join(out, "batch-summary.csv"))}
    incomplete, stages = os.path.join(out, "tianshengqiao-x2.incomplete.h5"), 0
    if os.path.exists(incomplete):
        with h5py.File(incomplete, "r") as f:
            stages = len(f["stages"]) if f.attrs["complete"] == 0 else -1
    parts = glob.glob(os.path.join(out, "*.part"))
    statuses = {d: rows.get(d, {}).get("status") for d in (first, second)}
    ok = sent and status == 143 and statuses == {
        first: "stopped (SIGTERM)", second: "not run"} and stages >= 1 and not parts and \
        not os.path.exists(os.path.join(out, "example.h5"))
    check("batch/sigterm", ok, f"exit {status} (expected 143), summary statuses "
          f"{statuses}, {stages} stages in tianshengqiao-x2.incomplete.h5 (expected >= 1), .part"
          f" files left: {parts or 'none'}" + ("" if ok else "\n" + text[-500:]))


# Stands in for cfrd (--out DIR DECK): notes its start, then waits (at most 30 s) until the
# other deck has started too, and records how many ran at once.
FAKE_CFRD = """#!/usr/bin/env bash
out=$2; stem=$(basename "$3" .dat); mode=$(cat "$out/mode")
mkdir "$out/running-$stem" "$out/started-$stem"
ls -d "$out"/running-* | wc -l >>"$out/at-once"
# started-* are never removed: a count of them cannot miss a deck that finished meanwhile
started() { ls -d "$out"/started-* 2>/dev/null | wc -l; }
if [[ $mode == barrier ]]; then
    met=0
    for i in $(seq 300); do [[ $(started) -ge 2 ]] && { met=1; break; }; sleep 0.1; done
    [[ $met == 1 ]] || { echo "cfrd: the other deck did not start"; exit 1; }
else
    sleep 0.2
fi
rmdir "$out/running-$stem"
"""


def check_parallel(work):
    out = os.path.join(work, "parallel")
    fake = os.path.join(work, "fake-cfrd")
    with open(fake, "w") as fh:
        fh.write(FAKE_CFRD)
    os.chmod(fake, 0o755)
    decks = ["inputs/column.dat", "inputs/example.dat"]
    for mode, jobs, name in (("barrier", "2", "batch/parallel"), ("count", "1", "batch/jobs-1")):
        fresh(out)
        open(os.path.join(out, "mode"), "w").write(mode)
        status, text = tool("batch.py", "--quiet", "--jobs", jobs, "--cfrd", fake, "--out", out,
                            *decks, *(["inputs/triaxial-iiib.dat"] if mode == "count" else []))
        at = os.path.join(out, "at-once")
        at_once = [int(x) for x in open(at).read().split()] if os.path.isfile(at) else []
        if mode == "barrier":
            check(name, status == 0, f"--jobs 2: both decks started before either finished "
                  f"(exit {status}, expected 0; processes at once: {at_once})")
        else:
            check(name, status == 0 and at_once == [1, 1, 1], f"--jobs 1: processes at once "
                  f"{at_once} (expected [1, 1, 1]), exit {status}")


def same_but_comments(expanded, source):
    """The expanded deck is the source deck, line for line, apart from comment cards."""
    a, b = ([ln for ln in open(p).read().split("\n") if not ln.startswith("*")]
            for p in (expanded, source))
    return a == b


def check_study(cfrd, work):
    sdir = os.path.join(work, "study")
    status, text = tool("study.py", "test/study/column.dat", "--dir", sdir, "--cfrd", cfrd)
    rows = read_rows(os.path.join(sdir, "study-results.csv"))
    worst = max((settlement_error(r)[0] for r in rows), default=0.0)
    png = os.path.join(sdir, "study-response.png")
    ok = status == 0 and len(rows) == 4 and worst <= 1e-9 and os.path.getsize(png) > 10000
    check("study/closed-form", ok, f"4 cases of E x NU: settlements "
          + ", ".join(f"{r['case']} {float(r['max_settlement_m']):.6f}" for r in rows
                      if r["status"] == "ok") + f" m against gamma H^2/(2M): max rel. error "
          f"{worst:.1e} (tol 1e-9); exit {status}; {png} written" + ("" if ok else "\n" + text))
    base = os.path.join(sdir, "decks", "column-soft-0.3.dat")
    check("study/expansion", os.path.isfile(base) and same_but_comments(base, "inputs/column.dat"),
          f"{base} (E 20000.0, NU 0.3) is inputs/column.dat but its comment cards")
    # The shipped example: its template is the joint deck with three placeholders.
    jdir, table = os.path.join(work, "study-joint"), os.path.join(work, "joint-base.csv")
    open(table, "w").write("case,KNT,KB,PHI\nbase,10000.0,204.0,30.0\n")
    status, text = tool("study.py", "inputs/studies/tianshengqiao-joint.dat", "--table", table,
                        "--dir", jdir, "--expand-only")
    deck = os.path.join(jdir, "decks", "tianshengqiao-joint-base.dat")
    ok = status == 0 and os.path.isfile(deck) and same_but_comments(
        deck, "inputs/tianshengqiao-x1-joint.dat")
    check("study/joint-template", ok, "inputs/studies/tianshengqiao-joint.dat with KNT 10000.0, "
          "KB 204.0, PHI 30.0 is inputs/tianshengqiao-x1-joint.dat but its comment cards"
          + ("" if ok else f" (exit {status}) {text}"))
    for name, table_text, expected in (
            ("misfit", "case,E,NU\nok,20000.0,0.3\nwide,200000000.0,0.3\n",
             "test/study/column.dat:22:1-10: field {E} is 10 columns wide; the value "
             "'200000000.0' of case wide ({t}:3, column E) has 11 characters"),
            ("unknown-column", "case,E,NU,KB\nok,20000.0,0.3,200\n",
             "column 4 'KB' is not a placeholder of test/study/column.dat"),
            ("missing-column", "case,E\nok,20000.0\n",
             "no column for the placeholder {NU} of test/study/column.dat"),
            ("not-a-number", "case,E,NU\nok,20000.0,0.3\ntypo,20000..0,0.3\n",
             "column-typo.dat:22:1-10: field E of MATERIALS 1: expected a real number, found "
             "'20000..0' (case typo, {t}:3)")):
        t = os.path.join(work, f"{name}.csv")
        open(t, "w").write(table_text)
        status, text = tool("study.py", "test/study/column.dat", "--table", t, "--dir",
                            os.path.join(work, name), "--cfrd", cfrd)
        check(f"study/{name}", status == 2 and expected.replace("{t}", t) in text,
              f"exit {status} (expected 2): {text.strip().splitlines()[-1]}")


def check_slurm(cfrd, work):
    sdir = os.path.join(work, "slurm")
    status, text = tool("study.py", "test/study/column.dat", "--dir", sdir, "--cfrd", cfrd,
                        "--slurm", "--sbatch=--time=00:05:00")
    script = os.path.join(sdir, "study.slurm")
    if status != 0 or not os.path.isfile(script):
        check("slurm/script", False, f"--slurm: exit {status}: {text}")
        return
    body = open(script).read()
    decks = open(os.path.join(sdir, "decks.txt")).read().split()
    syntax = subprocess.run(["bash", "-n", script], capture_output=True, text=True)
    ok = (syntax.returncode == 0 and "#SBATCH --array=1-4\n" in body
          and "#SBATCH --time=00:05:00\n" in body and len(decks) == 4
          and all(os.path.isfile(d) and os.path.isabs(d) for d in decks)
          and f"exec {os.path.abspath(cfrd)} --out {os.path.abspath(sdir)}/results" in body
          # Slurm opens the tasks' output files there before they run.
          and os.path.isdir(os.path.join(sdir, "results")))
    check("slurm/script", ok, f"bash -n: {syntax.returncode}, #SBATCH --array=1-4 and --time: "
          f"{'#SBATCH --array=1-4' in body}, decks.txt: {len(decks)} decks (expected 4, "
          f"absolute paths), runs {os.path.abspath(cfrd)} into {os.path.abspath(sdir)}/results "
          f"(made before submission)" + ("" if ok else "\n" + body))
    env = {k: v for k, v in os.environ.items() if not k.startswith("SLURM_")}
    outside = subprocess.run(["bash", script], capture_output=True, text=True, env=env)
    check("slurm/outside-slurm", outside.returncode != 0 and "run this script with sbatch"
          in outside.stderr, f"without SLURM_ARRAY_TASK_ID: exit {outside.returncode}, "
          f"{outside.stderr.strip()}")
    codes = [subprocess.run(["bash", script], capture_output=True, text=True, env=dict(
        env, SLURM_ARRAY_TASK_ID=str(task))).returncode for task in range(1, 5)]
    status, text = tool("study.py", "test/study/column.dat", "--dir", sdir, "--collect")
    rows = read_rows(os.path.join(sdir, "study-results.csv"))
    worst = max(settlement_error(r)[0] for r in rows) if rows else float("inf")
    check("slurm/array-tasks", codes == [0, 0, 0, 0] and status == 0 and len(rows) == 4
          and worst <= 1e-9, f"tasks 1-4 run as Slurm runs them: exit statuses {codes}; "
          f"--collect: exit {status}, 4 cases, max rel. error against gamma H^2/(2M) "
          f"{worst:.1e} (tol 1e-9)" + ("" if worst <= 1e-9 and status == 0 else "\n" + text))


def main():
    args = parser(__doc__, cfrd=True, workdir=True).parse_args()
    work = fresh(args.workdir)
    check_batch(args.cfrd, work)
    check_stop(args.cfrd, work)
    check_parallel(work)
    check_study(args.cfrd, work)
    check_slurm(args.cfrd, work)
    return check.status


if __name__ == "__main__":
    sys.exit(main())
