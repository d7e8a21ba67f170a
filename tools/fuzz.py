#!/usr/bin/env python3
"""Fuzzing harness for the deck reader (issue 9, section 4; docs/robustness.md).

Every mutant is one deck of inputs/*.dat changed by one seeded mutation:

  drop       a card deleted                  dup        a card duplicated
  swap       two cards exchanged             shift      a card's columns shifted left/right
  range      a numeric field out of range    text       a numeric field made non-numeric
  truncate   the file cut at a random byte   binary     random bytes inserted or overwritten

The mutant is read with `cfrd --check`; a deterministic fraction of the accepted ones is also
run in full (--out a fresh directory). Each outcome is one of

  rejected   exit 2, one message `cfrd: FILE:LINE[:C1-C2]: ...` (a field message names the
             field: `FILE:LINE:C1-C2: field NAME of ...`); only a whole-deck problem (missing
             group, no END card) may name no line
  accepted   --check exit 0, not run in full (a mutant asking for over 10 times its deck's
             increments is never run: valid and slow, not hung)
  ran        the full run exited 0, every result finite
  failed     the full run exited 1 with a `cfrd: ` diagnostic, every result finite
and the failures are
  crash      a signal, a Fortran runtime error or backtrace, an exit status other than 0/1/2
  hang       no answer within the timeout (--check: 20 s; a full run: 60 s, while every
             unmutated deck runs in 3 s)
  message    a rejection whose message lacks FILE:LINE (or names a line or column the mutant
             does not have, or a column range without the field)
  nan        NaN or Inf in a written result: the listing, a CSV, the XDMF file (not a word
             of the deck's own labels) or a float dataset or attribute of an HDF5 file

A mutant is determined by its seed alone: `tools/fuzz.py --reproduce SEED` writes it again
(build/fuzz/repro-SEED/), prints the mutation and runs it. Failed mutants are kept in
build/fuzz/RUN/SEED/ with repro.txt; the others are deleted.

Usage: tools/fuzz.py [--cfrd bin/cfrd] [--count 10000] [--seed 1] [--jobs 2] [--full-large N]
Prints PASS/FAIL lines (fuzz/crashes, fuzz/hangs, fuzz/messages, fuzz/nan) and a summary table;
exit status 1 if any mutant failed.
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

KINDS = ["drop", "dup", "swap", "shift", "range", "text", "truncate", "binary"]
OUTCOMES = ["rejected", "accepted", "ran", "failed", "crash", "hang", "message", "nan"]
FAILURES = ["crash", "hang", "message", "nan"]
SMALL_DECK_BYTES = 10000      # decks that run in well under a second: run every 1 in 2
CHECK_TIMEOUT = 20.0
RUN_TIMEOUT = 60.0

# ---------------------------------------------------------------------------------------
# Mutations. Each takes the deck's bytes and a random.Random, returns (bytes, description).


def split_lines(data):
    lines = data.split(b"\n")
    trailing = lines and lines[-1] == b""
    if trailing:
        lines.pop()
    return lines, trailing


def join_lines(lines, trailing):
    return b"\n".join(lines) + (b"\n" if trailing else b"")


def is_card(line):
    """Not a comment or blank line (the same rule as the reader's is_comment)."""
    s = line.rstrip(b"\r")
    if not s.strip():
        return False
    if s[:1] == b"*":
        return False
    if s[:1] in (b"C", b"c") and (len(s) == 1 or s[1:2] == b" "):
        return False
    return True


def card_indices(lines):
    return [i for i, line in enumerate(lines) if is_card(line)] or list(range(len(lines)))


NUMBER = re.compile(rb"[-+]?(\d+\.?\d*|\.\d+)([eEdD][-+]?\d+)?")


def numeric_tokens(line):
    return [m for m in NUMBER.finditer(line)
            if (m.start() == 0 or line[m.start() - 1:m.start()] in b" ,&")
            and (m.end() == len(line) or line[m.end():m.end() + 1] in b" ,\r")]


def mutate_drop(data, rng):
    lines, trailing = split_lines(data)
    i = rng.choice(card_indices(lines))
    del lines[i]
    return join_lines(lines, trailing), f"drop line {i + 1}"


def mutate_dup(data, rng):
    lines, trailing = split_lines(data)
    i = rng.choice(card_indices(lines))
    n = rng.choice([1, 1, 1, 2, 5])
    lines[i:i] = [lines[i]] * n
    return join_lines(lines, trailing), f"duplicate line {i + 1} x{n}"


def mutate_swap(data, rng):
    lines, trailing = split_lines(data)
    cards = card_indices(lines)
    i = rng.choice(cards)
    if rng.random() < 0.6:     # neighbours: the commonest slip
        near = [j for j in cards if j != i and abs(j - i) <= 3]
        j = rng.choice(near) if near else rng.choice(cards)
    else:
        j = rng.choice(cards)
    lines[i], lines[j] = lines[j], lines[i]
    return join_lines(lines, trailing), f"swap lines {i + 1} and {j + 1}"


def mutate_shift(data, rng):
    lines, trailing = split_lines(data)
    i = rng.choice(card_indices(lines))
    line = lines[i]
    k = rng.choice([1, 1, 2, 3, 5, 10])
    at = rng.randrange(len(line) + 1)
    if rng.random() < 0.5:
        lines[i] = line[:at] + b" " * k + line[at:]
        what = f"shift line {i + 1} right by {k} at column {at + 1}"
    else:
        lines[i] = line[:at] + line[at + k:]
        what = f"shift line {i + 1} left by {k} at column {at + 1}"
    return join_lines(lines, trailing), what


RANGE_VALUES = [b"0", b"-1", b"-0", b"-0.0", b"0.0", b"1", b"2", b"-999", b"99999",
                b"999999999", b"-99999999", b"2147483647", b"2147483648", b"1e30", b"-1e30",
                b"1e-30", b"1e19", b"-9e19", b"1e20", b"1e307", b"-1e307", b"1e308", b"9e999",
                b"1e-320", b"1e-999",
                b"0.4999999", b"0.5", b"1.5", b"-1.5", b"360", b"-90", b"100000"]
TEXT_VALUES = [b"abc", b"NaN", b"nan", b"Inf", b"-inf", b"1.2.3", b"1e", b"e5", b"--1",
               b"+-1", b".", b"-", b"+", b"1,5", b"1 0", b"0x10", b"1d", b"1e+", b"*", b"?",
               b"ELASTIC", b"1_dp", b"(1)", b"O", b"l0", b"1/2", b"'1'"]


def pick_field(data, rng):
    lines, trailing = split_lines(data)
    cards = [i for i in card_indices(lines) if numeric_tokens(lines[i])]
    if not cards:
        return None
    i = rng.choice(cards)
    m = rng.choice(numeric_tokens(lines[i]))
    return lines, trailing, i, m


def replace_field(line, m, value):
    """Right-align value where the token ends; a wider value takes the columns on its left
    (blanks in a right-aligned fixed-format field, else the neighbour: junk either way)."""
    start, end = m.start(), m.end()
    begin = max(end - len(value), 0)
    if begin >= start:
        return line[:start] + b" " * (begin - start) + value + line[end:]
    return line[:begin] + value + line[end:]


def mutate_field(data, rng, values):
    """One numeric field replaced by one of `values` (a deck without one: a dropped card)."""
    picked = pick_field(data, rng)
    if picked is None:
        return mutate_drop(data, rng)
    lines, trailing, i, m = picked
    value = rng.choice(values)
    lines[i] = replace_field(lines[i], m, value)
    return join_lines(lines, trailing), (f"line {i + 1} columns {m.start() + 1}-{m.end()}: "
                                         f"{m.group().decode()} -> {value.decode()}")


def mutate_range(data, rng):
    return mutate_field(data, rng, RANGE_VALUES)


def mutate_text(data, rng):
    return mutate_field(data, rng, TEXT_VALUES)


def mutate_truncate(data, rng):
    if rng.random() < 0.3:     # at a line end: a deck that looks complete up to there
        ends = [k + 1 for k, b in enumerate(data) if b == 10]
        at = rng.choice(ends) if ends else 0
    else:
        at = rng.randrange(len(data) + 1)
    return data[:at], f"truncate at byte {at} of {len(data)}"


def mutate_binary(data, rng):
    n = rng.choice([1, 1, 2, 4, 16, 64])
    style = rng.choice(["random", "random", "control", "utf8"])
    if style == "random":
        junk = bytes(rng.randrange(256) for _ in range(n))
    elif style == "control":
        junk = bytes(rng.choice([0, 1, 9, 11, 12, 13, 26, 27, 127]) for _ in range(n))
    else:
        junk = ("é°µ—€" * n)[:n].encode()
    at = rng.randrange(len(data) + 1)
    if rng.random() < 0.5:
        out = data[:at] + junk + data[at:]
        what = "insert"
    else:
        out = data[:at] + junk + data[at + len(junk):]
        what = "overwrite"
    line = data[:at].count(b"\n") + 1
    return out, f"{what} {len(junk)} {style} bytes at byte {at} (line {line}): {junk!r}"


MUTATORS = {"drop": mutate_drop, "dup": mutate_dup, "swap": mutate_swap,
            "shift": mutate_shift, "range": mutate_range, "text": mutate_text,
            "truncate": mutate_truncate, "binary": mutate_binary}


def decks_of(pattern):
    return sorted(glob.glob(pattern))


def make_mutant(seed, decks):
    """Deck, kind, mutated bytes and description: a function of the seed alone."""
    rng = random.Random(seed)
    kind = KINDS[seed % len(KINDS)]
    deck = decks[rng.randrange(len(decks))]
    with open(deck, "rb") as f:
        data = f.read()
    mutated, what = MUTATORS[kind](data, rng)
    if mutated == data:   # e.g. a shift inside trailing blanks: still a valid mutant
        what += " (no change)"
    full = rng.random()   # decides whether an accepted mutant also runs in full
    return deck, kind, mutated, what, full


# ---------------------------------------------------------------------------------------
# Classification.

CRASH_MARKS = ["Fortran runtime error", "Backtrace", "Program received signal",
               "Program aborted", "ERROR STOP", "Segmentation fault", "core dumped",
               "Floating-point exception", "malloc(): ", "double free"]
WHOLE_DECK = ["no END card", "missing group", "no such deck file", "cannot open the deck",
              "cannot read the deck"]
MESSAGE = re.compile(r"^cfrd: (?P<file>.+?):(?P<line>\d+)(:(?P<c1>\d+)-(?P<c2>\d+))?: (?P<text>.+)$")
WORDS = re.compile(rb"[\s\"']+")
NAN_TEXT = re.compile(rb"(?i)(?<![a-z])(nan|[-+]?inf(inity)?)(?![a-z])")


def error_line(stderr):
    lines = [ln for ln in stderr.splitlines()
             if ln.startswith("cfrd: ") and not ln.startswith("cfrd: warning:")
             and not ln.startswith("cfrd: the ")]
    return lines[-1] if lines else None


def check_message(stderr, path, deck_lines, deck_widths):
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
    if not 1 <= n <= max(deck_lines, 1):
        return f"line {n} outside the deck's {deck_lines} lines"
    if m["c1"] is not None:
        c1, c2 = int(m["c1"]), int(m["c2"])
        width = deck_widths[n - 1] if n - 1 < len(deck_widths) else 0
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
    for mark in CRASH_MARKS:
        if mark in stderr:
            return f"stderr has '{mark}'"
    return None


def nonfinite_in_outputs(outdir, deck_lines):
    """The first non-finite value in the result files of outdir, or None. A word 'Inf' or
    'NaN' that the deck itself holds with the same neighbours (in a label echoed in the
    listing) does not count."""
    deck_words = b" " + b" ".join(b" ".join(c.split()) for c in deck_lines) + b" "
    for name in sorted(os.listdir(outdir)):
        path = os.path.join(outdir, name)
        if name.endswith((".out", ".csv", ".lst", ".xmf")):
            with open(path, "rb") as f:
                text = f.read()
            for m in NAN_TEXT.finditer(text):
                start = text.rfind(b"\n", 0, m.start()) + 1
                end = text.find(b"\n", m.end())
                before = [w for w in WORDS.split(text[start:m.start()]) if w][-1:]
                after = [w for w in WORDS.split(text[m.end():end if end >= 0 else None]) if w]
                context = b" ".join(before + [m.group()] + after[:1])
                if (before or after) and b" " + context + b" " in deck_words:
                    continue
                number = text[:m.start()].count(b"\n") + 1
                return f"{name}:{number}: {m.group().decode()}"
        elif name.endswith(".h5"):
            bad = nonfinite_in_h5(path)
            if bad:
                return f"{name}: {bad}"
    return None


def nonfinite_in_h5(path):
    import h5py
    import numpy as np
    found = []

    def attrs(obj):
        for key, value in obj.attrs.items():
            a = np.asarray(value)
            if a.dtype.kind in "fc" and not np.all(np.isfinite(a)):
                found.append(f"{obj.name} attribute {key}")

    def visit(name, obj):
        if found:
            return
        attrs(obj)
        if isinstance(obj, h5py.Dataset) and obj.dtype.kind in "fc":
            if not np.all(np.isfinite(obj[()])):
                found.append(obj.name)
    try:
        with h5py.File(path, "r") as f:
            attrs(f)
            f.visititems(visit)
    except OSError as e:
        return f"unreadable: {e}"
    return found[0] if found else None


def run(cmd, timeout):
    try:
        p = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                           timeout=timeout)
    except subprocess.TimeoutExpired:
        return None, ""
    return p.returncode, p.stderr.decode("utf-8", "replace")


