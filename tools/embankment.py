#!/usr/bin/env python3
"""Mapped quad mesher for the trapezoidal embankment of issue 3, and its deck writers.

The embankment: height 178 m, crest 12 m wide, both slopes 1V:1.4H, base on y = 0, symmetric
about x = 0; nrow rows of equal height, ncol (even) elements spread evenly between the
slopes, material 1 left of x = 0 (upstream zone), 2 right. One mesh (RowMesh) goes to a cfrd
deck (one NODES generation card per row, one ELEMENTS card per row and zone; fixed columns or
the '&' free format) and to a CalculiX .inp (CPE4, plane strain). In fixed format the row
ends are rounded to what F10 holds; RowMesh.coords are the coordinates cfrd computes from the
cards written, so the .inp describes the mesh cfrd reads.

    python3 tools/embankment.py --elements N --deck out.dat [--ccx out.inp] [--free]
                                [--layers L --increments I] [--eb]
    python3 tools/embankment.py --selftest
"""

import argparse
import math
import os
import sys
import tempfile
from dataclasses import dataclass, field

import numpy as np

from cfrdtools import ccx
from cfrdtools.decks import REAL_RTOL, FieldOverflow, card, fmt_alpha, fmt_int, fmt_real, \
    free_real, groups

HEIGHT, CREST, SLOPE = 178.0, 12.0, 1.4     # m, m, horizontal per vertical (both faces)
GRAVITY_G = ccx.GRAVITY_G
EMBANKMENT_MATERIALS = {1: (60.0e3, 0.25, 21.0, "upstream zone"),     # (E kPa, nu,
                        2: (40.0e3, 0.30, 20.5, "downstream zone")}   # gamma kN/m3, label)


@dataclass
class RowMesh:
    """nrow+1 rows of ncol+1 nodes, row j from (xl[j], y[j]) to (xr[j], y[j]), numbered row
    by row from the bottom; element (j, i) is j*ncol + i + 1 with nodes (j,i), (j,i+1),
    (j+1,i+1), (j+1,i); col_mat[i] is the material of column i."""
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
    end_text: list = field(default_factory=list)  # by finalise(): per row (X1, Y1, X2, Y2)
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
        """Spell the row ends for the deck, then the mesh as the reader will rebuild it:
        node N1 + k*INC at X1 + (X2 - X1)*k/n, the end node as given."""
        spell = free_real if self.free else fmt_real
        self.end_text, n = [], self.ncol
        self.coords = np.empty((self.nnode, 2))
        for j in range(self.nrow + 1):
            texts = tuple(spell(v) for v in (self.xl[j], self.y[j], self.xr[j], self.y[j]))
            self.end_text.append(texts)
            x1, y1, x2, y2 = (float(t) for t in texts)
            k, row = np.arange(n + 1), slice(self.node(j, 0) - 1, self.node(j, n))
            self.coords[row] = np.column_stack([x1 + (x2 - x1) * k / n, y1 + (y2 - y1) * k / n])
            self.coords[row.stop - 1] = (x2, y2)
        jj, ii = (a.ravel() for a in np.meshgrid(np.arange(self.nrow), np.arange(self.ncol),
                                                 indexing="ij"))
        base = jj * (self.ncol + 1) + ii + 1
        self.conn = np.stack([base, base + 1, base + n + 2, base + n + 1], axis=1)
        self.mat = np.asarray(self.col_mat)[ii]
        return self

    def element_areas(self):
        """Exact areas of the bilinear quads (shoelace over the four corners)."""
        xy = self.coords[self.conn - 1]
        x, y = xy[..., 0], xy[..., 1]
        return 0.5 * np.sum(x * np.roll(y, -1, axis=1) - np.roll(x, -1, axis=1) * y, axis=1)

    def min_corner_cross(self):
        """Smallest cross product of the two edges at any corner (> 0: valid, CCW)."""
        xy = self.coords[self.conn - 1]
        a, b = np.roll(xy, -1, axis=1) - xy, np.roll(xy, 1, axis=1) - xy
        return (a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]).min()

    def total_weight(self):
        """Sum of gamma * area over elements, kN per m: what gravity applies."""
        gam = np.array([self.materials[m][2] for m in self.mat])
        return float(np.sum(gam * self.element_areas()))


