#!/usr/bin/env python3
"""Fuzzing harness for the deck reader (issue 9, section 4; docs/robustness.md, "Bad input at
scale": the mutations, the outcomes and the failures).

Every mutant is one deck of inputs/*.dat changed by one seeded mutation (KINDS), read with
`cfrd --check`, a deterministic fraction of the accepted ones run in full. The failures: crash
(a signal, a runtime error, another exit status), hang (20 s for --check, 60 s for a run),
message (a rejection without FILE:LINE or naming a line or columns the mutant lacks, or
columns without the field) and nan (NaN or Inf in a result file). `--reproduce SEED` writes
a mutant again (build/fuzz/repro-SEED/), prints its mutation and runs it; failed mutants are
kept in build/fuzz/RUN/SEED/ with repro.txt.

Usage: tools/fuzz.py [--cfrd bin/cfrd] [--count 10000] [--seed 1] [--jobs 2] [--full-large N]
Prints PASS/FAIL lines (fuzz/crashes, fuzz/hangs, fuzz/messages, fuzz/nan) and a table.
"""
import argparse
import glob
import multiprocessing
import os
import random
import re
import shutil
import signal
import subprocess
import sys
import time

import h5py
import numpy as np

from cfrdtools import tables
from cfrdtools.checks import Checks

KINDS = ["drop", "dup", "swap", "shift", "range", "text", "truncate", "binary"]
OUTCOMES = ["rejected", "accepted", "ran", "failed", "crash", "hang", "message", "nan"]
FAILURES = ["crash", "hang", "message", "nan"]
SMALL_DECK_BYTES = 10000      # decks that run in well under a second: run every 1 in 2
CHECK_TIMEOUT, RUN_TIMEOUT = 20.0, 60.0
RANGE_VALUES = [b"0", b"-1", b"-0", b"-0.0", b"0.0", b"1", b"2", b"-999", b"99999",
                b"999999999", b"-99999999", b"2147483647", b"2147483648", b"1e30", b"-1e30",
                b"1e-30", b"1e19", b"-9e19", b"1e20", b"1e307", b"-1e307", b"1e308", b"9e999",
                b"1e-320", b"1e-999", b"0.4999999", b"0.5", b"1.5", b"-1.5", b"360", b"-90",
                b"100000"]
TEXT_VALUES = [b"abc", b"NaN", b"nan", b"Inf", b"-inf", b"1.2.3", b"1e", b"e5", b"--1",
               b"+-1", b".", b"-", b"+", b"1,5", b"1 0", b"0x10", b"1d", b"1e+", b"*", b"?",
               b"ELASTIC", b"1_dp", b"(1)", b"O", b"l0", b"1/2", b"'1'"]
NUMBER = re.compile(rb"[-+]?(\d+\.?\d*|\.\d+)([eEdD][-+]?\d+)?")

# ---------------------------------------------------------------------------------------
# Mutations: each takes the deck's bytes and a random.Random, returns (bytes, description).


def is_card(line):
    """Not a comment or blank line (the same rule as the reader's is_comment)."""
    s = line.rstrip(b"\r")
    return bool(s.strip()) and s[:1] != b"*" and not (
        s[:1] in (b"C", b"c") and (len(s) == 1 or s[1:2] == b" "))


def mutate_lines(data, rng, change):
    """change(lines, cards, rng) edits the lines (a trailing newline kept apart) in place
    and returns the description."""
    lines = data.split(b"\n")
    trailing = lines and lines[-1] == b""
    if trailing:
        lines.pop()
    what = change(lines, [i for i, ln in enumerate(lines) if is_card(ln)] or
                  list(range(len(lines))), rng)
    return b"\n".join(lines) + (b"\n" if trailing else b""), what


def drop(lines, cards, rng):
    i = rng.choice(cards)
    del lines[i]
    return f"drop line {i + 1}"


def dup(lines, cards, rng):
    i, n = rng.choice(cards), rng.choice([1, 1, 1, 2, 5])
    lines[i:i] = [lines[i]] * n
    return f"duplicate line {i + 1} x{n}"


def swap(lines, cards, rng):
    i = rng.choice(cards)
    near = [j for j in cards if j != i and abs(j - i) <= 3]
    j = rng.choice(near) if rng.random() < 0.6 and near else rng.choice(cards)
    lines[i], lines[j] = lines[j], lines[i]      # (neighbours: the commonest slip)
    return f"swap lines {i + 1} and {j + 1}"


