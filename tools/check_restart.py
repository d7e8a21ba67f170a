#!/usr/bin/env python3
"""A run restarted from stage K gives the results of the run without a stop (issue 24, part 3).

    python3 tools/check_restart.py --cfrd build/debug-bin/cfrd --workdir build/test-work/restart

The reference is the uninterrupted run of the same deck by the same program (an independent
check of the restart, not of the physics). On the x1 Tianshengqiao-I decks, bonded, Goodman
joint, thin layer and contact (tools/tianshengqiao.py), and a bonded x1 deck with creep,
wetting and a LOAD stage (--creep, with WETTING cards, a named LOADS set and LOAD and WET
stages added here [choice]), each run once in full:

1. `cfrd --restart FULL.h5 --from-stage K` for K the last stage of each kind the deck has
   (FILL of a fill layer, RESET, FILL of a slab phase, WATER, LOAD, WAIT, WET) before its
   last stage: every dataset and attribute of every stage equal to the full run's to the
   last bit (timings and `symbolic_ahead` aside; of stage K+1 the count of symbolic
   factorisations too: the restart analyses its first matrix anew), and every CSV file
   equal line for line after its run-id comment.
2. On the contact deck: the same with the deck given (`--restart FULL.h5 --from-stage K
   DECK`); with `--compress 0` (the stored stages recorded again from their state and
   written, not copied); a scenario, a deck that differs only after K (the last reservoir level), against
   a full run of that deck; `--float32` restarted from a `--float32` file; and the run
   stopped by SIGTERM, finished from its DECK.incomplete.h5 (the incomplete file removed).
3. Refusals (exit 2 and the message): K beyond the last completed stage, a deck that
   differs before K (naming the first difference), a file that is not cfrd's, a text file,
   a results file of layout 3; --from-stage without --restart or not a number, two decks.
"""

import os
import re
import shutil
import signal
import subprocess
import sys

import h5py
import numpy as np

from cfrdtools.checks import Checks, fresh, parser
from check_stop import compare_stages, stop_after_stage

check = Checks("restart")
HERE = os.path.dirname(os.path.abspath(__file__))


def run(cmd):
    """(exit status, stderr) of a quiet cfrd run."""
    p = subprocess.run(cmd, capture_output=True, text=True)
    return p.returncode, p.stderr


def deck_for(name, folder):
    """Write the x1 deck `name` into `folder`; return its path. `fine-slab`: the hard case
    incipient-slip (a slab much finer than the body: the roles swapped, the cushion carries
    the multipliers, and CAST's moves of the slab's nodes are in the restart state's u);
    `fine-slab-asis`: incipient-slip-asis (ROLES ASIS: friction per master segment, whose
    groups the restart state carries)."""
    path = os.path.join(folder, name + ".dat")
    if name in ("fine-slab", "fine-slab-asis"):
        source = "incipient-slip" + ("-asis" if name.endswith("asis") else "") + ".dat"
        return shutil.copy(os.path.join(HERE, "..", "test", "hard_cases", source), path)
    interface = "bonded" if name == "creep" else name
    extra = ["--creep"] if name == "creep" else []
    subprocess.run([sys.executable, os.path.join(HERE, "tianshengqiao.py"), "--refine", "1",
                    "--interface", interface, "--solver", "midpoint", "--deck", path, *extra],
                   check=True, capture_output=True)
    if name == "creep":
        add_load_and_wetting(path)
    return path


def add_load_and_wetting(path):
    """The creep deck with a WETTING card after each CREEP card, a named LOADS set (1 % more
    weight on every active element) and, after the last WATER stage, a LOAD stage of it and
    a WET stage below El. 700 m: test values within the cards' limits [choice]."""
    out, lines = [], open(path).read().splitlines()
    last_water = max(i for i, ln in enumerate(lines) if ln.startswith("WATER "))
    for i, line in enumerate(lines):
        if line.startswith("STAGES"):
            out += ["LOADS     EXTRA", "GRAVITY   ALL              0.0     -0.01"]
        out.append(line)
        if line.startswith("CREEP "):
            out.append("WETTING        0.002       0.5     0.002")
        if i == last_water:
            out += ["LOAD      EXTRA         2           1 % more weight [choice]",
                    "WET            700.0    4           wetting below El. 700 m [choice]"]
    open(path, "w").write("\n".join(out) + "\n")


def stage_kinds(h5):
    """{kind: the last stage of that kind before the last stage}; a FILL of a slab phase
    (group SLAB...) is a kind of its own."""
    kinds = {}
    with h5py.File(h5, "r") as f:
        names = sorted(f["stages"])
        groups = [g.decode() if isinstance(g, bytes) else g for g in f["mesh/group_names"][...]]
        group = f["mesh/group"][...]
        for k, name in enumerate(names[:-1], start=1):
            s = f["stages"][name]
            kind = s.attrs["kind"].decode() if isinstance(s.attrs["kind"], bytes) else \
                str(s.attrs["kind"])
            if kind == "FILL":
                active = s["active"][...] == 1
                before = f["stages"][names[k - 2]]["active"][...] == 1 if k > 1 else \
                    np.zeros_like(active)
                placed = {groups[g - 1] for g in group[active & ~before] if g > 0}
                if any(g.startswith("SLAB") for g in placed):
                    kind = "FILL-slab"
            kinds[kind] = k
    return kinds


