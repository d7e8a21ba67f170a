#!/usr/bin/env python3
"""Mapped quad mesher for the trapezoidal embankment of issue 3, and deck writers.

The embankment: height 178 m, crest 12 m wide, both slopes 1V:1.4H, base on y = 0,
symmetric about x = 0. The mesh is structured: nrow rows of equal height, each row has
ncol elements spread evenly between the two slopes. ncol is even, so x = 0 is a mesh line:
elements left of it are material 1 (upstream zone), the others material 2.

Two writers share one mesh (RowMesh):
  * write_cfrd_deck: the card deck of /work/spec/cards-spec.md, one NODES generation card
    per mesh row, two ELEMENTS generation cards per row (one per material zone), fixed
    columns or the '&' free format;
  * write_ccx_deck: a CalculiX .inp of the same mesh (CPE4, plane strain).
In fixed format the row end coordinates are rounded to what fits in F10 columns. The mesh
coordinates kept in RowMesh.coords are the ones cfrd will compute from the written cards
(rounded ends, interior nodes interpolated as X1 + (X2-X1)*k/n), so the .inp describes the
same mesh cfrd reads.

CLI: python3 tools/embankment.py --elements N --deck out.dat [--ccx out.inp] [--free]
     python3 tools/embankment.py --selftest
"""

import argparse
import math
import re
import sys
from dataclasses import dataclass, field

import numpy as np

from cfrdtools.decks import (REAL_RTOL, FieldOverflow, fmt_int, fmt_real,  # noqa: F401
                             fmt_alpha, free_real, real_candidates)

HEIGHT = 178.0          # m
CREST = 12.0            # m
SLOPE = 1.4             # horizontal per vertical, both faces
GRAVITY_G = 9.81        # m/s2, only to turn unit weights into CalculiX densities

# (E kPa, nu, gamma kN/m3, label)
EMBANKMENT_MATERIALS = {
    1: (60.0e3, 0.25, 21.0, "upstream zone"),
    2: (40.0e3, 0.30, 20.5, "downstream zone"),
}


# --------------------------------------------------------------------------------------
# The structured "row" mesh (embankment, rectangular block, column all fit it)
# --------------------------------------------------------------------------------------

