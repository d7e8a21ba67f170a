#!/usr/bin/env python3
"""Checks of the batch runner, the parametric studies and their Slurm job arrays (issue 8,
section 3), run by make test:

  batch      three good decks and a bad one: the bad one fails with its message in its
             log, the others run (listing, HDF5 file, log each), the exit status is the
             number of failed decks (1), the summary's settlement of the column is its
             closed form gamma H^2 / (2M) (1e-9) and the triaxial test has its 11 stages;
             three bad decks give exit status 3; two decks of the same name, 101 (also
             from two folders: the message names both, nothing is run); --out naming a
             file, 101; a missing --out folder is created;
  stop       SIGTERM to a batch of two decks run one at a time, once the first has
             written a stage: exit status 143, the first deck "stopped (SIGTERM)" with
             its completed stages in DECK.incomplete.h5 and no .part file, the second
             "not run", the summary CSV written (tools/check_stop.py checks the stages);
  parallel   with --jobs 2 two decks run at the same time (a stand-in program waits for
             the other deck to start: run one after the other, it would give up after
             30 s and fail); with --jobs 1 never two at once;
  study      the column template (test/study/column.dat, E and NU as placeholders) over
             four cases: each case's settlement is gamma H^2 / (2M) with that case's E and
             NU (1e-9); the expansion of a template with the values of its source deck
             gives that deck again, line for line but the study's comment cards (the
             column, and inputs/studies/tianshengqiao-joint.dat against
             inputs/tianshengqiao-x1-joint.dat); a value wider than its field, a column
             that is no placeholder, a missing column and a value that is no number are
             each rejected with exit status 2 and a message naming file, line and columns;
  slurm      the job array script written by --slurm passes `bash -n`, has one task per
             case (#SBATCH --array=1-4, decks.txt of four decks), its output folder exists
             before submission (Slurm opens the tasks' output files there), refuses to run
             outside Slurm, and, run as Slurm would run its tasks (SLURM_ARRAY_TASK_ID=1..4),
             gives the results that --collect turns into the same closed-form table (a real
             cluster runs it in make slurm-check).

    python3 tools/check_batch.py --cfrd CFRD --workdir DIR

Prints one PASS/FAIL line per check; exit status 1 if any failed.
"""

import argparse
import csv
import glob
import os
import shutil
import signal
import subprocess
import sys
import time

import h5py

TOOLS = os.path.dirname(os.path.abspath(__file__))
failures = 0

GAMMA, HEIGHT = 20.0, 10.0          # inputs/column.dat


def verdict(ok, name, detail):
    global failures
    print(f"{'PASS' if ok else 'FAIL'} {name}: {detail}")
    failures += not ok


def tool(name, *args, env=None):
    proc = subprocess.run([sys.executable, os.path.join(TOOLS, name), *args],
                          capture_output=True, text=True, env=env)
    return proc.returncode, proc.stdout + proc.stderr


def column_settlement(e, nu):
    m = e * (1 - nu) / ((1 + nu) * (1 - 2 * nu))
    return GAMMA * HEIGHT ** 2 / (2 * m)


def read_rows(path):
    with open(path, newline="") as fh:
        return list(csv.DictReader(fh))