def shift(lines, cards, rng):
    i = rng.choice(cards)
    line, k = lines[i], rng.choice([1, 1, 2, 3, 5, 10])
    at = rng.randrange(len(line) + 1)
    if rng.random() < 0.5:
        lines[i] = line[:at] + b" " * k + line[at:]
        return f"shift line {i + 1} right by {k} at column {at + 1}"
    lines[i] = line[:at] + line[at + k:]
    return f"shift line {i + 1} left by {k} at column {at + 1}"


def numeric_tokens(line):
    return [m for m in NUMBER.finditer(line)
            if (m.start() == 0 or line[m.start() - 1:m.start()] in b" ,&")
            and (m.end() == len(line) or line[m.end():m.end() + 1] in b" ,\r")]


def mutate_field(data, rng, values):
    """One numeric field replaced by one of `values` (a deck without one: a dropped card),
    right-aligned where the token ends; a wider value takes the columns on its left (blanks
    of a right-aligned fixed field, else the neighbour's: junk either way)."""
    def field(lines, cards, rng):
        numeric = [i for i in cards if numeric_tokens(lines[i])]
        if not numeric:
            return drop(lines, cards, rng)
        i = rng.choice(numeric)
        m, value = rng.choice(numeric_tokens(lines[i])), rng.choice(values)
        start, end = m.start(), m.end()
        begin = max(end - len(value), 0)
        lines[i] = lines[i][:start] + b" " * (begin - start) + value + lines[i][end:] \
            if begin >= start else lines[i][:begin] + value + lines[i][end:]
        return f"line {i + 1} columns {start + 1}-{end}: {m.group().decode()} -> {value.decode()}"
    return mutate_lines(data, rng, field)


def truncate(data, rng):
    if rng.random() < 0.3:     # at a line end: a deck that looks complete up to there
        ends = [k + 1 for k, b in enumerate(data) if b == 10]
        at = rng.choice(ends) if ends else 0
    else:
        at = rng.randrange(len(data) + 1)
    return data[:at], f"truncate at byte {at} of {len(data)}"


def binary(data, rng):
    n = rng.choice([1, 1, 2, 4, 16, 64])
    style = rng.choice(["random", "random", "control", "utf8"])
    junk = bytes(rng.randrange(256) for _ in range(n)) if style == "random" else \
        bytes(rng.choice([0, 1, 9, 11, 12, 13, 26, 27, 127]) for _ in range(n)) \
        if style == "control" else ("é°µ—€" * n)[:n].encode()
    at = rng.randrange(len(data) + 1)
    insert = rng.random() < 0.5
    out = data[:at] + junk + data[at + (0 if insert else len(junk)):]
    line = data[:at].count(b"\n") + 1
    return out, f"{'insert' if insert else 'overwrite'} {len(junk)} {style} bytes at byte {at}" \
                f" (line {line}): {junk!r}"


MUTATORS = {"drop": lambda d, r: mutate_lines(d, r, drop),
            "dup": lambda d, r: mutate_lines(d, r, dup),
            "swap": lambda d, r: mutate_lines(d, r, swap),
            "shift": lambda d, r: mutate_lines(d, r, shift),
            "range": lambda d, r: mutate_field(d, r, RANGE_VALUES),
            "text": lambda d, r: mutate_field(d, r, TEXT_VALUES),
            "truncate": truncate, "binary": binary}


def make_mutant(seed, decks):
    """Deck, kind, mutated bytes, description and the draw deciding a full run: a function
    of the seed alone."""
    rng = random.Random(seed)
    kind = KINDS[seed % len(KINDS)]
    deck = decks[rng.randrange(len(decks))]
    data = open(deck, "rb").read()
    mutated, what = MUTATORS[kind](data, rng)
    if mutated == data:   # e.g. a shift inside trailing blanks: still a valid mutant
        what += " (no change)"
    return deck, kind, mutated, what, rng.random()


# ---------------------------------------------------------------------------------------
# Classification.

CRASH_MARKS = ["Fortran runtime error", "Backtrace", "Program received signal",
               "Program aborted", "ERROR STOP", "Segmentation fault", "core dumped",
               "Floating-point exception", "malloc(): ", "double free"]
