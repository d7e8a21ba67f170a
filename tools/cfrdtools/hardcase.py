"""The machinery of tools/hard_cases.py (docs/robustness.md, hard cases): the free-format deck
writer, decks made from committed or generated ones, one cfrd run read back per stage, and
the checks every case shares (exit status, NaN, diagnostics, Newton's balance)."""
import os
import shutil
import tempfile

import h5py
import numpy as np

from cfrdtools import results, runner
from cfrdtools.checks import Checks
from cfrdtools.decks import free


DECKS = os.path.join(runner.ROOT, "test", "hard_cases")


class Deck:
    """A deck of free-format cards (docs/cards.md section 1)."""

    def __init__(self, title):
        self.title = title
        self.nodes, self.elems = [], []      # (x, y); (n1..n4, mat, group, type)
        self.materials, self.boundary, self.loads = [], [], {"": []}
        self.contact, self.interface, self.reservoir, self.stages = [], [], [], []
        self.control = None

    def rect(self, x0, y0, w, h, nx, ny, mat, group, etype=""):
        """A block of nx x ny quads, its own nodes; returns (node grid [j][i], elem grid)."""
        first = len(self.nodes) + 1
        self.nodes += [(x0 + w * i / nx, y0 + h * j / ny) for j in range(ny + 1)
                       for i in range(nx + 1)]
        grid = [[first + j * (nx + 1) + i for i in range(nx + 1)] for j in range(ny + 1)]
        elems = []
        for j in range(ny):
            for i in range(nx):
                a = grid[j][i]
                self.elems.append((a, a + 1, a + nx + 2, a + nx + 1, mat, group, etype))
            elems.append(list(range(len(self.elems) - nx + 1, len(self.elems) + 1)))
        return grid, elems

    def fix(self, nodes, ix, iy, ux=None, uy=None):
        self.boundary += [f"&{n}, {n}, 1, {ix}, {iy}, {'' if ux is None else repr(ux)}, "
                          f"{'' if uy is None else repr(uy)}" for n in nodes]

    def text(self):
        out = [f"* {self.title}", "* written by tools/hard_cases.py --write (issue 9, section 2)",
               "TITLE     " + self.title[:70]] + (["CONTROL", self.control] if self.control else [])
        out += ["NODES"] + [f"&{k}, , , {x!r}, {y!r}" for k, (x, y) in enumerate(self.nodes, 1)]
        out += ["ELEMENTS"] + [f"&{k}, {a}, {b}, {c}, {d}, {m}, 0, 1, {g}, {t}"
                               for k, (a, b, c, d, m, g, t) in enumerate(self.elems, 1)]
        out += ["MATERIALS"] + self.materials + ["BOUNDARY"] + self.boundary
        for name, cards in self.loads.items():
            out += [("LOADS     " + name).rstrip()] + cards if cards else []
        for group, cards in (("INTERFACE", self.interface), ("RESERVOIR", self.reservoir),
                             ("CONTACT", self.contact), ("STAGES", self.stages)):
            out += [group] + cards if cards else []
        return "\n".join(out + ["END"]) + "\n"


def elastic(k, label, e, nu, gamma=0.0):
    return [f"&{k}, ELASTIC, {label}", free(e, nu, gamma)]


def oedometric(e, nu):
    """Constrained modulus M = E (1 - nu) / ((1 + nu)(1 - 2 nu)) (plane strain, ux = 0)."""
    return e * (1 - nu) / ((1 + nu) * (1 - 2 * nu))


def pressures(elements, p, face=3):
    return [f"&PRESSURE, {e}, {face}, {p!r}, {p!r}" for e in elements]


class Derived:
    """A deck made from a committed one by replacing lines (text() as Deck's)."""

    def __init__(self, name, header, replace):
        self.name, self.header, self.replace = name, header, replace

    def text(self):
        text = open(os.path.join(DECKS, self.name)).read()
        for old, new in self.replace:
            if old not in text:
                raise SystemExit(f"{self.name}: no line {old!r} to replace")
            text = text.replace(old, new)
        return self.header + text