def check_batch(cfrd, work):
    out = os.path.join(work, "batch")
    bad = "test/bad_decks/13-negative-modulus.dat"
    decks = ["inputs/column.dat", bad, "inputs/example.dat", "inputs/triaxial-iiib.dat"]
    status, text = tool("batch.py", "--cfrd", cfrd, "--out", out, *decks)
    rows = {r["deck"]: r for r in read_rows(os.path.join(out, "batch-summary.csv"))} \
        if os.path.isfile(os.path.join(out, "batch-summary.csv")) else {}
    statuses = [rows.get(d, {}).get("status") for d in decks]
    files_ok = all(os.path.isfile(os.path.join(out, f"{s}{x}"))
                   for s in ("column", "example", "triaxial-iiib")
                   for x in (".out", ".h5", ".log"))
    log = open(os.path.join(out, "13-negative-modulus.log")).read() \
        if os.path.isfile(os.path.join(out, "13-negative-modulus.log")) else ""
    ok = (status == 1 and statuses == ["ok", "bad input", "ok", "ok"] and files_ok
          and "field E of MATERIALS 1" in log
          and not os.path.exists(os.path.join(out, "13-negative-modulus.h5")))
    verdict(ok, "batch/one-bad-deck", f"exit {status} (expected 1: one failed), statuses "
            f"{statuses}, listing/HDF5/log of each good deck: {files_ok}, the bad deck's "
            f"message in its log: {'field E of MATERIALS 1' in log}" + ("" if ok else text))
    if not ok:
        return
    column = rows["inputs/column.dat"]
    value = float(column["max_settlement_m"])
    expected = column_settlement(20000.0, 0.3)
    err = abs(value - expected) / expected
    ok = err <= 1e-9 and column["max_settlement_node"] in ("21", "22") and \
        rows["inputs/triaxial-iiib.dat"]["stages"] == "11"
    verdict(ok, "batch/summary", f"column max settlement {value:.12g} m at node "
            f"{column['max_settlement_node']} vs gamma H^2/(2M) = {expected:.12g} (rel. "
            f"error {err:.1e}, tol 1e-9); triaxial stages "
            f"{rows['inputs/triaxial-iiib.dat']['stages']} (expected 11)")
    three = ["test/bad_decks/13-negative-modulus.dat", "test/bad_decks/14-poisson-half.dat",
             "test/bad_decks/07-no-end.dat", "inputs/example.dat"]
    status, text = tool("batch.py", "--quiet", "--cfrd", cfrd, "--out",
                        os.path.join(work, "batch3"), *three)
    verdict(status == 3, "batch/exit-status-counts", f"three bad decks and a good one: exit "
            f"{status} (expected 3)")
    status, text = tool("batch.py", "--cfrd", cfrd, "--out", os.path.join(work, "batch-dup"),
                        "inputs/example.dat", "test/study/../../inputs/example.dat")
    verdict(status == 101 and "would both write example.out" in text, "batch/same-name",
            f"two decks named example: exit {status} (expected 101): {text.strip()}")
    for folder in ("a", "b"):
        os.makedirs(os.path.join(work, "names", folder))
        shutil.copy("inputs/example.dat", os.path.join(work, "names", folder, "col.dat"))
    decks = [os.path.join(work, "names", f, "col.dat") for f in ("a", "b")]
    same = os.path.join(work, "names", "same")
    status, text = tool("batch.py", "--cfrd", cfrd, "--out", same, *decks)
    verdict(status == 101 and f"{decks[0]} and {decks[1]} would both write" in text and
            not os.path.exists(same), "batch/same-name-two-folders",
            f"col.dat from two folders into one --out: exit {status} (expected 101), "
            f"nothing run: {not os.path.exists(same)}: {text.strip()}")
    a_file = os.path.join(work, "names", "a-file")
    open(a_file, "w").close()
    status, text = tool("batch.py", "--cfrd", cfrd, "--out", a_file, decks[0])
    verdict(status == 101 and "a file of that name exists" in text, "batch/out-is-a-file",
            f"--out naming a file: exit {status} (expected 101): {text.strip()[-200:]}")
    deep = os.path.join(work, "names", "new", "deep")
    status, text = tool("batch.py", "--quiet", "--cfrd", cfrd, "--out", deep, decks[0])
    verdict(status == 0 and os.path.getsize(os.path.join(deep, "col.h5")) > 0,
            "batch/out-creates-folder", f"a missing --out folder: exit {status}, "
            f"col.h5 in it: {os.path.exists(os.path.join(deep, 'col.h5'))}")