def work_factor(deck, data):
    with open(deck, "rb") as f:
        return requested_increments(data) / requested_increments(f.read())


def full_run_wanted(deck, full, full_large):
    """Small decks: every other accepted mutant; large ones: 1 in full_large (0: none; -1:
    every accepted mutant of every deck, as --reproduce does)."""
    if full_large < 0:
        return True
    if os.path.getsize(deck) <= SMALL_DECK_BYTES:
        return full < 0.5
    return full_large > 0 and full < 1.0 / full_large


STAGE_WORDS = (b"FILL", b"LOAD", b"RESET", b"WATER")


def requested_increments(data):
    """Sum of NINC over the STAGES cards (columns 21-25, or the third field of an & card):
    the work a deck asks for. Unreadable fields count 1."""
    total, in_stages = 0, False
    for line in data.replace(b"\r", b"").split(b"\n"):
        if not is_card(line):
            continue
        word = line[:10].strip().upper()
        free = line[:1] == b"&"
        if free:
            fields = [f.strip() for f in line[1:].split(b",")]
            word = fields[0].upper()
        if line[:1] not in (b" ", b"&") and word.startswith(b"STAGES"):
            in_stages = True
            continue
        if not in_stages:
            continue
        if word in STAGE_WORDS:
            text = fields[2] if free and len(fields) > 2 else b"" if free else line[20:25]
            try:
                total += max(int(text.strip() or b"1"), 1)
            except ValueError:
                total += 1
        elif line[:1] not in (b" ", b"&"):
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
    outcome, detail, ran = None, "", False
    status, stderr = run([cfrd, "--check", path], CHECK_TIMEOUT)
    if status is None:
        outcome, detail = "hang", f"--check took more than {CHECK_TIMEOUT:.0f} s"
    elif crash_reason(status, stderr):
        outcome, detail = "crash", "--check: " + crash_reason(status, stderr)
    elif status == 2:
        bad = check_message(stderr, path, len(text_lines), widths)
        outcome, detail = ("message", bad) if bad else ("rejected", "")
    elif status == 1:
        # --check reads and validates only: exit 1 would be a file failure.
        outcome, detail = ("failed", "") if error_line(stderr) else \
            ("message", "exit 1 without a 'cfrd: ' message")
    elif full_run_wanted(deck, full, full_large) and work_factor(deck, data) > 10:
        # A valid deck that asks for far more increments (NINC up to 100000) than the
        # original is slow, not hung: it is read and checked, not run.
        outcome = "accepted"
        detail = f"not run: {work_factor(deck, data):.0f} times the increments of {deck}"
    elif full_run_wanted(deck, full, full_large):
        ran = True
        outdir = os.path.join(workdir, "out")
        os.makedirs(outdir)
        t0 = time.monotonic()
        status, stderr = run([cfrd, "--quiet", "--out", outdir, path], RUN_TIMEOUT)
        if status is None:
            outcome, detail = "hang", f"the run took more than {RUN_TIMEOUT:.0f} s"
        elif crash_reason(status, stderr):
            outcome, detail = "crash", "run: " + crash_reason(status, stderr)
        else:
            bad = nonfinite_in_outputs(outdir, text_lines)
            if bad:
                outcome, detail = "nan", bad
            elif status == 0:
                outcome = "ran"
            elif status == 2:
                bad = check_message(stderr, path, len(text_lines), widths)
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