@dataclass
class RowMesh:
    """nrow+1 rows of ncol+1 nodes; row j runs from (xl[j], y[j]) to (xr[j], y[j]).

    Nodes are numbered row by row from the bottom, left to right, from 1. Element (j, i)
    (row j, column i, both from 0) is number j*ncol + i + 1 with nodes counter-clockwise:
    (j,i), (j,i+1), (j+1,i+1), (j+1,i). col_mat[i] is the material of column i.
    """
    nrow: int
    ncol: int
    xl: np.ndarray
    xr: np.ndarray
    y: np.ndarray
    col_mat: np.ndarray
    materials: dict                      # number -> (E, nu, gamma, label)
    title: str = "structured mesh"
    groups: dict = field(default_factory=dict)   # material -> element group name
    free: bool = False                   # '&' free format (full precision ends)
    lateral_fixed_x: bool = False        # every node fixed in x (the confined column)
    layers: int = 0                      # > 0: rows grouped into this many FILL layers
    layer_increments: int = 1            # increments per FILL stage
    eb: dict = None                      # material -> E-B (gamma, K, n, Rf, Kb, m, Kur, phi0, dphi)
    # Filled by finalise():
    end_text: list = field(default_factory=list)  # per row: (X1, Y1, X2, Y2) strings
    coords: np.ndarray = None            # (nnode, 2) as cfrd computes them from the cards
    conn: np.ndarray = None              # (nelem, 4) 1-based
    mat: np.ndarray = None               # (nelem,)

    @property
    def nnode(self):
        return (self.nrow + 1) * (self.ncol + 1)

    @property
    def nelem(self):
        return self.nrow * self.ncol

    def node(self, j, i):
        return j * (self.ncol + 1) + i + 1

    def layer_of_row(self, j):
        """1-based fill layer of mesh row j (rows split as evenly as possible)."""
        return j * self.layers // self.nrow + 1

    def base_nodes(self):
        return np.arange(1, self.ncol + 2)

    def finalise(self):
        """Spell the row ends for the deck, then the mesh as the reader will rebuild it."""
        spell = free_real if self.free else fmt_real
        self.end_text = []
        coords = np.empty((self.nnode, 2))
        n = self.ncol
        for j in range(self.nrow + 1):
            texts = tuple(spell(v) for v in (self.xl[j], self.y[j], self.xr[j], self.y[j]))
            self.end_text.append(texts)
            x1, y1, x2, y2 = (float(t) for t in texts)
            k = np.arange(n + 1)
            row = slice(self.node(j, 0) - 1, self.node(j, n))
            # cfrd's generation rule: N1 + k*INC sits at X1 + (X2 - X1)*k/n.
            coords[row, 0] = x1 + (x2 - x1) * k / n
            coords[row, 1] = y1 + (y2 - y1) * k / n
            coords[row.stop - 1] = (x2, y2)      # the end node is given, not interpolated
        self.coords = coords
        jj, ii = np.meshgrid(np.arange(self.nrow), np.arange(self.ncol), indexing="ij")
        jj, ii = jj.ravel(), ii.ravel()
        base = jj * (self.ncol + 1) + ii + 1
        self.conn = np.stack([base, base + 1, base + self.ncol + 2, base + self.ncol + 1],
                             axis=1)
        self.mat = np.asarray(self.col_mat)[ii]
        return self

    # ---- quantities for checks -------------------------------------------------------
    def element_areas(self):
        """Exact areas of the bilinear quads (shoelace over the four corners)."""
        xy = self.coords[self.conn - 1]                      # (nelem, 4, 2)
        x, y = xy[..., 0], xy[..., 1]
        return 0.5 * np.sum(x * np.roll(y, -1, axis=1) - np.roll(x, -1, axis=1) * y, axis=1)

    def min_corner_cross(self):
        """Smallest cross product of the two edges at any corner (> 0: valid, CCW)."""
        xy = self.coords[self.conn - 1]
        e_next = np.roll(xy, -1, axis=1) - xy
        e_prev = np.roll(xy, 1, axis=1) - xy
        cross = e_next[..., 0] * e_prev[..., 1] - e_next[..., 1] * e_prev[..., 0]
        return cross.min()

    def total_weight(self):
        """Sum of gamma * area over elements, kN per m: what gravity applies."""
        gam = np.array([self.materials[m][2] for m in self.mat])
        return float(np.sum(gam * self.element_areas()))


def choose_rows_cols(elements, ratio=2.5):
    """nrow, ncol with ncol even, ncol ~ ratio*nrow and nrow*ncol ~ elements."""
    nrow = max(1, round(math.sqrt(elements / ratio)))
    ncol = max(2, 2 * round(elements / nrow / 2))
    return nrow, ncol


