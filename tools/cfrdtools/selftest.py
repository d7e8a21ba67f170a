"""The package's own checks: python3 -m cfrdtools.selftest (from tools/, or PYTHONPATH=tools).

decks: fields and cards against hand-written card strings, a deck read back by group;
results: a tiny HDF5 written here by h5py; runner: a deck written and a stand-in program run;
tables: a small table. One PASS/FAIL line each."""

import os
import sys
import tempfile

import h5py
import numpy as np

from cfrdtools import decks, results, runner, tables
from cfrdtools.checks import Checks

check = Checks("cfrdtools")


def overflow(fn, *args):
    try:
        fn(*args)
    except decks.FieldOverflow:
        return True
    return False


def test_decks():
    cases = [(decks.fmt_int(12), "   12"), (decks.fmt_int(-3, 3), " -3"),
             (decks.fmt_real(255.2), "     255.2"), (decks.fmt_real(0.0), "       0.0"),
             (decks.fmt_real(-0.5), "      -0.5"), (decks.fmt_real(1.0e-10), "1.0000E-10"),
             (decks.fmt_real(0.0075679160123), ".007567916"),
             (decks.fmt_real(60.0e3), "   60000.0"), (decks.fmt_alpha("KN-M"), "KN-M      "),
             (decks.free_real(1.0e-10), "1E-10"), (decks.free_real(0.1), "0.1")]
    bad = [(s, w) for s, w in cases if s != w]
    check("decks/fields", not bad, f"{len(cases)} fields" + (f"; wrong: {bad}" if bad else ""))
    over = [overflow(decks.fmt_int, 123456), overflow(decks.fmt_real, 1.23456789e-300),
            overflow(decks.fmt_real, float("nan")), overflow(decks.fmt_alpha, "ELEVENCHARS")]
    check("decks/overflow", all(over), f"{sum(over)} of {len(over)} refused")
    fields = [("i", 3), ("r", 2.5), ("a", "SOIL"), ("r", None), ("i", None)]
    cards = [decks.card(fields), decks.card(fields, free=True), decks.free(1, None, 0.5, "X")]
    want = ["    3       2.5SOIL", "&3, 2.5, SOIL", "&1, , 0.5, X"]
    check("decks/cards", cards == want, str(cards))
    text = ("TITLE     t\n* a comment\nMATERIALS\n    1ELASTIC   soil\n   20000.0       0.3"
            "      20.0\n    2EB        rock\n      21.0     564.0\n      51.0\n"
            "    3GOODMAN   joint\n     1.0E7\nEND\n")
    got = ([g for g, _ in decks.groups(text)], decks.unit_weights(text))
    want = (["TITLE", "MATERIALS", "END"], {1: 20.0, 2: 21.0, 3: 0.0})
    check("decks/groups", got == want, str(got))


def test_results(tmp):
    path = os.path.join(tmp, "tiny.h5")
    with h5py.File(path, "w") as f:
        for s in (2, 1, 3):                     # written out of order on purpose
            f[f"stages/stage_{s:04d}/displacement"] = np.full((2, 2), float(s))
    with results.open_results(path) as f:
        names = results.stage_names(f)
        check("results/stage-names", names == ["stage_0001", "stage_0002", "stage_0003"],
              str(names))
        last, two = results.read(f, "displacement"), results.read(f, "displacement", 2)
        check("results/read", last[0, 0] == 3.0 and two[1, 1] == 2.0,
              f"last {last[0, 0]}, stage 2 {two[1, 1]}")
        hist = [float(v) for v in results.series(f, "displacement", (0, 1))]
        check("results/series", hist == [1.0, 2.0, 3.0], str(hist))


def test_runner(tmp):
    fake = os.path.join(tmp, "fake-cfrd")
    with open(fake, "w") as f:                   # writes DECK.h5; fails on decks holding FAIL
        f.write(f"#!{sys.executable}\nimport sys\nd = sys.argv[-1]\n"
                "if 'FAIL' in open(d).read(): sys.exit('bad deck')\n"
                "open(d[:-4] + '.h5', 'w').write('')\n")
    os.chmod(fake, 0o755)
    h5 = runner.run_text(fake, os.path.join(tmp, "sub", "a.dat"), ["TITLE", "END"])
    check("runner/run-text", os.path.exists(h5) and h5.endswith("a.h5"), h5)
    try:
        runner.run_text(fake, os.path.join(tmp, "b.dat"), "FAIL\n")
        refused = False
    except runner.CfrdFailed as e:
        refused = "bad deck" in str(e)
    check("runner/failure", refused, "a non-zero exit raises CfrdFailed with stderr")
    decks_ = [runner.write_deck(os.path.join(tmp, f"m{i}.dat"), "FAIL\n" if i == 1 else "OK\n")
              for i in range(3)]
    codes = [d.returncode for d in runner.run_many(fake, decks_, jobs=2)]
    check("runner/many", codes[0] == 0 and codes[1] != 0 and codes[2] == 0, str(codes))


def test_tables():
    got = tables.markdown(["a", "b"], [["1", "x|y"]], "lr").split("\n") + \
        tables.aligned(["a", "bb"], [["xyz", "1"]], right={1}).split("\n")
    want = ["| a | b |", "|:---|---:|", "| 1 | x\\|y |", "a    bb", "---  --", "xyz   1"]
    check("tables", got == want, str(got))


def main():
    with tempfile.TemporaryDirectory() as tmp:
        test_decks()
        test_results(tmp)
        test_runner(tmp)
        test_tables()
    return check.status


if __name__ == "__main__":
    sys.exit(main())
