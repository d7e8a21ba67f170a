#!/usr/bin/env python3
"""Parametric studies (issue 8, section 3): a template deck and a table of cases.

    python3 tools/study.py TEMPLATE [--table CSV] [--dir DIR] [--cfrd bin/cfrd] [--jobs N]
                           [--x NAME]                  expand, run in parallel, collect
    python3 tools/study.py TEMPLATE ... --expand-only   write the decks only
    python3 tools/study.py TEMPLATE ... --slurm [--sbatch OPTION ...] [--cluster-cfrd PATH]
                                                        write the decks and a Slurm job array
    python3 tools/study.py TEMPLATE ... --collect       results of a finished (Slurm) run
    make study STUDY=TEMPLATE                           the first form, with bin/cfrd

The template is a deck (docs/cards.md) in which fields are placeholders: `{NAME}` padded
with blanks inside the braces to the field's width, e.g. `{KB      }` for a 10-column field.
The columns the braces span are the field: each case's value is right-justified in them,
and a value wider than the field is an error that names the template's line and columns,
the case and the table's line. The template names its table on a comment card,
`* study: TABLE.csv` (a path relative to the template; --table overrides). The table is a
CSV: a header with one column per placeholder name (and an optional `case` column naming
each case), then one row per case; `#` lines are comments.

Writes into DIR (default study-TEMPLATE_STEM):
  decks/STEM-CASE.dat       the expanded decks (each read by `cfrd --check` before runs);
  results/                  their listings, HDF5 files, CSVs and logs (tools/batch.py);
  study-results.csv         one row per case: parameters, status, stages, the largest
                            settlement and interface opening over all stages with where;
  study-response.png        those two responses against one parameter (--x, default the
                            one with the most values), one line per combination of the
                            others;
  study.slurm, decks.txt    with --slurm: a job array with one task per case (line k of
                            decks.txt is task k), to submit with `sbatch DIR/study.slurm`;
                            afterwards `--collect` writes the CSV and the figure.

Exit status: 0 when every case ran, 1 when one failed, 2 for a bad template or table (or a
deck that cfrd --check rejects).
"""

import argparse
import csv
import os
import re
import shlex
import subprocess
import sys

import batch

PLACEHOLDER = re.compile(r"\{([A-Za-z][A-Za-z0-9_]*) *\}")
STUDY_CARD = re.compile(r"^\*\s*study:\s*(\S+)\s*$", re.IGNORECASE)
CASE_NAME = re.compile(r"[A-Za-z0-9][A-Za-z0-9_.+-]*")


class StudyError(Exception):
    """A bad template or table (exit status 2)."""


class Placeholder:
    def __init__(self, name, line, col1, col2):
        self.name, self.line, self.col1, self.col2 = name, line, col1, col2

    @property
    def width(self):
        return self.col2 - self.col1 + 1

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
            continue
        if line.startswith("*"):
            continue
        for p in PLACEHOLDER.finditer(line):
            places.append(Placeholder(p.group(1), number, p.start() + 1, p.end()))
        inside = {k for p in PLACEHOLDER.finditer(line) for k in range(p.start(), p.end())}
        stray = [k for k, ch in enumerate(line) if ch in "{}" and k not in inside]
        if stray:
            raise StudyError(f"{path}:{number}:{stray[0] + 1}: a brace that is not part of a "
                             f"placeholder such as {{NAME   }}")
    if not places:
        raise StudyError(f"{path}: no placeholder {{NAME   }} in the template")
    return lines, places, table


def read_table(path, names, template):
    """Cases as (case name, {placeholder: value}, table line)."""
    try:
        with open(path, newline="") as fh:
            raw = fh.read().split("\n")
    except OSError as exc:
        raise StudyError(f"{path}: cannot read the parameter table ({exc.strerror})")
    rows = [(n, r) for n, r in zip(range(1, len(raw) + 1), csv.reader(raw))
            if r and "".join(r).strip() and not r[0].lstrip().startswith("#")]
    if not rows:
        raise StudyError(f"{path}: no header line")
    header_line, header = rows[0]
    header = [h.strip() for h in header]
    for k, h in enumerate(header, start=1):
        if h != "case" and h not in names:
            raise StudyError(f"{path}:{header_line}: column {k} '{h}' is not a placeholder "
                             f"of {template} (placeholders: {', '.join(sorted(names))})")
        if header.count(h) > 1:
            raise StudyError(f"{path}:{header_line}: column '{h}' appears twice")
    for name in sorted(names):
        if name not in header:
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
        for h in header:
            if not values[h]:
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
    by_line = {}
    for p in places:
        by_line.setdefault(p.line, []).append(p)
    decks = []
    for case, values, table_line in cases:
        for p in places:
            v = values[p.name]
            if len(v) > p.width:
                raise StudyError(
                    f"{p.where(template)}: field {{{p.name}}} is {p.width} columns wide; "
                    f"the value '{v}' of case {case} ({table}:{table_line}, column "
                    f"{p.name}) has {len(v)} characters")
        out = []
        for number, line in enumerate(lines, start=1):
            if STUDY_CARD.match(line):
                line = f"* study case {case} of {template}: " + \
                    ", ".join(f"{k} = {v}" for k, v in values.items())
            for p in sorted(by_line.get(number, []), key=lambda p: -p.col1):
                line = line[:p.col1 - 1] + values[p.name].rjust(p.width) + line[p.col2:]
            out.append(line)
        path = os.path.join(deck_dir, f"{stem}-{case}.dat")
        text = "\n".join(out)
        # An unchanged deck is not rewritten: its time stamp tells --collect whether the
        # results in results/ are newer than it.
        if not os.path.isfile(path) or open(path).read() != text:
            with open(path, "w") as fh:
                fh.write(text)
        decks.append(path)
    return decks