WHOLE_DECK = ["no END card", "missing group", "no such deck file", "cannot open the deck",
              "cannot read the deck"]
MESSAGE = re.compile(r"^cfrd: (?P<file>.+?):(?P<line>\d+)(:(?P<c1>\d+)-(?P<c2>\d+))?: "
                     r"(?P<text>.+)$")
WORDS = re.compile(rb"[\s\"']+")
NAN_TEXT = re.compile(rb"(?i)(?<![a-z])(nan|[-+]?inf(inity)?)(?![a-z])")


def error_line(stderr):
    lines = [ln for ln in stderr.splitlines() if ln.startswith("cfrd: ") and
             not ln.startswith("cfrd: warning:") and not ln.startswith("cfrd: the ")]
    return lines[-1] if lines else None


def check_message(stderr, path, widths):
    """None when the rejection message is well formed, else why not."""
    line = error_line(stderr)
    if line is None:
        return "no 'cfrd: ' message on stderr"
    m = MESSAGE.match(line)
    if not m:
        if line.startswith("cfrd: " + path + ": ") and any(w in line for w in WHOLE_DECK):
            return None
        return "no FILE:LINE in the message"
    if m["file"] != path:
        return f"the message names file {m['file']!r}, not {path!r}"
    n = int(m["line"])
    if not 1 <= n <= max(len(widths), 1):
        return f"line {n} outside the deck's {len(widths)} lines"
    if m["c1"] is not None:
        c1, c2 = int(m["c1"]), int(m["c2"])
        width = widths[n - 1] if n - 1 < len(widths) else 0
        if not 1 <= c1 <= c2 or c1 > max(width, 80) + 1:
            return f"columns {c1}-{c2} impossible on line {n} ({width} columns)"
        if not (m["text"].startswith("field ") or "character" in m["text"]
                or "beyond column" in m["text"]):
            return "a column range without the field's name"
    return None


def crash_reason(status, stderr):
    if status < 0:
        return f"killed by signal {signal.Signals(-status).name}"
    if status not in (0, 1, 2):
        return f"exit status {status}"
    return next((f"stderr has '{mark}'" for mark in CRASH_MARKS if mark in stderr), None)


def nonfinite_in_outputs(outdir, deck_lines):
    """The first non-finite value in the result files of outdir, or None. A word 'Inf' or
    'NaN' that the deck itself holds with the same neighbours (a label echoed in the
    listing) does not count."""
    deck_words = b" " + b" ".join(b" ".join(c.split()) for c in deck_lines) + b" "
    for name in sorted(os.listdir(outdir)):
        path = os.path.join(outdir, name)
        if name.endswith((".out", ".csv", ".lst", ".xmf")):
            text = open(path, "rb").read()
            for m in NAN_TEXT.finditer(text):
                start, end = text.rfind(b"\n", 0, m.start()) + 1, text.find(b"\n", m.end())
                before = [w for w in WORDS.split(text[start:m.start()]) if w][-1:]
                after = [w for w in WORDS.split(text[m.end():end if end >= 0 else None]) if w]
                context = b" ".join(before + [m.group()] + after[:1])
                if not ((before or after) and b" " + context + b" " in deck_words):
                    line = text[:m.start()].count(b"\n") + 1
                    return f"{name}:{line}: {m.group().decode()}"
        elif name.endswith(".h5"):
            found = []

            def visit(name_, obj):
                for key, value in obj.attrs.items():
                    a = np.asarray(value)
                    if a.dtype.kind in "fc" and not np.all(np.isfinite(a)):
                        found.append(f"{obj.name} attribute {key}")
                if isinstance(obj, h5py.Dataset) and obj.dtype.kind in "fc" and \
                        not np.all(np.isfinite(obj[()])):
                    found.append(obj.name)
            try:
                with h5py.File(path, "r") as f:
                    visit("/", f)
                    f.visititems(lambda n_, o: None if found else visit(n_, o))
            except OSError as e:
                found.append(f"unreadable: {e}")
            if found:
                return f"{name}: {found[0]}"
    return None


def run(cmd, timeout):
    try:
        p = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, timeout=timeout)
    except subprocess.TimeoutExpired:
        return None, ""
    return p.returncode, p.stderr.decode("utf-8", "replace")


