#!/usr/bin/env python3
"""Parametric studies (issue 8, section 3; docs/results.md, "Parametric studies"): a template
deck and a table of cases.

    python3 tools/study.py TEMPLATE [--table CSV] [--dir DIR] [--cfrd bin/cfrd] [--jobs N]
                           [--x NAME]                  expand, run in parallel, collect
    python3 tools/study.py TEMPLATE ... --expand-only   write the decks only
    python3 tools/study.py TEMPLATE ... --slurm [--sbatch OPTION ...] [--cluster-cfrd PATH]
                                                        write the decks and a Slurm job array
    python3 tools/study.py TEMPLATE ... --collect       results of a finished (Slurm) run
    make study STUDY=TEMPLATE                           the first form, with bin/cfrd

Placeholders `{NAME    }` fill a field's columns; the table (a `* study: TABLE.csv` card, or
--table) has a column per placeholder and a row per case. Writes into DIR (default
study-TEMPLATE_STEM) decks/, results/, study-results.csv and study-response.png. Exit status:
0 when every case ran, 1 when one failed, 2 for a bad template or table (or a deck that
cfrd --check rejects).
"""

import argparse
import csv
import os
import re
import shlex
import subprocess
import sys

import batch
from cfrdtools.plots import plt, save

PLACEHOLDER = re.compile(r"\{([A-Za-z][A-Za-z0-9_]*) *\}")
STUDY_CARD = re.compile(r"^\*\s*study:\s*(\S+)\s*$", re.IGNORECASE)
CASE_NAME = re.compile(r"[A-Za-z0-9][A-Za-z0-9_.+-]*")


class StudyError(Exception):
    """A bad template or table (exit status 2)."""


class Placeholder:
    def __init__(self, name, line, col1, col2):
        self.name, self.line, self.col1, self.col2 = name, line, col1, col2
        self.width = col2 - col1 + 1

    def where(self, template):
        return f"{template}:{self.line}:{self.col1}-{self.col2}"


def read_template(path):
    """(lines, placeholders, table named on a `* study:` card or None)."""
    try:
        with open(path) as fh:
            lines = fh.read().split("\n")
    except OSError as exc:
        raise StudyError(f"{path}: cannot read the template ({exc.strerror})")
    places, table = [], None
    for number, line in enumerate(lines, start=1):
        m = STUDY_CARD.match(line)
        if m:
            table = os.path.join(os.path.dirname(path), m.group(1))
        if m or line.startswith("*"):
            continue
        found = list(PLACEHOLDER.finditer(line))
        places += [Placeholder(p.group(1), number, p.start() + 1, p.end()) for p in found]
        inside = {k for p in found for k in range(p.start(), p.end())}
        stray = [k for k, ch in enumerate(line) if ch in "{}" and k not in inside]
        if stray:
            raise StudyError(f"{path}:{number}:{stray[0] + 1}: a brace that is not part of a "
                             f"placeholder such as {{NAME   }}")
    if not places:
        raise StudyError(f"{path}: no placeholder {{NAME   }} in the template")
    return lines, places, table


