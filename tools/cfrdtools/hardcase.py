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
            xy, nelem = f["mesh/coordinates"][...], f["mesh/connectivity"].shape[0]
            for g in results.stages(f):
                stage = {k: results.field(g, k) for k in (
                    "displacement", "reaction", "stress_level", "principal", "stress_gauss")}
                stage.update({"c_" + k: g["contact"][k][...] for k in g.get("contact", {})})
                stage.update(cutbacks=int(g.attrs["cutbacks"]), applied=g.attrs["applied_load"],
                             water_level=float(g.attrs.get("water_level", -np.inf)),
                             reservoir_empty=bool(g.attrs.get("reservoir_empty", 1)),
                             reaction_sum=g.attrs["reaction_sum"],
                             contact_iterations=int(g["solver"].attrs["contact_iterations"]))
                if "state" in g:
                    stage.update(state_multipliers(g["state"], xy, nelem))
                self.stages.append(stage)

    def _finite(self, name, obj):
        if isinstance(obj, h5py.Dataset) and obj.dtype.kind == "f" and \
                not np.all(np.isfinite(obj[...])):
            self.nonfinite.append(name)
        self.nonfinite += [f"{name}@{key}" for key, value in obj.attrs.items()
                           if np.asarray(value).dtype.kind == "f" and
                           not np.all(np.isfinite(value))]


def state_multipliers(state, xy, nelem):
    """The contact multipliers at their own (slave) nodes, from a stage's restart state
    (src/io/cfrd_h5_state.f90, state_reals): m_node (mesh node, the positive entry D_jj of
    its coupling row; 0 when uncoupled), m_x, m_y (as meshed), m_p, m_q (kPa), m_status,
    m_supported. Where the
    roles were swapped (docs/theory.md section 14) these are the cushion's nodes, while the
    contact datasets report the slab's."""
    ints, reals, nnode = state["ints"][...], state["reals"][...], len(xy)
    n = ints[:8]
    nc, ncpl = int(n[2]), int(n[3])
    if nc < 0:
        return {}
    i = 8 + (nelem if n[7] == 1 else 0)
    supported, status = ints[i + nc:i + 2 * nc], ints[i + 2 * nc:i + 3 * nc]
    i += 4 * nc + nnode                       # placed, supported, status, slip_sign, birth
    ptr, cnode = ints[i:i + nc + 1], ints[i + nc + 1:i + nc + 1 + ncpl]
    r = 2 * nnode * (2 if n[6] == 1 else 1)   # f_ext, u_before_reset
    p, q = reals[r:r + nc], reals[r + nc:r + 2 * nc]
    a = reals[r + 13 * nc:r + 13 * nc + ncpl]  # after p .. g_curve (9), normal, tangent (4)
    node = np.zeros(nc, int)
    for c in range(nc):
        if ptr[c + 1] > ptr[c]:
            row = slice(ptr[c] - 1, ptr[c + 1] - 1)
            node[c] = cnode[row][np.argmax(a[row])]
    return dict(m_node=node, m_x=xy[node - 1, 0], m_y=xy[node - 1, 1], m_p=p, m_q=q,
                m_status=status, m_supported=supported)


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