def requested_increments(data):
    """Sum of NINC over the STAGES cards (columns 21-25, or the third field of an & card):
    the work a deck asks for. Unreadable fields count 1."""
    total, in_stages = 0, False
    for line in data.replace(b"\r", b"").split(b"\n"):
        if not is_card(line):
            continue
        word, free = line[:10].strip().upper(), line[:1] == b"&"
        if free:
            fields = [f.strip() for f in line[1:].split(b",")]
            word = fields[0].upper()
        if line[:1] not in (b" ", b"&") and word.startswith(b"STAGES"):
            in_stages = True
        elif in_stages and word in (b"FILL", b"LOAD", b"RESET", b"WATER"):
            text = fields[2] if free and len(fields) > 2 else b"" if free else line[20:25]
            try:
                total += max(int(text.strip() or b"1"), 1)
            except ValueError:
                total += 1
        elif in_stages and line[:1] not in (b" ", b"&"):
            in_stages = False
    return max(total, 1)


def classify(job):
    seed, cfrd, decks, root, full_large, keep = job
    deck, kind, data, what, full = make_mutant(seed, decks)
    workdir = os.path.join(root, str(seed))
    shutil.rmtree(workdir, ignore_errors=True)
    os.makedirs(workdir)
    path = os.path.join(workdir, os.path.basename(deck))
    with open(path, "wb") as f:
        f.write(data)
    text_lines = data.replace(b"\r", b"").split(b"\n")
    if text_lines and text_lines[-1] == b"":
        text_lines.pop()
    widths = [len(x) for x in text_lines]
    # Small decks: every other accepted mutant in full; large ones 1 in full_large (0: none;
    # -1: every accepted mutant, as --reproduce does).
    full_run = full_large < 0 or (full < 0.5 if os.path.getsize(deck) <= SMALL_DECK_BYTES
                                  else full_large > 0 and full < 1.0 / full_large)
    work = requested_increments(data) / requested_increments(open(deck, "rb").read())
    outcome, detail, ran = None, "", False
    status, stderr = run([cfrd, "--check", path], CHECK_TIMEOUT)
    if status is None:
        outcome, detail = "hang", f"--check took more than {CHECK_TIMEOUT:.0f} s"
    elif crash_reason(status, stderr):
        outcome, detail = "crash", "--check: " + crash_reason(status, stderr)
    elif status == 2:
        bad = check_message(stderr, path, widths)
        outcome, detail = ("message", bad) if bad else ("rejected", "")
    elif status == 1:
        # --check reads and validates only: exit 1 would be a file failure.
        outcome, detail = ("failed", "") if error_line(stderr) else \
            ("message", "exit 1 without a 'cfrd: ' message")
    elif full_run and work > 10:
        # A valid deck that asks for far more increments (NINC up to 100000) than the
        # original is slow, not hung: it is read and checked, not run.
        outcome, detail = "accepted", f"not run: {work:.0f} times the increments of {deck}"
    elif full_run:
        ran = True
        outdir = os.path.join(workdir, "out")
        os.makedirs(outdir)
        t0 = time.monotonic()
        status, stderr = run([cfrd, "--quiet", "--out", outdir, path], RUN_TIMEOUT)
        if status is None:
            outcome, detail = "hang", f"the run took more than {RUN_TIMEOUT:.0f} s"
        elif crash_reason(status, stderr):
            outcome, detail = "crash", "run: " + crash_reason(status, stderr)
        elif (bad := nonfinite_in_outputs(outdir, text_lines)):
            outcome, detail = "nan", bad
        elif status == 0:
            outcome = "ran"
        elif status == 2:
            bad = check_message(stderr, path, widths)
            outcome, detail = ("message", "run: " + bad) if bad else ("rejected", "")
        else:
            outcome, detail = ("failed", "") if error_line(stderr) else \
                ("message", "run: exit 1 without a 'cfrd: ' message")
        detail += f" ({time.monotonic() - t0:.1f} s)" if outcome in FAILURES else ""
    else:
        outcome = "accepted"
    if outcome in FAILURES or keep:
        with open(os.path.join(workdir, "repro.txt"), "w") as f:
            f.write(f"seed {seed}\ndeck {deck}\nkind {kind}\nmutation {what}\n"
                    f"outcome {outcome}: {detail}\nfull run {ran}\n"
                    f"reproduce: python3 tools/fuzz.py --cfrd {cfrd} --reproduce {seed}\n"
                    f"stderr:\n{stderr}")
    else:
        shutil.rmtree(workdir, ignore_errors=True)
    message = error_line(stderr) or "" if status is not None else ""
    return seed, deck, kind, what, outcome, detail, ran, message


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--cfrd", default="bin/cfrd")
    ap.add_argument("--decks", default="inputs/*.dat", help="glob of the decks to mutate")
    ap.add_argument("--count", type=int, default=10000)
    ap.add_argument("--seed", type=int, default=1, help="first seed; mutants SEED..SEED+N-1")
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--full-large", type=int, default=10, metavar="N",
                    help="run 1 in N accepted mutants of large decks in full (0: none); "
                         "of small decks (under 10 kB), 1 in 2")
    ap.add_argument("--workdir", default="build/fuzz/run")
    ap.add_argument("--reproduce", type=int, metavar="SEED",
                    help="write mutant SEED again, print its mutation and classify it")
    args = ap.parse_args()
    decks = sorted(glob.glob(args.decks))
    if not decks:
        sys.exit(f"fuzz: no decks match {args.decks}")
    cfrd = os.path.abspath(args.cfrd) if os.sep in args.cfrd else args.cfrd
    if args.reproduce is not None:
        root = os.path.join(os.path.dirname(args.workdir) or ".", f"repro-{args.reproduce}")
        os.makedirs(root, exist_ok=True)
        r = classify((args.reproduce, cfrd, decks, root, -1, True))
        print(f"seed {r[0]}: {r[1]}, {r[2]}: {r[3]}\noutcome: {r[4]} {r[5]}\n"
              f"mutant and output: {os.path.join(root, str(r[0]))}/")
        sys.exit(1 if r[4] in FAILURES else 0)
    shutil.rmtree(args.workdir, ignore_errors=True)
    os.makedirs(args.workdir)
    t0, results = time.monotonic(), []
    with multiprocessing.Pool(max(1, args.jobs)) as pool:
        for r in pool.imap_unordered(classify, [
                (s, cfrd, decks, args.workdir, args.full_large, False)
                for s in range(args.seed, args.seed + args.count)], chunksize=4):
            results.append(r)
            if r[4] in FAILURES:
                print(f"  {r[4]}: seed {r[0]} ({os.path.basename(r[1])}, {r[3]}): {r[5]}",
                      flush=True)
    elapsed = time.monotonic() - t0
    results.sort()
    with open(os.path.join(args.workdir, "mutants.tsv"), "w") as f:
        f.write("seed\tdeck\tkind\tmutation\toutcome\tfull_run\tdetail\tmessage\n")
        f.writelines("\t".join(str(x).replace("\t", " ").replace("\n", " ") for x in
                               (r[0], r[1], r[2], r[3], r[4], r[6], r[5], r[7])) + "\n"
                     for r in results)
    counts = {k: {o: sum(1 for r in results if r[2] == k and r[4] == o) for o in OUTCOMES}
              for k in KINDS}
    total = {o: sum(c[o] for c in counts.values()) for o in OUTCOMES}
    print(f"fuzz: {len(results)} mutants of {len(decks)} decks (seeds {args.seed}.."
          f"{args.seed + args.count - 1}), {sum(1 for r in results if r[6])} run in full, "
          f"{elapsed:.0f} s, {args.jobs} jobs, {cfrd}")
    print(tables.markdown(["mutation", "mutants"] + OUTCOMES,
                          [[k, sum(counts[k].values())] + [counts[k][o] for o in OUTCOMES]
                           for k in KINDS] + [["all", len(results)] + [total[o] for o in
                                                                      OUTCOMES]]))
    check = Checks("fuzz")
    for failure, name, word in (("crash", "crashes", "crashes"), ("hang", "hangs", "hangs"),
                                ("message", "messages", "bad rejection messages"),
                                ("nan", "nan", "non-finite results")):
        n = total[failure]
        check(name, n == 0, f"{n} {word} in {len(results)} mutants (seed {args.seed})"
              + ("" if n == 0 else f"; kept in {args.workdir}/"))
    sys.exit(check.status)


if __name__ == "__main__":
    main()