def read_table(path, names, template):
    """The header and the cases as (case name, {placeholder: value}, table line)."""
    try:
        with open(path, newline="") as fh:
            raw = fh.read().split("\n")
    except OSError as exc:
        raise StudyError(f"{path}: cannot read the parameter table ({exc.strerror})")
    rows = [(n, r) for n, r in enumerate(csv.reader(raw), 1)
            if r and "".join(r).strip() and not r[0].lstrip().startswith("#")]
    if not rows:
        raise StudyError(f"{path}: no header line")
    header_line, header = rows[0][0], [h.strip() for h in rows[0][1]]
    for k, h in enumerate(header, start=1):
        if h != "case" and h not in names:
            raise StudyError(f"{path}:{header_line}: column {k} '{h}' is not a placeholder "
                             f"of {template} (placeholders: {', '.join(sorted(names))})")
        if header.count(h) > 1:
            raise StudyError(f"{path}:{header_line}: column '{h}' appears twice")
    for name in sorted(names - set(header)):
        raise StudyError(f"{path}:{header_line}: no column for the placeholder {{{name}}} "
                         f"of {template}")
    if len(rows) == 1:
        raise StudyError(f"{path}: no case (a row per case after the header)")
    cases, seen = [], set()
    for k, (line, row) in enumerate(rows[1:], start=1):
        if len(row) != len(header):
            raise StudyError(f"{path}:{line}: {len(row)} fields, expected {len(header)} "
                             f"({', '.join(header)})")
        values = {h: v.strip() for h, v in zip(header, row)}
        for h in (h for h in header if not values[h]):
            raise StudyError(f"{path}:{line}: column {h}: empty value")
        case = values.pop("case", f"case{k:03d}")
        if not CASE_NAME.fullmatch(case):
            raise StudyError(f"{path}:{line}: column case: '{case}' cannot name a file "
                             f"(letters, digits, _ . + -)")
        if case in seen:
            raise StudyError(f"{path}:{line}: case '{case}' named twice")
        seen.add(case)
        cases.append((case, values, line))
    return header, cases


def expand(template, lines, places, table, cases, deck_dir):
    """Write one deck per case; returns their paths. Every value must fit its field."""
    stem = os.path.splitext(os.path.basename(template))[0]
    os.makedirs(deck_dir, exist_ok=True)
    decks = []
    for case, values, table_line in cases:
        for p in (p for p in places if len(values[p.name]) > p.width):
            raise StudyError(
                f"{p.where(template)}: field {{{p.name}}} is {p.width} columns wide; the value "
                f"'{values[p.name]}' of case {case} ({table}:{table_line}, column {p.name}) has "
                f"{len(values[p.name])} characters")
        out = []
        for number, line in enumerate(lines, start=1):
            if STUDY_CARD.match(line):
                line = f"* study case {case} of {template}: " + \
                    ", ".join(f"{k} = {v}" for k, v in values.items())
            for p in sorted((p for p in places if p.line == number), key=lambda p: -p.col1):
                line = line[:p.col1 - 1] + values[p.name].rjust(p.width) + line[p.col2:]
            out.append(line)
        path, text = os.path.join(deck_dir, f"{stem}-{case}.dat"), "\n".join(out)
        # An unchanged deck is not rewritten: its time stamp tells --collect whether the
        # results in results/ are newer than it.
        if not os.path.isfile(path) or open(path).read() != text:
            with open(path, "w") as fh:
                fh.write(text)
        decks.append(path)
    return decks


def collect_runs(decks, results_dir):
    """DeckRun of each deck from what a finished run left in results_dir (Slurm)."""
    runs = []
    for deck in decks:
        run = batch.DeckRun(deck, batch.stem_of(deck))
        h5, log = (os.path.join(results_dir, run.stem + x) for x in (".h5", ".log"))
        if os.path.isfile(h5) and os.path.getmtime(h5) >= os.path.getmtime(deck):
            run.returncode = 0
            try:
                run.read(h5)
            except (OSError, KeyError) as exc:
                run.returncode, run.message = 1, f"cannot read {h5}: {exc}"
        else:
            run.returncode = 1
            run.message = (batch.error_of(open(log)) if os.path.isfile(log) else None) or \
                f"no results ({h5}, see {log})"
        runs.append(run)
    return runs


def number(text):
    try:
        return float(text)
    except ValueError:
        return None