def embankment_mesh(elements=1000, free=False, ratio=2.5, nrow=None, ncol=None):
    """The issue's embankment, two zones split at x = 0."""
    if nrow is None or ncol is None:
        nrow, ncol = choose_rows_cols(elements, ratio)
    if ncol % 2:
        raise ValueError("ncol must be even so that x = 0 is a mesh line")
    y = np.arange(nrow + 1) * HEIGHT / nrow
    half = 0.5 * CREST + SLOPE * (HEIGHT - y)
    col_mat = np.where(np.arange(ncol) < ncol // 2, 1, 2)
    return RowMesh(nrow, ncol, -half, half, y, col_mat, dict(EMBANKMENT_MATERIALS),
                   title=f"Embankment H=178 m, crest 12 m, slopes 1:1.4, {nrow}x{ncol} quads",
                   groups={1: "UPSTREAM", 2: "DOWNSTREAM"}, free=free).finalise()


def block_mesh(nx, ny, dx=1.0, dy=1.0, material=(40.0e3, 0.30, 20.0, "fill"), free=False):
    """Rectangle nx*dx wide, ny*dy high, one material, base fixed (for the benchmark)."""
    y = np.arange(ny + 1) * dy
    return RowMesh(ny, nx, np.zeros(ny + 1), np.full(ny + 1, nx * dx), y,
                   np.ones(nx, dtype=int), {1: material},
                   title=f"Rectangular block {nx}x{ny} quads", free=free).finalise()


def column_mesh(n, width=1.0, height=10.0, material=(60.0e3, 0.25, 21.0, "column"),
                free=False):
    """Confined column: one element wide, every node fixed in x, base fixed."""
    y = np.arange(n + 1) * height / n
    return RowMesh(n, 1, np.zeros(n + 1), np.full(n + 1, width), y, np.ones(1, dtype=int),
                   {1: material}, title=f"Confined column, {n} elements",
                   free=free, lateral_fixed_x=True).finalise()


# --------------------------------------------------------------------------------------
# cfrd deck
# --------------------------------------------------------------------------------------

def _header(word, rest=""):
    return fmt_alpha(word) + rest


def _card(fields, free):
    """fields: list of (kind, value) with kind in 'i', 'r', 'a'; None = blank.

    Fixed: I5 / F10 / A10 in order. Free: '&' then the same fields comma-separated.
    Trailing blank fields are dropped (missing trailing fields = blank).
    """
    while fields and fields[-1][1] is None:
        fields = fields[:-1]
    if free:
        parts = []
        for kind, val in fields:
            if val is None:
                parts.append("")
            elif kind == "i":
                parts.append(str(int(val)))
            elif kind == "r":
                parts.append(val if isinstance(val, str) else free_real(val))
            else:
                if "," in str(val):
                    raise FieldOverflow(f"text '{val}' has a comma: not allowed in free format")
                parts.append(str(val))
        return "&" + ", ".join(parts)
    out = []
    for kind, val in fields:
        width = 5 if kind == "i" else 10
        if val is None:
            out.append(" " * width)
        elif kind == "i":
            out.append(fmt_int(val))
        elif kind == "r":
            text = val if isinstance(val, str) else fmt_real(val)
            if len(text) > 10:
                raise FieldOverflow(f"'{text}' longer than 10 columns")
            out.append(text.rjust(10))
        else:
            out.append(fmt_alpha(val))
    line = "".join(out).rstrip()
    if len(line) > 80:
        raise FieldOverflow(f"card longer than 80 columns: {line!r}")
    return line


def deck_lines(mesh):
    """The cfrd deck of mesh as a list of lines (no newlines)."""
    free = mesh.free
    ccol = mesh.ncol
    lines = ["* cfrd deck written by tools/embankment.py",
             _header("TITLE", mesh.title[:70]),
             _header("CONTROL"),
             _card([("i", mesh.nnode), ("i", mesh.nelem), ("i", len(mesh.materials)),
                    ("i", 1), ("r", None), ("r", None), ("a", "KN-M")], free),
             _header("NODES")]
    for j, (x1, y1, x2, y2) in enumerate(mesh.end_text):
        lines.append(_card([("i", mesh.node(j, 0)), ("i", mesh.node(j, ccol)), ("i", 1),
                            ("r", x1), ("r", y1), ("r", x2), ("r", y2)], free))
    lines.append(_header("ELEMENTS"))
    for j in range(mesh.nrow):
        i = 0
        while i < ccol:                       # one generation card per run of one material
            m = mesh.col_mat[i]
            i_end = i
            while i_end + 1 < ccol and mesh.col_mat[i_end + 1] == m:
                i_end += 1
            ne = j * ccol + i + 1
            a = mesh.node(j, i)
            group = mesh.groups.get(int(m))
            if mesh.layers:
                group = f"L{mesh.layer_of_row(j):03d}"
            lines.append(_card([("i", ne), ("i", a), ("i", a + 1), ("i", a + ccol + 2),
                                ("i", a + ccol + 1), ("i", int(m)), ("i", i_end - i),
                                ("i", 1), ("a", group)], free))
            i = i_end + 1
    lines.append(_header("MATERIALS"))
    for m in sorted(mesh.materials):
        e, nu, gam, label = mesh.materials[m]
        law = "EB" if mesh.eb else "ELASTIC"
        if free:
            lines.append(f"&{m}, {law}, {label}")
        else:
            lines.append((fmt_int(m) + fmt_alpha(law) + label[:65]).rstrip())
        if mesh.eb:
            g, k, n, rf, kb, mm, kur, phi0, dphi = mesh.eb[m]
            lines.append(_card([("r", g), ("r", k), ("r", n), ("r", rf), ("r", kb), ("r", mm),
                                ("r", kur)], free))
            lines.append(_card([("r", phi0), ("r", dphi)], free))
        else:
            lines.append(_card([("r", e), ("r", nu), ("r", gam)], free))
    lines.append(_header("BOUNDARY"))
    lines.append(_card([("i", 1), ("i", ccol + 1), ("i", 1), ("i", 1), ("i", 1)], free))
    if mesh.lateral_fixed_x:
        lines.append(_card([("i", ccol + 2), ("i", mesh.nnode), ("i", 1), ("i", 1),
                            ("i", 0)], free))
    if mesh.layers:
        # Layer by layer: each FILL stage places one layer under its own weight.
        lines.append(_header("STAGES"))
        for k in range(1, mesh.layers + 1):
            lines.append(_card([("a", "FILL"), ("a", f"L{k:03d}"), ("i", mesh.layer_increments)],
                               free))
    else:
        lines.append(_header("LOADS"))
        if free:
            lines.append("&GRAVITY, , 0.0, -1.0")
        else:
            lines.append((fmt_alpha("GRAVITY") + fmt_alpha("") + fmt_real(0.0)
                          + fmt_real(-1.0)).rstrip())
    lines.append(_header("END"))
    return [ln.rstrip() for ln in lines]


def write_cfrd_deck(mesh, path):
    with open(path, "w") as f:
        f.write("\n".join(deck_lines(mesh)) + "\n")


# --------------------------------------------------------------------------------------
# CalculiX deck
# --------------------------------------------------------------------------------------

def ccx_real(value):
    """Shortest round-trip spelling if it fits CalculiX's 20-character fields, else 14
    significant digits (relative 5e-14)."""
    text = repr(float(value))
    return text if len(text) <= 20 else f"{float(value):.13e}"


def write_ccx_deck(mesh, path, print_set="NALL"):
    """CalculiX input of the same mesh: CPE4 (expanded to C3D8 by ccx), thickness 1 m.

    Unit weight gamma becomes density gamma/9.81 under a 9.81 gravity, so the body force
    per volume is gamma (kN/m3) and displacements come out in m.
    """
    out = ["** CalculiX deck written by tools/embankment.py: " + mesh.title, "*NODE"]
    for k, (x, y) in enumerate(mesh.coords, start=1):
        out.append(f"{k}, {ccx_real(x)}, {ccx_real(y)}, 0.0")
    for m in sorted(mesh.materials):
        idx = np.nonzero(mesh.mat == m)[0]
        out.append(f"*ELEMENT, TYPE=CPE4, ELSET=EMAT{m}")
        for e in idx:
            a, b, c, d = mesh.conn[e]
            out.append(f"{e + 1}, {a}, {b}, {c}, {d}")
    out.append("*ELSET, ELSET=EALL")
    out.extend(f"EMAT{m}" for m in sorted(mesh.materials))
    out += ["*NSET, NSET=NALL, GENERATE", f"1, {mesh.nnode}, 1",
            "*NSET, NSET=NBASE, GENERATE", f"1, {mesh.ncol + 1}, 1"]
    for m in sorted(mesh.materials):
        e, nu, gam, _ = mesh.materials[m]
        out += [f"*MATERIAL, NAME=MAT{m}", "*ELASTIC", f"{ccx_real(e)}, {ccx_real(nu)}",
                "*DENSITY", ccx_real(float(gam) / GRAVITY_G),
                f"*SOLID SECTION, ELSET=EMAT{m}, MATERIAL=MAT{m}", "1.0"]
    out += ["*BOUNDARY", "NBASE, 1, 2"]
    if mesh.lateral_fixed_x:
        out.append("NALL, 1, 1")
    out += ["*STEP", "*STATIC", "*DLOAD", f"EALL, GRAV, {GRAVITY_G!r}, 0., -1., 0.",
            f"*NODE PRINT, NSET={print_set}", "U", "*END STEP"]
    with open(path, "w") as f:
        f.write("\n".join(out) + "\n")


_DISP_HEAD = re.compile(r"^\s*displacements\s*\(vx,vy,vz\)\s*for set\s+(\S+)\s+and time\s+(\S+)",
                        re.IGNORECASE)


def _ffloat(text):
    """Fortran E output may drop the 'E' for 3-digit exponents: '1.234567-100'."""
    text = text.strip()
    if re.search(r"[0-9][+-][0-9]+$", text) and "E" not in text.upper():
        text = re.sub(r"([0-9])([+-][0-9]+)$", r"\1E\2", text)
    return float(text)


def read_ccx_displacements(path, nset="NALL"):
    """Displacements of the last 'displacements (vx,vy,vz) for set NSET' block: {node: (vx, vy, vz)}."""
    blocks = []
    current = None
    with open(path) as f:
        for line in f:
            head = _DISP_HEAD.match(line)
            if head:
                current = {} if head.group(1).upper() == nset.upper() else None
                if current is not None:
                    blocks.append(current)
                continue
            if current is None:
                continue
            parts = line.split()
            if not parts:
                continue
            try:
                node = int(parts[0])
                vals = tuple(_ffloat(p) for p in parts[1:4])
                if len(vals) != 3:
                    raise ValueError
            except ValueError:
                current = None          # the block ended (next heading of another kind)
                continue
            current[node] = vals
    if not blocks:
        raise ValueError(f"{path}: no 'displacements (vx,vy,vz) for set {nset}' block")
    return blocks[-1]


def ccx_displacement_array(path, nnode, nset="NALL"):
    disp = read_ccx_displacements(path, nset)
    missing = [n for n in range(1, nnode + 1) if n not in disp]
    if missing:
        raise ValueError(f"{path}: {len(missing)} nodes missing from the displacement block "
                         f"(first: {missing[:5]})")
    return np.array([disp[n][:2] for n in range(1, nnode + 1)])


# --------------------------------------------------------------------------------------
# Self-test: read the deck back by the spec's columns, independently of the writer
# --------------------------------------------------------------------------------------

_KEYWORDS = {"TITLE", "CONTROL", "NODES", "ELEMENTS", "MATERIALS", "BOUNDARY", "LOADS",
             "END", "STOP"}


def _fields(line, spec):
    """spec: list of (col1, col2) 1-based inclusive; free format splits on commas."""
    if line.startswith("&"):
        toks = [t.strip() for t in line[1:].split(",")]
        toks += [""] * (len(spec) - len(toks))
        return toks[:len(spec)]
    return [line[a - 1:b].strip() for a, b in spec]


def read_deck(path):
    """A small, separate reader of the subset of the spec that the writer uses."""
    groups = {}
    cur = None
    with open(path) as f:
        for line in f:
            line = line.rstrip("\n").rstrip("\r")
            if not line.strip() or line[0] == "*" or line == "C" or line.startswith("C "):
                continue
            if "\t" in line:
                raise AssertionError("tab in deck")
            if not line.startswith("&") and len(line) > 80:
                raise AssertionError(f"line longer than 80 columns: {line!r}")
            word = line[:10].strip().upper()
            if word in _KEYWORDS:
                cur = word
                groups[cur] = [line]
                if cur in ("END", "STOP"):
                    break
                continue
            groups[cur].append(line)
    I5 = lambda k: (5 * k + 1, 5 * k + 5)               # noqa: E731
    ctrl = _fields(groups["CONTROL"][1], [I5(0), I5(1), I5(2), I5(3), (21, 30), (31, 40),
                                          (41, 50)])
    nnode, nelem, nmat = int(ctrl[0]), int(ctrl[1]), int(ctrl[2])
    coords = np.full((nnode, 2), np.nan)
    for line in groups["NODES"][1:]:
        f_ = _fields(line, [I5(0), I5(1), I5(2), (16, 25), (26, 35), (36, 45), (46, 55)])
        n1, n2, inc = int(f_[0]), int(f_[1] or f_[0]), int(f_[2] or 1)
        x1, y1 = float(f_[3] or 0), float(f_[4] or 0)
        nseg = (n2 - n1) // inc
        for k in range(nseg + 1):
            if k == nseg:
                x, y = (float(f_[5]), float(f_[6])) if nseg else (x1, y1)
            else:
                x = x1 + (float(f_[5]) - x1) * k / nseg
                y = y1 + (float(f_[6]) - y1) * k / nseg
            assert np.isnan(coords[n1 + k * inc - 1, 0]), "node defined twice"
            coords[n1 + k * inc - 1] = (x, y)
    conn = np.zeros((nelem, 4), dtype=int)
    mat = np.zeros(nelem, dtype=int)
    for line in groups["ELEMENTS"][1:]:
        f_ = _fields(line, [I5(k) for k in range(8)] + [(41, 50)])
        ne = int(f_[0])
        nodes = np.array([int(t) for t in f_[1:5]])
        ngen, ninc = int(f_[6] or 0), int(f_[7] or 1)
        for g in range(ngen + 1):
            assert conn[ne + g - 1, 0] == 0, "element defined twice"
            conn[ne + g - 1] = nodes + g * ninc
            mat[ne + g - 1] = int(f_[5])
    mats = {}
    mlines = groups["MATERIALS"][1:]
    for c1, c2 in zip(mlines[0::2], mlines[1::2]):
        a = _fields(c1, [I5(0), (6, 15), (16, 80)])
        b = _fields(c2, [(1, 10), (11, 20), (21, 30)])
        assert a[1].upper() == "ELASTIC"
        mats[int(a[0])] = (float(b[0]), float(b[1]), float(b[2] or 0), a[2])
    fixed = np.zeros((nnode, 2), dtype=bool)
    for line in groups["BOUNDARY"][1:]:
        f_ = _fields(line, [I5(k) for k in range(5)])
        n1, n2, inc = int(f_[0]), int(f_[1] or f_[0]), int(f_[2] or 1)
        for n in range(n1, n2 + 1, inc):
            fixed[n - 1, 0] |= (f_[3] or "0") == "1"
            fixed[n - 1, 1] |= (f_[4] or "0") == "1"
    loads = []
    for line in groups["LOADS"][1:]:
        if line.startswith("&"):
            toks = [t.strip() for t in line[1:].split(",")] + ["", "", ""]
            loads.append((toks[0].upper(), toks[1], float(toks[2] or 0), float(toks[3] or -1)))
        else:
            loads.append((line[:10].strip().upper(), line[10:20].strip(),
                          float(line[20:30].strip() or 0), float(line[30:40].strip() or -1)))
    assert len(mats) == nmat
    return dict(coords=coords, conn=conn, mat=mat, mats=mats, fixed=fixed, loads=loads,
                title=groups["TITLE"][0][10:80].strip())


def selftest():
    fails = 0

    def check(cond, what):
        nonlocal fails
        print(("PASS " if cond else "FAIL ") + what)
        fails += 0 if cond else 1

    # fmt_real: every value must come back within 1e-7 relative (the requirement itself).
    rng = np.random.default_rng(3)
    mags = 10.0 ** rng.uniform(-1, 7, 3000)
    vals = np.concatenate([rng.uniform(-300, 300, 2000), mags, -mags,
                           [255.2, -255.2, 178.0, 6.0, 0.1, -0.1, 9999999.0]])
    worst = max(abs(float(fmt_real(v)) - v) / abs(v) for v in vals)
    check(worst <= REAL_RTOL and all(len(fmt_real(v)) == 10 for v in vals),
          f"fmt_real round trip: worst relative error {worst:.2e} <= 1e-7 "
          f"({len(vals)} values, 0.1 <= |v| <= 1e7)")
    # Ten columns keep 8 digits (5e-8) only for 0.1 <= |v| <= 1e7: elsewhere exact
    # enough or raise.
    silent = 0
    for v in np.concatenate([10.0 ** rng.uniform(-12, 12, 3000)]) * rng.choice([-1, 1], 3000):
        try:
            silent += abs(float(fmt_real(v)) - v) > REAL_RTOL * abs(v)
        except FieldOverflow:
            pass
    check(silent == 0, "fmt_real over 1e-12..1e12: never a silently inaccurate field")
    for bad in (1.23456789e-300, 1.2345678e123, float("nan")):
        try:
            fmt_real(bad)
            check(False, f"fmt_real({bad!r}) must raise")
        except FieldOverflow:
            check(True, f"fmt_real({bad!r}) raises FieldOverflow")
    try:
        fmt_int(100000)
        check(False, "fmt_int(100000) must raise")
    except FieldOverflow:
        check(True, "fmt_int(100000) raises FieldOverflow (I5 holds at most 99999)")

    import os
    import tempfile
    tmp = tempfile.mkdtemp()
    # Trapezoid area (closed form) = (crest + base)/2 * H.
    area_exact = 0.5 * (CREST + CREST + 2 * SLOPE * HEIGHT) * HEIGHT
    for n, free in ((1000, False), (1000, True), (10000, False), (100000, True)):
        mesh = embankment_mesh(n, free=free)
        path = os.path.join(tmp, f"e{n}{'f' if free else ''}.dat")
        write_cfrd_deck(mesh, path)
        d = read_deck(path)
        tag = f"embankment {n} ({'free' if free else 'fixed'}, {mesh.nrow}x{mesh.ncol})"
        # The reader above interpolates independently, so equality is to rounding of a
        # different but equivalent expression: allow 1e-12 of the size of the dam.
        check(np.max(np.abs(d["coords"] - mesh.coords)) <= 1e-12 * HEIGHT,
              f"{tag}: deck read back by column gives the mesh coordinates")
        check(np.array_equal(d["conn"], mesh.conn) and np.array_equal(d["mat"], mesh.mat),
              f"{tag}: connectivity and materials read back")
        rel_area = abs(mesh.element_areas().sum() - area_exact) / area_exact
        check(rel_area <= (1e-12 if free else 1e-6),
              f"{tag}: total area vs closed form {area_exact:.4f} m2, rel err {rel_area:.1e}")
        check(mesh.min_corner_cross() > 0, f"{tag}: every corner cross product > 0 (CCW)")
        # The zone split: material 1 exactly where the centroid is left of x = 0.
        cx = mesh.coords[mesh.conn - 1, 0].mean(axis=1)
        check(np.array_equal(mesh.mat == 1, cx < 0), f"{tag}: material 1 iff centroid x < 0")
        base = np.abs(mesh.coords[:, 1]) == 0.0
        check(np.array_equal(d["fixed"][:, 0], base) and np.array_equal(d["fixed"][:, 1], base),
              f"{tag}: exactly the y = 0 nodes are fixed in x and y")
        # The ideal geometry: end nodes on the slopes within the F10 rounding.
        ideal = np.abs(mesh.coords[:, 0]) - (0.5 * CREST + SLOPE * (HEIGHT - mesh.coords[:, 1]))
        ends = np.concatenate([[mesh.node(j, 0) - 1, mesh.node(j, mesh.ncol) - 1]
                               for j in range(mesh.nrow + 1)])
        tol = (1e-12 if free else 1e-7) * 300
        check(np.max(np.abs(ideal[ends])) <= tol, f"{tag}: row ends on the slopes")
        check(d["mats"][1][:3] == EMBANKMENT_MATERIALS[1][:3]
              and d["mats"][2][:3] == EMBANKMENT_MATERIALS[2][:3]
              and d["loads"] == [("GRAVITY", "", 0.0, -1.0)],
              f"{tag}: materials and gravity card read back")
    try:
        write_cfrd_deck(embankment_mesh(100000), os.path.join(tmp, "big.dat"))
        check(False, "fixed-format deck of 1e5 elements must raise (I5 limit)")
    except FieldOverflow:
        check(True, "fixed-format deck of 1e5 elements raises FieldOverflow (I5 limit)")
    # The .dat parser on a hand-written ccx excerpt (format of ccx 2.20).
    sample = os.path.join(tmp, "s.dat")
    with open(sample, "w") as f:
        f.write("\n displacements (vx,vy,vz) for set NALL and time  0.1000000E+01\n\n"
                "         1  0.000000E+00  0.000000E+00  0.000000E+00\n"
                "         2  1.500000E-02 -4.375000E-04  0.000000E+00\n"
                "         3 -1.000000-100  2.000000E+00  0.000000E+00\n"
                "\n total force (fx,fy,fz) for set NBASE and time  0.1000000E+01\n\n"
                "        0.000000E+00  3.150000E+01  0.000000E+00\n")
    u = ccx_displacement_array(sample, 3)
    check(np.array_equal(u, [[0, 0], [1.5e-2, -4.375e-4], [-1e-100, 2.0]]),
          "ccx .dat parser reads the block, a 3-digit exponent, and stops at the next block")
    print(f"{'PASS' if not fails else 'FAIL'} embankment selftest: {fails} failed")
    return 1 if fails else 0


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--elements", type=int, default=1000, help="target element count")
    ap.add_argument("--deck", help="cfrd deck to write")
    ap.add_argument("--ccx", help="CalculiX .inp to write (same mesh)")
    ap.add_argument("--free", action="store_true", help="'&' free format, full precision")
    ap.add_argument("--ratio", type=float, default=2.5, help="ncol/nrow (default 2.5)")
    ap.add_argument("--layers", type=int, default=0,
                    help="build in this many layers (FILL stages) instead of one load step")
    ap.add_argument("--increments", type=int, default=1, help="increments per layer")
    ap.add_argument("--eb", action="store_true",
                    help="homogeneous IIIB rockfill, Duncan-Chang E-B (paper Table 3)")
    ap.add_argument("--selftest", action="store_true")
    args = ap.parse_args(argv)
    if args.selftest:
        return selftest()
    if not args.deck and not args.ccx:
        ap.error("give --deck and/or --ccx")
    try:
        mesh = embankment_mesh(args.elements, free=args.free, ratio=args.ratio)
        if args.layers:
            if args.layers > mesh.nrow:
                ap.error(f"--layers {args.layers} exceeds the {mesh.nrow} element rows")
            mesh.layers = args.layers
            mesh.layer_increments = args.increments
        if args.eb:
            # IIIB of Table 3: density 2100 kg/m3 -> 20.601 kN/m3; Kur = 2K [choice].
            iiib = (2100 * 9.81 / 1000, 564.0, 0.35, 0.85, 204.0, 0.18, 1128.0, 51.0, 13.0)
            mesh.eb = {1: iiib, 2: iiib}
            mesh.materials = {m: (0.0, 0.0, iiib[0], "IIIB rockfill (E-B, Table 3)")
                              for m in mesh.materials}
            mesh.title = f"Homogeneous IIIB E-B embankment, {mesh.nrow}x{mesh.ncol} quads"
        if args.deck:
            write_cfrd_deck(mesh, args.deck)
    except FieldOverflow as exc:
        print(f"embankment.py: {exc}; use --free for meshes this large", file=sys.stderr)
        return 2
    if args.ccx:
        write_ccx_deck(mesh, args.ccx)
    print(f"embankment: {mesh.nrow} rows x {mesh.ncol} columns = {mesh.nelem} elements, "
          f"{mesh.nnode} nodes")
    return 0


if __name__ == "__main__":
    sys.exit(main())