def check_decks(cfrd, decks):
    """cfrd --check on every deck: its messages, or [] when all are valid."""
    proc = subprocess.run([cfrd, "--check", "--quiet", *decks], capture_output=True,
                          text=True)
    if proc.returncode == 0:
        return []
    return [l for l in proc.stderr.splitlines() if l.startswith("cfrd: ") and
            "warning" not in l] or [proc.stderr.strip() or f"cfrd exit {proc.returncode}"]


def collect_runs(decks, results_dir):
    """DeckRun of each deck from what a finished run left in results_dir (Slurm)."""
    runs = []
    for deck in decks:
        run = batch.DeckRun(deck, batch.stem_of(deck))
        h5 = os.path.join(results_dir, run.stem + ".h5")
        log = os.path.join(results_dir, run.stem + ".log")
        if os.path.isfile(h5) and os.path.getmtime(h5) >= os.path.getmtime(deck):
            run.returncode = 0
            try:
                run.stages, run.max_settlement, run.max_opening = batch.key_results(h5)
            except (OSError, KeyError) as exc:
                run.returncode, run.message = 1, f"cannot read {h5}: {exc}"
        else:
            run.returncode = 1
            lines = []
            if os.path.isfile(log):
                lines = [l.strip()[6:] for l in open(log) if l.startswith("cfrd: ")
                         and "warning" not in l]
            run.message = lines[-1] if lines else f"no results ({h5}, see {log})"
        runs.append(run)
    return runs


def write_results_csv(path, names, cases, runs):
    with open(path, "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["case", *names, "deck", "status", "stages", "wall_time_s",
                    "max_settlement_m", "max_settlement_node", "max_settlement_stage",
                    "max_opening_m", "max_opening_phase", "max_opening_stage", "message"])
        for (case, values, _), r in zip(cases, runs):
            s = r.max_settlement or ("", "", "")
            o = r.max_opening or ("", "", "")
            w.writerow([case, *(values[n] for n in names), r.deck, r.status,
                        "" if r.stages is None else r.stages, f"{r.wall:.3f}", *s, *o,
                        r.message])


def as_number(text):
    try:
        return float(text)
    except ValueError:
        return None