def plot_response(path, title, names, cases, runs, x_name=None):
    """Largest settlement (and opening) against one parameter, a line per combination of
    the others."""
    x_name = x_name or max(names, key=lambda n: len({v[n] for _, v, _ in cases}))
    others = [n for n in names if n != x_name]
    xs_text = [v[x_name] for _, v, _ in cases]
    numeric = all(number(x) is not None for x in xs_text)
    categories = sorted(set(xs_text), key=xs_text.index)
    responses = [("max_settlement", "largest settlement since placement (m)")]
    if any(r.max_opening is not None for r in runs):
        responses.append(("max_opening", "largest interface opening (m)"))
    fig, axes = plt.subplots(1, len(responses), figsize=(6 * len(responses), 4.2), squeeze=False)
    groups = {}
    for (case, values, _), run in zip(cases, runs):
        groups.setdefault(tuple(values[n] for n in others), []).append((values[x_name], run))
    for ax, (attr, label) in zip(axes[0], responses):
        for key, members in groups.items():
            pts = sorted((number(x) if numeric else categories.index(x), getattr(run, attr)[0])
                         for x, run in members if getattr(run, attr) is not None)
            if pts:
                ax.plot([p[0] for p in pts], [p[1] for p in pts], marker="o",
                        label=", ".join(f"{n} = {k}" for n, k in zip(others, key)) or "cases")
        if numeric:
            xs = [number(x) for x in xs_text]
            if min(xs) > 0 and max(xs) / min(xs) >= 100:
                ax.set_xscale("log")
        else:
            ax.set_xticks(range(len(categories)), categories)
        ax.set_xlabel(x_name)
        ax.set_ylabel(label)
        ax.grid(alpha=0.3)
        if len(groups) > 1:
            ax.legend(fontsize=7)
    fig.suptitle(f"{title}: {len(cases)} cases", fontsize=10)
    save(fig, path, dpi=110, close=True)


def write_slurm(path, decks_txt, decks, results_dir, cfrd, name, options):
    """A job array, task k running the deck on line k of decks_txt."""
    q = shlex.quote
    lines = ["#!/bin/bash", f"# cfrd study {name}: {len(decks)} cases, one array task each.",
             "# Written by tools/study.py --slurm; submit with: sbatch " + path,
             "# then collect: python3 tools/study.py ... --collect",
             f"#SBATCH --job-name=cfrd-{name}", f"#SBATCH --array=1-{len(decks)}",
             "#SBATCH --ntasks=1", "#SBATCH --cpus-per-task=1",
             f"#SBATCH --output={results_dir}/slurm-%A_%a.out"] + [f"#SBATCH {o}" for o in options]
    lines += ["set -euo pipefail", "# One BLAS thread: the cluster runs the cases side by side.",
              "export OPENBLAS_NUM_THREADS=1",
              "# Each task has one core: the stages written on the run's own thread, not behind",
              "# its analysis, and no system prepared ahead of it (docs/performance.md (ag), (ak)).",
              "export CFRD_WRITE_BEHIND=0",
              "export CFRD_AHEAD=0",
              ": \"${SLURM_ARRAY_TASK_ID:?not set: run this script with sbatch}\"",
              f"deck=$(sed -n \"${{SLURM_ARRAY_TASK_ID}}p\" {q(decks_txt)})",
              "[[ -n $deck ]] || { echo \"no deck for task $SLURM_ARRAY_TASK_ID\" >&2; exit 2; }",
              "stem=$(basename \"$deck\" .dat)", f"mkdir -p {q(results_dir)}",
              f"exec {q(cfrd)} --out {q(results_dir)} \"$deck\" > {q(results_dir)}/\"$stem\".log "
              "2>&1", ""]
    with open(path, "w") as fh:
        fh.write("\n".join(lines))
    os.chmod(path, 0o755)
    with open(decks_txt, "w") as fh:
        fh.write("\n".join(decks) + "\n")