def csv_lines(folder, stem):
    """{CSV name suffix: its lines but the run-id comment} of a result set."""
    found = {}
    for name in sorted(os.listdir(folder)):
        if name.startswith(stem + "-") and name.endswith(".csv"):
            found[name[len(stem):]] = [ln for ln in open(os.path.join(folder, name))
                                       if not ln.startswith("#")]
    return found


def same_results(restarted, full, k, folder, full_folder, stem, full_stem):
    """(ok, detail): every stage of `restarted` equal to `full` (timings aside, and the
    symbolic factorisations of stage K+1), the CSV files equal."""
    names, _, differences = compare_stages(restarted, full)
    allowed = f"stage_{k + 1:04d}/solver attribute symbolic_factorisations differs"
    differences = [d for d in differences if d != allowed]
    with h5py.File(full, "r") as f:
        n = len(f["stages"])
    a, b = csv_lines(folder, stem), csv_lines(full_folder, full_stem)
    if a != b:
        differences.append(f"CSV files differ: {sorted(x for x in set(a) | set(b) if a.get(x) != b.get(x))}")
    if len(names) != n:
        differences.append(f"{len(names)} stages, the full run {n}")
    return not differences, (f"{len(names)} stages, every dataset and attribute to 0 difference"
                             f", {len(a)} CSV files equal" if not differences
                             else "; ".join(differences[:4]))


def restart_kinds(cfrd, name, deck, work):
    """Section 1 for deck `name`: returns the full run's results file."""
    full_folder = os.path.join(work, name, "full")
    status, err = run([cfrd, "--quiet", "--out", full_folder, deck])
    if not check(f"{name}/full-run", status == 0, f"exit {status} {err[-300:]}"):
        return None
    full = os.path.join(full_folder, name + ".h5")
    for kind, k in stage_kinds(full).items():
        folder = os.path.join(work, name, f"k{k}")
        status, err = run([cfrd, "--quiet", "--restart", full, "--from-stage", str(k),
                           "--out", folder])
        if status != 0:
            check(f"{name}/after-{kind}-K{k}", False, f"exit {status}: {err[-300:]}")
            continue
        ok, detail = same_results(os.path.join(folder, name + ".h5"), full, k, folder,
                                  full_folder, name, name)
        check(f"{name}/after-{kind}-K{k}", ok, detail)
    return full


def contact_cases(cfrd, deck, full, work):
    """Section 2: with the deck, a scenario, --float32, SIGTERM."""
    full_folder = os.path.dirname(full)
    k = 39   # the WATER stage to El. 720 m
    folder = os.path.join(work, "with-deck")
    status, err = run([cfrd, "--quiet", "--restart", full, "--from-stage", str(k), "--out",
                       folder, deck])
    ok, detail = same_results(os.path.join(folder, "contact.h5"), full, k, folder,
                              full_folder, "contact", "contact") if status == 0 else \
        (False, f"exit {status}: {err[-300:]}")
    check("contact/with-deck-K39", ok, detail)
    # Stored another way (no filter): the stored stages are recorded and written again, not
    # copied; the values are the same.
    folder = os.path.join(work, "compress0")
    status, err = run([cfrd, "--quiet", "--compress", "0", "--restart", full, "--from-stage",
                       "30", "--out", folder])
    ok, detail = same_results(os.path.join(folder, "contact.h5"), full, 30, folder,
                              full_folder, "contact", "contact") if status == 0 else \
        (False, f"exit {status}: {err[-300:]}")
    check("contact/rewritten-compress0-K30", ok, detail)
    # A scenario: the last reservoir level 760 m instead of 768 m, from the stage before it.
    text = open(deck).read()
    scenario = os.path.join(work, "scenario.dat")
    open(scenario, "w").write(re.sub(r"^WATER          768\.0", "WATER          760.0", text,
                                     flags=re.M))

    def last_level(h5):
        with h5py.File(h5, "r") as f:
            level = float(f["stages/stage_0045"].attrs["water_level"])
        return level == 760.0, f"last level {level} m"
    against_own_run(cfrd, work, "scenario-after-K44", scenario, 44, [], [scenario], last_level,
                    source=full)

    # --float32: the state is kept in double beside the single fields.
    def doubles(h5):
        with h5py.File(h5, "r") as f:
            kinds = (f["stages/stage_0035/stress_gauss"].dtype,
                     f["stages/stage_0035/state/stress_gauss"].dtype)
        return kinds == (np.float32, np.float64), f"stress_gauss {kinds[0]}, " \
            f"state/stress_gauss {kinds[1]}"
    against_own_run(cfrd, work, "float32-K35", deck, 35, ["--float32"], [], doubles)
    # SIGTERM, then finish from DECK.incomplete.h5.
    folder = fresh(os.path.join(work, "stopped"))
    stopped = shutil.copy(deck, os.path.join(folder, "contact.dat"))
    status, log, sent = stop_after_stage([cfrd, stopped], os.path.join(work, "stop.log"),
                                         signal.SIGTERM, stage=20)
    incomplete = os.path.join(folder, "contact.incomplete.h5")
    if not (sent and status == 143 and os.path.exists(incomplete)):
        check("contact/sigterm-then-restart", False, f"exit {status}, sent {sent}, "
              f"{incomplete} there: {os.path.exists(incomplete)}")
        return
    with h5py.File(incomplete, "r") as f:
        kept = int(f.attrs["stages_completed"])
    status, err = run([cfrd, "--quiet", "--restart", incomplete])
    ok, detail = same_results(os.path.join(folder, "contact.h5"), full, kept, folder,
                              full_folder, "contact", "contact") if status == 0 else \
        (False, f"exit {status}: {err[-300:]}")
    check("contact/sigterm-then-restart", ok and not os.path.exists(incomplete),
          f"stopped after stage {kept}, finished from contact.incomplete.h5 (removed: "
          f"{not os.path.exists(incomplete)}): {detail}")