class Generated:
    """A Tianshengqiao-I deck of tools/tianshengqiao.py OPTIONS with its one contact pair's
    search LINEAR replaced by RPIM (text() as Deck's)."""

    def __init__(self, header, *options):
        self.header, self.options = header, options

    def text(self):
        with tempfile.TemporaryDirectory() as tmp:
            text = open(runner.tianshengqiao(os.path.join(tmp, "deck.dat"),
                                             *self.options)).read()
        if text.count("MORTAR    LINEAR ") != 1:
            raise SystemExit("tianshengqiao.py: not one MORTAR LINEAR pair to make RPIM")
        return self.header + text.replace("MORTAR    LINEAR ", "MORTAR    RPIM   ")


class Run:
    """One cfrd run of a deck copied into the work directory: exit status, stderr, and per
    stage of its results (or of DECK.incomplete.h5) the datasets the checks read."""

    def __init__(self, cfrd, workdir, name, earlier=None):
        self.deck = shutil.copy(os.path.join(DECKS, name), os.path.join(workdir, name))
        self.h5, self.incomplete = self.deck[:-4] + ".h5", self.deck[:-4] + ".incomplete.h5"
        for path in (self.h5, self.incomplete):
            if os.path.exists(path):
                os.remove(path)
        if earlier is not None:       # the results of an earlier run, to be left untouched
            open(self.h5, "wb").write(earlier)
        run = runner.run(os.path.abspath(cfrd), os.path.abspath(self.deck), check=False)
        self.status, self.stderr = run.returncode, run.stderr.strip()
        self.stages, self.nonfinite = [], []
        path = self.h5 if self.status == 0 else self.incomplete
        if not os.path.exists(path):
            return
        with h5py.File(path, "r") as f:
            f.visititems(self._finite)
            for g in results.stages(f):
                stage = {k: results.field(g, k) for k in (
                    "displacement", "reaction", "stress_level", "principal", "stress_gauss")}
                stage.update({"c_" + k: g["contact"][k][...] for k in g.get("contact", {})})
                stage.update(cutbacks=int(g.attrs["cutbacks"]), applied=g.attrs["applied_load"],
                             water_level=float(g.attrs.get("water_level", -np.inf)),
                             reservoir_empty=bool(g.attrs.get("reservoir_empty", 1)),
                             reaction_sum=g.attrs["reaction_sum"],
                             contact_iterations=int(g["solver"].attrs["contact_iterations"]))
                self.stages.append(stage)

    def _finite(self, name, obj):
        if isinstance(obj, h5py.Dataset) and obj.dtype.kind == "f" and \
                not np.all(np.isfinite(obj[...])):
            self.nonfinite.append(name)
        self.nonfinite += [f"{name}@{key}" for key, value in obj.attrs.items()
                           if np.asarray(value).dtype.kind == "f" and
                           not np.all(np.isfinite(value))]


def rel(a, b):
    """|a - b| / |b| (largest entries)."""
    a, b = np.asarray(a, float), np.asarray(b, float)
    return float(np.max(np.abs(a - b)) / max(np.max(np.abs(b)), 1e-300))


check = Checks("hard-case")


def common(name, run, expect_status):
    check(name + "/exit", run.status == expect_status, f"exit status {run.status}, expected "
          f"{expect_status}" + (f" ({run.stderr[:300]})" if run.status != expect_status else ""))
    check(name + "/finite", not run.nonfinite, "no NaN or Inf in the results" if not
          run.nonfinite else "not finite: " + ", ".join(run.nonfinite[:5]))
    return run.status == 0


def diagnostic(name, run, words):
    missing = [w for w in words if w not in run.stderr]
    check(name + "/diagnostic", not missing, f"the message names {', '.join(words)}" if not
          missing else f"the message lacks {missing}: {run.stderr[:400]}")


def balance_check(name, run):
    """Newton's balance: reactions against the applied loads at every stage, to 1e-8."""
    e = max(float(np.max(np.abs(t["reaction_sum"] + t["applied"])) /
                  np.max(np.abs(t["applied"]))) for t in run.stages)
    check(name + "/balance", e <= 1e-8, f"reactions against the applied loads "
          f"(statics), the largest over the stages: {e:.1e} (1e-8)")
    return f"; balance {e:.0e}"


def finished(cfrd, work, name, deck):
    """The run of a deck expected to converge, and its last stage (None if it did not)."""
    r = Run(cfrd, work, deck)
    return r, r.stages[-1] if common(name, r, 0) else None