def main(argv=None):
    ap = argparse.ArgumentParser(
        description="Expand a template deck over a table of cases, run and plot them.")
    ap.add_argument("template")
    ap.add_argument("--table", help="parameter table (default: the `* study:` card)")
    ap.add_argument("--dir", help="study folder (default study-TEMPLATE_STEM)")
    ap.add_argument("--cfrd", default="bin/cfrd")
    ap.add_argument("--jobs", "-j", type=int, default=batch.default_jobs())
    ap.add_argument("--x", dest="x_name", help="parameter on the plot's x axis")
    mode = ap.add_mutually_exclusive_group()
    for option in ("--expand-only", "--slurm", "--collect"):
        mode.add_argument(option, action="store_true")
    ap.add_argument("--sbatch", action="append", default=[], metavar="OPTION",
                    help="extra #SBATCH line, e.g. --sbatch=--time=00:10:00")
    ap.add_argument("--cluster-cfrd", help="the program's path on the cluster "
                    "(default: the absolute path of --cfrd)")
    args = ap.parse_args(argv)
    stem = os.path.splitext(os.path.basename(args.template))[0]
    study_dir = args.dir or f"study-{stem}"
    deck_dir, results_dir = (os.path.join(study_dir, d) for d in ("decks", "results"))
    try:
        lines, places, named_table = read_template(args.template)
        table = args.table or named_table
        if table is None:
            raise StudyError(f"{args.template}: no `* study: TABLE.csv` card and no --table")
        header, cases = read_table(table, {p.name for p in places}, args.template)
        names = [h for h in header if h != "case"]
        if args.x_name is not None and args.x_name not in names:
            raise StudyError(f"--x {args.x_name}: not a parameter ({', '.join(names)})")
        decks = expand(args.template, lines, places, table, cases, deck_dir)
    except StudyError as exc:
        print(f"study: {exc}", file=sys.stderr)
        return 2
    print(f"{len(decks)} decks in {deck_dir}/ from {args.template} and {table}")
    if args.expand_only:
        return 0
    if args.slurm:
        # Slurm opens each task's --output file before the task runs: the folder must exist.
        os.makedirs(results_dir, exist_ok=True)
        script = os.path.join(study_dir, "study.slurm")
        write_slurm(script, os.path.abspath(os.path.join(study_dir, "decks.txt")),
                    [os.path.abspath(d) for d in decks], os.path.abspath(results_dir),
                    args.cluster_cfrd or os.path.abspath(args.cfrd), stem, args.sbatch)
        print(f"Slurm job array ({len(decks)} tasks): sbatch {script}\n"
              f"afterwards: python3 tools/study.py {args.template} --dir {study_dir} --collect")
        return 0
    if args.collect:
        runs = collect_runs(decks, results_dir)
    else:
        if not (os.path.isfile(args.cfrd) and os.access(args.cfrd, os.X_OK)):
            print(f"study: {args.cfrd}: no such program (make build makes bin/cfrd)",
                  file=sys.stderr)
            return 2
        proc = subprocess.run([args.cfrd, "--check", "--quiet", *decks], capture_output=True,
                              text=True)
        if proc.returncode != 0:
            problems = [ln for ln in proc.stderr.splitlines() if ln.startswith("cfrd: ") and
                        "warning" not in ln] or [proc.stderr.strip() or
                                                 f"cfrd exit {proc.returncode}"]
            for p in problems:
                p = p[6:] if p.startswith("cfrd: ") else p
                # Say which case and table row made the deck.
                p += "".join(f" (case {case}, {table}:{line})" for deck, (case, _, line)
                             in zip(decks, cases) if p.startswith(deck + ":"))
                print(f"study: {p}", file=sys.stderr)
            return 2
        os.makedirs(results_dir, exist_ok=True)
        runs = batch.run_batch(decks, args.cfrd, results_dir, args.jobs, lambda done, total, run:
                               print(f"[{done}/{total}] {run.stem}: {run.status}, "
                                     f"{run.wall:.2f} s", flush=True))
        batch.write_summary_csv(runs, os.path.join(results_dir, "batch-summary.csv"))
    out_csv = os.path.join(study_dir, "study-results.csv")
    with open(out_csv, "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["case", *names, "deck"] + [c for c in batch.SUMMARY_COLUMNS
                                               if c != "exit_status"])
        w.writerows([case, *(values[n] for n in names), r.deck] +
                    [v for c, v in zip(batch.SUMMARY_COLUMNS, batch.summary_row(r))
                     if c != "exit_status"] for (case, values, _), r in zip(cases, runs))
    png = os.path.join(study_dir, "study-response.png")
    if any(r.ok for r in runs):
        plot_response(png, stem, names, cases, runs, args.x_name)
    print()
    batch.print_summary(runs)
    print(f"Table: {out_csv}; figure: {png}")
    return 0 if all(r.ok for r in runs) else 1


if __name__ == "__main__":
    sys.exit(main())