def plot_response(path, title, names, cases, runs, x_name=None):
    """Largest settlement (and opening) against one parameter, a line per combination of
    the others."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    if x_name is None:
        x_name = max(names, key=lambda n: len({v[n] for _, v, _ in cases}))
    others = [n for n in names if n != x_name]
    xs_text = [v[x_name] for _, v, _ in cases]
    numeric = all(as_number(x) is not None for x in xs_text)
    categories = sorted(set(xs_text), key=xs_text.index)
    responses = [("max_settlement", "largest settlement since placement (m)")]
    if any(r.max_opening is not None for r in runs):
        responses.append(("max_opening", "largest interface opening (m)"))
    fig, axes = plt.subplots(1, len(responses), figsize=(6 * len(responses), 4.2),
                             squeeze=False)
    groups = {}
    for (case, values, _), run in zip(cases, runs):
        key = tuple(values[n] for n in others)
        groups.setdefault(key, []).append((values[x_name], run))
    for ax, (attr, label) in zip(axes[0], responses):
        for key, members in groups.items():
            pts = []
            for x, run in members:
                value = getattr(run, attr)
                if value is None:
                    continue
                pts.append((as_number(x) if numeric else categories.index(x), value[0]))
            pts.sort()
            if not pts:
                continue
            legend = ", ".join(f"{n} = {k}" for n, k in zip(others, key)) or "cases"
            ax.plot([p[0] for p in pts], [p[1] for p in pts], marker="o", label=legend)
        if numeric:
            xs = [as_number(x) for x in xs_text]
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
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def write_slurm(path, decks_txt, decks, results_dir, cfrd, name, options):
    """A job array, task k running the deck on line k of decks_txt."""
    lines = ["#!/bin/bash",
             f"# cfrd study {name}: {len(decks)} cases, one array task each.",
             "# Written by tools/study.py --slurm; submit with: sbatch " + path,
             "# then collect: python3 tools/study.py ... --collect",
             f"#SBATCH --job-name=cfrd-{name}",
             f"#SBATCH --array=1-{len(decks)}",
             "#SBATCH --ntasks=1",
             "#SBATCH --cpus-per-task=1",
             f"#SBATCH --output={results_dir}/slurm-%A_%a.out"]
    lines += [f"#SBATCH {o}" for o in options]
    lines += ["set -euo pipefail",
              "# One BLAS thread: the cluster runs the cases side by side.",
              "export OPENBLAS_NUM_THREADS=1",
              ": \"${SLURM_ARRAY_TASK_ID:?not set: run this script with sbatch}\"",
              f"deck=$(sed -n \"${{SLURM_ARRAY_TASK_ID}}p\" {shlex.quote(decks_txt)})",
              "[[ -n $deck ]] || { echo \"no deck for task $SLURM_ARRAY_TASK_ID\" >&2; exit 2; }",
              "stem=$(basename \"$deck\" .dat)",
              f"mkdir -p {shlex.quote(results_dir)}",
              f"exec {shlex.quote(cfrd)} --out {shlex.quote(results_dir)} \"$deck\" "
              f"> {shlex.quote(results_dir)}/\"$stem\".log 2>&1",
              ""]
    with open(path, "w") as fh:
        fh.write("\n".join(lines))
    os.chmod(path, 0o755)
    with open(decks_txt, "w") as fh:
        fh.write("\n".join(decks) + "\n")


def main(argv=None):
    parser = argparse.ArgumentParser(
        description="Expand a template deck over a table of cases, run and plot them.")
    parser.add_argument("template")
    parser.add_argument("--table", help="parameter table (default: the `* study:` card)")
    parser.add_argument("--dir", help="study folder (default study-TEMPLATE_STEM)")
    parser.add_argument("--cfrd", default="bin/cfrd")
    parser.add_argument("--jobs", "-j", type=int, default=batch.default_jobs())
    parser.add_argument("--x", dest="x_name", help="parameter on the plot's x axis")
    mode = parser.add_mutually_exclusive_group()
    mode.add_argument("--expand-only", action="store_true")
    mode.add_argument("--slurm", action="store_true")
    mode.add_argument("--collect", action="store_true")
    parser.add_argument("--sbatch", action="append", default=[], metavar="OPTION",
                        help="extra #SBATCH line, e.g. --sbatch=--time=00:10:00")
    parser.add_argument("--cluster-cfrd", help="the program's path on the cluster "
                        "(default: the absolute path of --cfrd)")
    args = parser.parse_args(argv)
    stem = os.path.splitext(os.path.basename(args.template))[0]
    study_dir = args.dir or f"study-{stem}"
    deck_dir = os.path.join(study_dir, "decks")
    results_dir = os.path.join(study_dir, "results")
    try:
        lines, places, named_table = read_template(args.template)
        table = args.table or named_table
        if table is None:
            raise StudyError(f"{args.template}: no `* study: TABLE.csv` card and no --table")
        names = list(dict.fromkeys(p.name for p in places))
        header, cases = read_table(table, set(names), args.template)
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
        cfrd = args.cluster_cfrd or os.path.abspath(args.cfrd)
        write_slurm(script, os.path.abspath(os.path.join(study_dir, "decks.txt")),
                    [os.path.abspath(d) for d in decks], os.path.abspath(results_dir),
                    cfrd, stem, args.sbatch)
        print(f"Slurm job array ({len(decks)} tasks): sbatch {script}\n"
              f"afterwards: python3 tools/study.py {args.template} --dir {study_dir} "
              f"--collect")
        return 0
    if args.collect:
        runs = collect_runs(decks, results_dir)
    else:
        if not (os.path.isfile(args.cfrd) and os.access(args.cfrd, os.X_OK)):
            print(f"study: {args.cfrd}: no such program (make build makes bin/cfrd)",
                  file=sys.stderr)
            return 2
        problems = check_decks(args.cfrd, decks)
        if problems:
            for p in problems:
                p = p[6:] if p.startswith("cfrd: ") else p
                # Say which case and table row made the deck.
                for deck, (case, _, line) in zip(decks, cases):
                    if p.startswith(deck + ":"):
                        p += f" (case {case}, {table}:{line})"
                print(f"study: {p}", file=sys.stderr)
            return 2
        os.makedirs(results_dir, exist_ok=True)

        def progress(done, total, run):
            print(f"[{done}/{total}] {run.stem}: {run.status}, {run.wall:.2f} s", flush=True)
        runs = batch.run_batch(decks, args.cfrd, results_dir, args.jobs, progress)
        batch.write_summary_csv(runs, os.path.join(results_dir, "batch-summary.csv"))
    out_csv = os.path.join(study_dir, "study-results.csv")
    write_results_csv(out_csv, names, cases, runs)
    png = os.path.join(study_dir, "study-response.png")
    if any(r.ok for r in runs):
        plot_response(png, stem, names, cases, runs, args.x_name)
    print()
    batch.print_summary(runs)
    print(f"Table: {out_csv}; figure: {png}")
    return 0 if all(r.ok for r in runs) else 1


if __name__ == "__main__":
    sys.exit(main())