def against_own_run(cfrd, work, name, deck, k, options, deck_args, extra, source=None):
    """A full run of `deck` with `options`, and a restart from stage k of its results (or of
    `source`) with the same options (and `deck_args`): equal, and extra(restarted h5) ->
    (ok, detail)."""
    stem = os.path.splitext(os.path.basename(deck))[0]
    ref, folder = os.path.join(work, name + "-full"), os.path.join(work, name)
    status, err = run([cfrd, "--quiet", *options, "--out", ref, deck])
    status2, err2 = run([cfrd, "--quiet", *options, "--restart", source or os.path.join(
        ref, stem + ".h5"), "--from-stage", str(k), "--out", folder, *deck_args])
    if status or status2:
        check(f"contact/{name}", False, f"exit {status}/{status2}: {err}{err2}")
        return
    ok, detail = same_results(os.path.join(folder, stem + ".h5"), os.path.join(
        ref, stem + ".h5"), k, folder, ref, stem, stem)
    ok2, detail2 = extra(os.path.join(folder, stem + ".h5"))
    check(f"contact/{name}", ok and ok2, f"{detail2}; against a full run: {detail}")


def refusals(cfrd, deck, full, work):
    """Section 3."""
    def refused(name, message, *args):
        status, err = run([cfrd, "--quiet", "--out", os.path.join(work, "refused"), *args])
        check(f"refused/{name}", status == 2 and message in err,
              f"exit {status}: {err.strip()[:300]}")
        return err

    with h5py.File(full, "r") as f:
        n = int(f.attrs["stages_completed"])
    refused("K-beyond-last", f"holds stages 1 to {n}", "--restart", full, "--from-stage",
            str(n + 1))
    changed = os.path.join(work, "changed.dat")
    lines = open(deck).read().splitlines(keepends=True)
    i = next(i for i, ln in enumerate(lines) if ln.startswith("FILL      B1R03"))
    lines[i] = lines[i][:20] + "    2" + lines[i][25:]   # 2 increments instead of 1
    open(changed, "w").write("".join(lines))
    err = refused("deck-differs-before-K", f"stage 3 (line {i + 1}, ", "--restart", full,
                  "--from-stage", "10", changed)
    check("refused/deck-differs-names-the-field", "the increments: 2 here, 1 there" in err,
          err.strip()[-120:])
    other = os.path.join(work, "other.h5")
    with h5py.File(other, "w") as f:
        f["x"] = np.arange(3.0)
    refused("not-cfrd", "not a cfrd results file", "--restart", other)
    refused("not-hdf5", "not a readable HDF5 file", "--restart", deck)
    old = shutil.copy(full, os.path.join(work, "layout3.h5"))
    with h5py.File(old, "a") as f:
        f.attrs["layout_version"] = np.int32(3)
    refused("layout-3", "results layout 3 keeps no restart state", "--restart", old)
    refused("from-stage-alone", "option --from-stage goes with --restart", "--from-stage", "3",
            deck)
    refused("from-stage-not-a-number", "option --from-stage needs a stage number",
            "--restart", full, "--from-stage", "x")
    refused("two-decks", "option --restart takes at most one deck", "--restart", full, deck,
            deck)


def main():
    ap = parser(__doc__, cfrd="build/debug-bin/cfrd", workdir="build/test-work/restart")
    ap.add_argument("--decks", default="bonded,joint,thin,contact,creep,fine-slab,"
                    "fine-slab-asis")
    args = ap.parse_args()
    work = fresh(args.workdir)
    decks = fresh(os.path.join(work, "decks"))
    fulls = {}
    for name in args.decks.split(","):
        deck = deck_for(name, decks)
        fulls[name] = (deck, restart_kinds(args.cfrd, name, deck, work))
    if fulls.get("contact", (None, None))[1]:
        deck, full = fulls["contact"]
        check.guard("contact/cases", contact_cases, args.cfrd, deck, full, work)
        check.guard("refused", refusals, args.cfrd, deck, full, work)
    return check.status


if __name__ == "__main__":
    sys.exit(main())