# ---------------------------------------------------------------------------------------


def table(results):
    counts = {k: {o: 0 for o in OUTCOMES} for k in KINDS}
    for _, _, kind, _, outcome, _, _, _ in results:
        counts[kind][outcome] += 1
    head = "| mutation | mutants | " + " | ".join(OUTCOMES) + " |"
    rows = [head, "|" + "---|" * (len(OUTCOMES) + 2)]
    total = {o: 0 for o in OUTCOMES}
    for k in KINDS:
        n = sum(counts[k].values())
        rows.append(f"| {k} | {n} | " + " | ".join(str(counts[k][o]) for o in OUTCOMES) + " |")
        for o in OUTCOMES:
            total[o] += counts[k][o]
    rows.append(f"| all | {len(results)} | " + " | ".join(str(total[o]) for o in OUTCOMES)
                + " |")
    return "\n".join(rows), total


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
    decks = decks_of(args.decks)
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
    jobs = [(s, cfrd, decks, args.workdir, args.full_large, False)
            for s in range(args.seed, args.seed + args.count)]
    t0 = time.monotonic()
    results = []
    with multiprocessing.Pool(max(1, args.jobs)) as pool:
        for r in pool.imap_unordered(classify, jobs, chunksize=4):
            results.append(r)
            if r[4] in FAILURES:
                print(f"  {r[4]}: seed {r[0]} ({os.path.basename(r[1])}, {r[3]}): {r[5]}",
                      flush=True)
    elapsed = time.monotonic() - t0
    results.sort()
    with open(os.path.join(args.workdir, "mutants.tsv"), "w") as f:
        f.write("seed\tdeck\tkind\tmutation\toutcome\tfull_run\tdetail\tmessage\n")
        for r in results:
            f.write("\t".join(str(x).replace("\t", " ").replace("\n", " ") for x in
                              (r[0], r[1], r[2], r[3], r[4], r[6], r[5], r[7])) + "\n")
    text, total = table(results)
    ran = sum(1 for r in results if r[6])
    print(f"fuzz: {len(results)} mutants of {len(decks)} decks (seeds {args.seed}.."
          f"{args.seed + args.count - 1}), {ran} run in full, {elapsed:.0f} s, "
          f"{args.jobs} jobs, {cfrd}")
    print(text)
    for failure, name in [("crash", "crashes"), ("hang", "hangs"), ("message", "messages"),
                          ("nan", "nan")]:
        n = total[failure]
        verdict = "PASS" if n == 0 else "FAIL"
        word = {"crash": "crashes", "hang": "hangs", "message": "bad rejection messages",
                "nan": "non-finite results"}[failure]
        print(f"{verdict} fuzz/{name}: {n} {word} in {len(results)} mutants (seed {args.seed})"
              + ("" if n == 0 else f"; kept in {args.workdir}/"))
    sys.exit(1 if any(total[f] for f in FAILURES) else 0)


if __name__ == "__main__":
    main()