def choose_rows_cols(elements, ratio=2.5):
    """nrow, ncol with ncol even, ncol ~ ratio*nrow and nrow*ncol ~ elements."""
    nrow = max(1, round(math.sqrt(elements / ratio)))
    return nrow, max(2, 2 * round(elements / nrow / 2))


def embankment_mesh(elements=1000, free=False, ratio=2.5, nrow=None, ncol=None):
    """The issue's embankment, two zones split at x = 0."""
    if nrow is None or ncol is None:
        nrow, ncol = choose_rows_cols(elements, ratio)
    if ncol % 2:
        raise ValueError("ncol must be even so that x = 0 is a mesh line")
    y = np.arange(nrow + 1) * HEIGHT / nrow
    half = 0.5 * CREST + SLOPE * (HEIGHT - y)
    return RowMesh(nrow, ncol, -half, half, y, np.where(np.arange(ncol) < ncol // 2, 1, 2),
                   dict(EMBANKMENT_MATERIALS),
                   title=f"Embankment H=178 m, crest 12 m, slopes 1:1.4, {nrow}x{ncol} quads",
                   groups={1: "UPSTREAM", 2: "DOWNSTREAM"}, free=free).finalise()


def block_mesh(nx, ny, dx=1.0, dy=1.0, material=(40.0e3, 0.30, 20.0, "fill"), free=False):
    """Rectangle nx*dx wide, ny*dy high, one material, base fixed (for the benchmark)."""
    return RowMesh(ny, nx, np.zeros(ny + 1), np.full(ny + 1, nx * dx), np.arange(ny + 1) * dy,
                   np.ones(nx, dtype=int), {1: material},
                   title=f"Rectangular block {nx}x{ny} quads", free=free).finalise()


def column_mesh(n, width=1.0, height=10.0, material=(60.0e3, 0.25, 21.0, "column"),
                free=False):
    """Confined column: one element wide, every node fixed in x, base fixed."""
    return RowMesh(n, 1, np.zeros(n + 1), np.full(n + 1, width), np.arange(n + 1) * height / n,
                   np.ones(1, dtype=int), {1: material}, title=f"Confined column, {n} elements",
                   free=free, lateral_fixed_x=True).finalise()


def deck_lines(mesh):
    """The cfrd deck of mesh as a list of lines (no newlines)."""
    free, ccol = mesh.free, mesh.ncol
    lines = ["* cfrd deck written by tools/embankment.py", fmt_alpha("TITLE") + mesh.title[:70],
             "CONTROL", card([("i", mesh.nnode), ("i", mesh.nelem), ("i", len(mesh.materials)),
                              ("i", 1), ("r", None), ("r", None), ("a", "KN-M")], free), "NODES"]
    lines += [card([("i", mesh.node(j, 0)), ("i", mesh.node(j, ccol)), ("i", 1), ("r", x1),
                    ("r", y1), ("r", x2), ("r", y2)], free)
              for j, (x1, y1, x2, y2) in enumerate(mesh.end_text)]
    lines.append("ELEMENTS")
    for j in range(mesh.nrow):
        i = 0
        while i < ccol:                       # one generation card per run of one material
            m, end = mesh.col_mat[i], i
            while end + 1 < ccol and mesh.col_mat[end + 1] == m:
                end += 1
            a = mesh.node(j, i)
            group = f"L{mesh.layer_of_row(j):03d}" if mesh.layers else mesh.groups.get(int(m))
            lines.append(card([("i", j * ccol + i + 1), ("i", a), ("i", a + 1),
                               ("i", a + ccol + 2), ("i", a + ccol + 1), ("i", int(m)),
                               ("i", end - i), ("i", 1), ("a", group)], free))
            i = end + 1
    lines.append("MATERIALS")
    law = "EB" if mesh.eb else "ELASTIC"
    for m in sorted(mesh.materials):
        e, nu, gam, label = mesh.materials[m]
        lines.append(f"&{m}, {law}, {label}" if free else
                     (fmt_int(m) + fmt_alpha(law) + label[:65]).rstrip())
        if mesh.eb:
            g, k, n, rf, kb, mm, kur, phi0, dphi = mesh.eb[m]
            lines += [card([("r", v) for v in (g, k, n, rf, kb, mm, kur)], free),
                      card([("r", phi0), ("r", dphi)], free)]
        else:
            lines.append(card([("r", e), ("r", nu), ("r", gam)], free))
    lines += ["BOUNDARY", card([("i", 1), ("i", ccol + 1), ("i", 1), ("i", 1), ("i", 1)], free)]
    if mesh.lateral_fixed_x:
        lines.append(card([("i", ccol + 2), ("i", mesh.nnode), ("i", 1), ("i", 1), ("i", 0)],
                          free))
    if mesh.layers:                 # layer by layer: each FILL stage places one layer
        lines.append("STAGES")
        lines += [card([("a", "FILL"), ("a", f"L{k:03d}"), ("i", mesh.layer_increments)], free)
                  for k in range(1, mesh.layers + 1)]
    else:
        lines += ["LOADS", "&GRAVITY, , 0.0, -1.0" if free else
                  (fmt_alpha("GRAVITY") + fmt_alpha("") + fmt_real(0.0) + fmt_real(-1.0)).rstrip()]
    return [ln.rstrip() for ln in lines + ["END"]]


def write_cfrd_deck(mesh, path):
    with open(path, "w") as f:
        f.write("\n".join(deck_lines(mesh)) + "\n")


def write_ccx_deck(mesh, path, print_set="NALL"):
    """CalculiX input of the same mesh: CPE4 (expanded to C3D8 by ccx), thickness 1 m; unit
    weight gamma as density gamma/9.81 under a 9.81 gravity (displacements in m)."""
    out = ["** CalculiX deck written by tools/embankment.py: " + mesh.title]
    out += ccx.node_cards(mesh.coords)
    for m in sorted(mesh.materials):
        idx = np.nonzero(mesh.mat == m)[0]
        out += ccx.element_cards(f"EMAT{m}", mesh.conn[idx], idx + 1)
    out += ["*ELSET, ELSET=EALL"] + [f"EMAT{m}" for m in sorted(mesh.materials)]
    out += ["*NSET, NSET=NALL, GENERATE", f"1, {mesh.nnode}, 1",
            "*NSET, NSET=NBASE, GENERATE", f"1, {mesh.ncol + 1}, 1"]
    for m in sorted(mesh.materials):
        out += ccx.material_cards(f"MAT{m}", *mesh.materials[m][:3], elset=f"EMAT{m}")
    out += ["*BOUNDARY", "NBASE, 1, 2"] + (["NALL, 1, 1"] if mesh.lateral_fixed_x else [])
    out += ["*STEP", "*STATIC", "*DLOAD", f"EALL, GRAV, {GRAVITY_G!r}, 0., -1., 0.",
            f"*NODE PRINT, NSET={print_set}", "U", "*END STEP"]
    with open(path, "w") as f:
        f.write("\n".join(out) + "\n")


def read_deck(path):
    """A small reader of the fixed and free cards the writer uses, by the spec's columns
    (the self-test's check of the writer): coordinates, elements, materials, fixities, loads."""
    cards = dict(groups(open(path).read()))

    def fields(line, spec):                 # spec: (first, last) columns, 1-based
        if line.startswith("&"):
            toks = [t.strip() for t in line[1:].split(",")] + [""] * len(spec)
            return toks[:len(spec)]
        assert "\t" not in line and len(line) <= 80, line
        return [line[a - 1:b].strip() for a, b in spec]
    i5 = [(5 * k + 1, 5 * k + 5) for k in range(8)]
    nnode, nelem, nmat = (int(v) for v in fields(cards["CONTROL"][0], i5[:3]))
    coords = np.full((nnode, 2), np.nan)
    for line in cards["NODES"]:
        f = fields(line, i5[:3] + [(16, 25), (26, 35), (36, 45), (46, 55)])
        n1, n2, inc = int(f[0]), int(f[1] or f[0]), int(f[2] or 1)
        (x1, y1), (x2, y2), nseg = (float(f[3] or 0), float(f[4] or 0)), \
            (float(f[5] or 0), float(f[6] or 0)), (n2 - n1) // inc
        for k in range(nseg + 1):
            assert np.isnan(coords[n1 + k * inc - 1, 0]), "node defined twice"
            coords[n1 + k * inc - 1] = (x2, y2) if k == nseg and nseg else \
                (x1 + (x2 - x1) * k / max(nseg, 1), y1 + (y2 - y1) * k / max(nseg, 1))
    conn, mat = np.zeros((nelem, 4), dtype=int), np.zeros(nelem, dtype=int)
    for line in cards["ELEMENTS"]:
        f = fields(line, i5 + [(41, 50)])
        for g in range(int(f[6] or 0) + 1):
            e = int(f[0]) + g - 1
            assert conn[e, 0] == 0, "element defined twice"
            conn[e] = np.array([int(t) for t in f[1:5]]) + g * int(f[7] or 1)
            mat[e] = int(f[5])
    m = cards["MATERIALS"]
    mats = {int(a[0]): (float(b[0]), float(b[1]), float(b[2] or 0), a[2])
            for a, b in ((fields(h, [(1, 5), (6, 15), (16, 80)]), fields(
                c, [(1, 10), (11, 20), (21, 30)])) for h, c in zip(m[::2], m[1::2]))
            if a[1].upper() == "ELASTIC"}
    fixed = np.zeros((nnode, 2), dtype=bool)
    for line in cards["BOUNDARY"]:
        f = fields(line, i5[:5])
        for n in range(int(f[0]), int(f[1] or f[0]) + 1, int(f[2] or 1)):
            fixed[n - 1] |= ((f[3] or "0") == "1", (f[4] or "0") == "1")
    loads = [(f[0].upper(), f[1], float(f[2] or 0), float(f[3] or -1))
             for f in (fields(line, [(1, 10), (11, 20), (21, 30), (31, 40)])
                       for line in cards["LOADS"])]
    assert len(mats) == nmat
    return dict(coords=coords, conn=conn, mat=mat, mats=mats, fixed=fixed, loads=loads)


def selftest():
    """The writer against the spec's columns, the closed-form trapezoid and the rounding."""
    from cfrdtools.checks import Checks
    check = Checks()
    # fmt_real: every value must come back within 1e-7 relative (the requirement itself).
    rng = np.random.default_rng(3)
    mags = 10.0 ** rng.uniform(-1, 7, 3000)
    vals = np.concatenate([rng.uniform(-300, 300, 2000), mags, -mags,
                           [255.2, -255.2, 178.0, 6.0, 0.1, -0.1, 9999999.0]])
    worst = max(abs(float(fmt_real(v)) - v) / abs(v) for v in vals)
    check(f"fmt_real round trip: worst relative error {worst:.2e} <= 1e-7 ({len(vals)} values,"
          " 0.1 <= |v| <= 1e7)", worst <= REAL_RTOL and all(len(fmt_real(v)) == 10 for v in vals))

    def raises(fn, *args):
        try:
            fn(*args)
        except FieldOverflow:
            return True
        return False
    # Ten columns keep 8 digits only for 0.1 <= |v| <= 1e7: elsewhere exact enough or raise.
    silent = sum(not raises(fmt_real, v) and abs(float(fmt_real(v)) - v) > REAL_RTOL * abs(v)
                 for v in 10.0 ** rng.uniform(-12, 12, 3000) * rng.choice([-1, 1], 3000))
    check("fmt_real over 1e-12..1e12: never a silently inaccurate field", silent == 0)
    for bad in (1.23456789e-300, 1.2345678e123, float("nan")):
        check(f"fmt_real({bad!r}) raises FieldOverflow", raises(fmt_real, bad))
    check("fmt_int(100000) raises FieldOverflow (I5 holds at most 99999)",
          raises(fmt_int, 100000))
    tmp = tempfile.mkdtemp()
    area_exact = 0.5 * (CREST + CREST + 2 * SLOPE * HEIGHT) * HEIGHT    # trapezoid
    for n, free in ((1000, False), (1000, True), (10000, False), (100000, True)):
        mesh = embankment_mesh(n, free=free)
        path = os.path.join(tmp, f"e{n}{'f' if free else ''}.dat")
        write_cfrd_deck(mesh, path)
        d = read_deck(path)
        tag = f"embankment {n} ({'free' if free else 'fixed'}, {mesh.nrow}x{mesh.ncol})"
        # An independent interpolation: equal to rounding, 1e-12 of the size of the dam.
        check(f"{tag}: deck read back by column gives the mesh coordinates",
              np.max(np.abs(d["coords"] - mesh.coords)) <= 1e-12 * HEIGHT)
        check(f"{tag}: connectivity and materials read back",
              np.array_equal(d["conn"], mesh.conn) and np.array_equal(d["mat"], mesh.mat))
        rel_area = abs(mesh.element_areas().sum() - area_exact) / area_exact
        check(f"{tag}: total area vs closed form {area_exact:.4f} m2, rel err {rel_area:.1e}",
              rel_area <= (1e-12 if free else 1e-6))
        check(f"{tag}: every corner cross product > 0 (CCW)", mesh.min_corner_cross() > 0)
        cx = mesh.coords[mesh.conn - 1, 0].mean(axis=1)
        check(f"{tag}: material 1 iff centroid x < 0", np.array_equal(mesh.mat == 1, cx < 0))
        base = np.abs(mesh.coords[:, 1]) == 0.0
        check(f"{tag}: exactly the y = 0 nodes are fixed in x and y",
              np.array_equal(d["fixed"][:, 0], base) and np.array_equal(d["fixed"][:, 1], base))
        ideal = np.abs(mesh.coords[:, 0]) - (0.5 * CREST + SLOPE * (HEIGHT - mesh.coords[:, 1]))
        ends = np.concatenate([[mesh.node(j, 0) - 1, mesh.node(j, mesh.ncol) - 1]
                               for j in range(mesh.nrow + 1)])
        check(f"{tag}: row ends on the slopes",
              np.max(np.abs(ideal[ends])) <= (1e-12 if free else 1e-7) * 300)
        check(f"{tag}: materials and gravity card read back",
              all(d["mats"][m][:3] == EMBANKMENT_MATERIALS[m][:3] for m in (1, 2))
              and d["loads"] == [("GRAVITY", "", 0.0, -1.0)])
    check("fixed-format deck of 1e5 elements raises FieldOverflow (I5 limit)",
          raises(write_cfrd_deck, embankment_mesh(100000), os.path.join(tmp, "big.dat")))
    sample = os.path.join(tmp, "s.dat")        # a hand-written ccx 2.20 excerpt
    with open(sample, "w") as f:
        f.write("\n displacements (vx,vy,vz) for set NALL and time  0.1000000E+01\n\n"
                "         1  0.000000E+00  0.000000E+00  0.000000E+00\n"
                "         2  1.500000E-02 -4.375000E-04  0.000000E+00\n"
                "         3 -1.000000-100  2.000000E+00  0.000000E+00\n"
                "\n total force (fx,fy,fz) for set NBASE and time  0.1000000E+01\n\n"
                "        0.000000E+00  3.150000E+01  0.000000E+00\n")
    check("ccx .dat parser reads the block, a 3-digit exponent, and stops at the next block",
          np.array_equal(ccx.displacement_array(sample, 3), [[0, 0], [1.5e-2, -4.375e-4],
                                                                [-1e-100, 2.0]]))
    return 0 if Checks()("embankment selftest", not check.failed, f"{check.failed} failed") \
        else 1


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
            mesh.layers, mesh.layer_increments = args.layers, args.increments
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