def check_stop(cfrd, work):
    """SIGTERM to the batch once its first deck has written a stage."""
    out = os.path.join(work, "stop")
    first, second = "inputs/tianshengqiao-x2.dat", "inputs/example.dat"
    log = os.path.join(out, "tianshengqiao-x2.log")
    proc = subprocess.Popen([sys.executable, os.path.join(TOOLS, "batch.py"), "--cfrd", cfrd,
                             "--jobs", "1", "--out", out, first, second],
                            stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    sent = False
    end = time.monotonic() + 300
    while not sent and time.monotonic() < end and proc.poll() is None:
        if os.path.exists(log):
            with open(log) as fh:
                sent = "stage 2/" in fh.read()
        if sent:
            proc.send_signal(signal.SIGTERM)
        else:
            time.sleep(0.01)
    text = proc.communicate()[0]
    rows = {r["deck"]: r for r in read_rows(os.path.join(out, "batch-summary.csv"))} \
        if os.path.exists(os.path.join(out, "batch-summary.csv")) else {}
    incomplete = os.path.join(out, "tianshengqiao-x2.incomplete.h5")
    stages = 0
    if os.path.exists(incomplete):
        with h5py.File(incomplete, "r") as f:
            stages = len(f["stages"]) if f.attrs["complete"] == 0 else -1
    parts = glob.glob(os.path.join(out, "*.part"))
    statuses = {d: rows.get(d, {}).get("status") for d in (first, second)}
    ok = sent and proc.returncode == 143 and statuses == {
        first: "stopped (SIGTERM)", second: "not run"} and stages >= 1 and not parts and \
        not os.path.exists(os.path.join(out, "example.h5"))
    verdict(ok, "batch/sigterm", f"exit {proc.returncode} (expected 143), summary "
            f"statuses {statuses}, {stages} stages in tianshengqiao-x2.incomplete.h5 "
            f"(expected >= 1), .part files left: {parts or 'none'}"
            + ("" if ok else "\n" + text[-500:]))


def check_parallel(work):
    out = os.path.join(work, "parallel")
    os.makedirs(out, exist_ok=True)
    fake = os.path.join(out, "fake-cfrd")
    # Stands in for cfrd (--out DIR DECK): notes its start, then waits (at most 30 s) until
    # the other deck has started too, and records how many ran at once.
    with open(fake, "w") as fh:
        fh.write("""#!/usr/bin/env bash
out=$2; stem=$(basename "$3" .dat); mode=$(cat "$out/mode")
mkdir "$out/running-$stem"
ls -d "$out"/running-* | wc -l >>"$out/at-once"
others() { ls -d "$out"/running-* "$out"/done-* 2>/dev/null | wc -l; }
if [[ $mode == barrier ]]; then
    for i in $(seq 300); do [[ $(others) -ge 2 ]] && break; sleep 0.1; done
    [[ $(others) -ge 2 ]] || { echo "cfrd: the other deck did not start"; exit 1; }
else
    sleep 0.2
fi
mkdir "$out/done-$stem"
rmdir "$out/running-$stem"
""")

    os.chmod(fake, 0o755)
    decks = ["inputs/column.dat", "inputs/example.dat"]
    for mode, jobs in (("barrier", "2"), ("count", "1")):
        for f in os.listdir(out):
            if f != "fake-cfrd":
                p = os.path.join(out, f)
                shutil.rmtree(p) if os.path.isdir(p) else os.remove(p)
        open(os.path.join(out, "mode"), "w").write(mode)
        status, text = tool("batch.py", "--quiet", "--jobs", jobs, "--cfrd", fake,
                            "--out", out, *decks,
                            *(["inputs/triaxial-iiib.dat"] if mode == "count" else []))
        at_once = [int(x) for x in open(os.path.join(out, "at-once")).read().split()] \
            if os.path.isfile(os.path.join(out, "at-once")) else []
        if mode == "barrier":
            verdict(status == 0, "batch/parallel", f"--jobs 2: both decks started before "
                    f"either finished (exit {status}, expected 0; processes at once: "
                    f"{at_once})")
        else:
            verdict(status == 0 and at_once == [1, 1, 1], "batch/jobs-1",
                    f"--jobs 1: processes at once {at_once} (expected [1, 1, 1]), exit "
                    f"{status}")


def same_but_comments(expanded, source):
    """Whether the expanded deck is the source deck, line for line, apart from comment
    cards (the study card and the template's notes)."""
    a = [l for l in open(expanded).read().split("\n") if not l.startswith("*")]
    b = [l for l in open(source).read().split("\n") if not l.startswith("*")]
    return a == b


def check_study(cfrd, work):
    sdir = os.path.join(work, "study")
    status, text = tool("study.py", "test/study/column.dat", "--dir", sdir, "--cfrd", cfrd)
    results = os.path.join(sdir, "study-results.csv")
    rows = read_rows(results) if os.path.isfile(results) else []
    worst, lines = 0.0, []
    for r in rows:
        if r["status"] != "ok":
            worst = float("inf")
            continue
        expected = column_settlement(float(r["E"]), float(r["NU"]))
        err = abs(float(r["max_settlement_m"]) - expected) / expected
        worst = max(worst, err)
        lines.append(f"{r['case']} {float(r['max_settlement_m']):.6f}")
    png = os.path.join(sdir, "study-response.png")
    ok = status == 0 and len(rows) == 4 and worst <= 1e-9 and os.path.getsize(png) > 10000
    verdict(ok, "study/closed-form", f"4 cases of E x NU: settlements {', '.join(lines)} m "
            f"against gamma H^2/(2M): max rel. error {worst:.1e} (tol 1e-9); exit {status}; "
            f"{png} written" + ("" if ok else "\n" + text))
    base = os.path.join(sdir, "decks", "column-soft-0.3.dat")
    verdict(os.path.isfile(base) and same_but_comments(base, "inputs/column.dat"),
            "study/expansion", f"{base} (E 20000.0, NU 0.3) is inputs/column.dat but its "
            f"comment cards")
    # The shipped example: its template is the joint deck with three placeholders.
    jdir = os.path.join(work, "study-joint")
    table = os.path.join(work, "joint-base.csv")
    open(table, "w").write("case,KNT,KB,PHI\nbase,10000.0,204.0,30.0\n")
    status, text = tool("study.py", "inputs/studies/tianshengqiao-joint.dat", "--table", table,
                        "--dir", jdir, "--expand-only")
    deck = os.path.join(jdir, "decks", "tianshengqiao-joint-base.dat")
    ok = status == 0 and os.path.isfile(deck) and \
        same_but_comments(deck, "inputs/tianshengqiao-x1-joint.dat")
    verdict(ok, "study/joint-template", "inputs/studies/tianshengqiao-joint.dat with KNT "
            "10000.0, KB 204.0, PHI 30.0 is inputs/tianshengqiao-x1-joint.dat but its comment "
            "cards" + ("" if ok else f" (exit {status}) {text}"))

    def rejected(name, table_text, expected):
        t = os.path.join(work, f"{name}.csv")
        open(t, "w").write(table_text)
        status, text = tool("study.py", "test/study/column.dat", "--table", t, "--dir",
                            os.path.join(work, name), "--cfrd", cfrd)
        verdict(status == 2 and expected in text, f"study/{name}",
                f"exit {status} (expected 2): {text.strip().splitlines()[-1]}")
    t = os.path.join(work, "misfit.csv")
    rejected("misfit", "case,E,NU\nok,20000.0,0.3\nwide,200000000.0,0.3\n",
             f"test/study/column.dat:22:1-10: field {{E}} is 10 columns wide; the value "
             f"'200000000.0' of case wide ({t}:3, column E) has 11 characters")
    rejected("unknown-column", "case,E,NU,KB\nok,20000.0,0.3,200\n",
             "column 4 'KB' is not a placeholder of test/study/column.dat")
    rejected("missing-column", "case,E\nok,20000.0\n",
             "no column for the placeholder {NU} of test/study/column.dat")
    t = os.path.join(work, "not-a-number.csv")
    rejected("not-a-number", "case,E,NU\nok,20000.0,0.3\ntypo,20000..0,0.3\n",
             f"column-typo.dat:22:1-10: field E of MATERIALS 1: expected a real number, "
             f"found '20000..0' (case typo, {t}:3)")


def check_slurm(cfrd, work):
    sdir = os.path.join(work, "slurm")
    status, text = tool("study.py", "test/study/column.dat", "--dir", sdir, "--cfrd", cfrd,
                        "--slurm", "--sbatch=--time=00:05:00")
    script = os.path.join(sdir, "study.slurm")
    if status != 0 or not os.path.isfile(script):
        verdict(False, "slurm/script", f"--slurm: exit {status}: {text}")
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
    verdict(ok, "slurm/script", f"bash -n: {syntax.returncode}, #SBATCH --array=1-4 and "
            f"--time: {'#SBATCH --array=1-4' in body}, decks.txt: {len(decks)} decks "
            f"(expected 4, absolute paths), runs {os.path.abspath(cfrd)} into "
            f"{os.path.abspath(sdir)}/results (made before submission)"
            + ("" if ok else "\n" + body))
    env = {k: v for k, v in os.environ.items() if not k.startswith("SLURM_")}
    outside = subprocess.run(["bash", script], capture_output=True, text=True, env=env)
    verdict(outside.returncode != 0 and "run this script with sbatch" in outside.stderr,
            "slurm/outside-slurm", f"without SLURM_ARRAY_TASK_ID: exit {outside.returncode}, "
            f"{outside.stderr.strip()}")
    codes = []
    for task in range(1, 5):
        proc = subprocess.run(["bash", script], capture_output=True, text=True,
                              env=dict(env, SLURM_ARRAY_TASK_ID=str(task)))
        codes.append(proc.returncode)
    status, text = tool("study.py", "test/study/column.dat", "--dir", sdir, "--collect")
    rows = read_rows(os.path.join(sdir, "study-results.csv"))
    errs = [abs(float(r["max_settlement_m"]) - column_settlement(float(r["E"]), float(r["NU"])))
            / column_settlement(float(r["E"]), float(r["NU"])) if r["status"] == "ok"
            else float("inf") for r in rows]
    ok = codes == [0, 0, 0, 0] and status == 0 and len(rows) == 4 and max(errs) <= 1e-9
    verdict(ok, "slurm/array-tasks", f"tasks 1-4 run as Slurm runs them: exit statuses "
            f"{codes}; --collect: exit {status}, 4 cases, max rel. error against "
            f"gamma H^2/(2M) {max(errs):.1e} (tol 1e-9)" + ("" if ok else "\n" + text))


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--cfrd", required=True)
    parser.add_argument("--workdir", required=True)
    args = parser.parse_args()
    shutil.rmtree(args.workdir, ignore_errors=True)
    os.makedirs(args.workdir)
    check_batch(args.cfrd, args.workdir)
    check_stop(args.cfrd, args.workdir)
    check_parallel(args.workdir)
    check_study(args.cfrd, args.workdir)
    check_slurm(args.cfrd, args.workdir)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
