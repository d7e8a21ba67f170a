#!/usr/bin/env python3
"""Mesh generator and deck writer for the Tianshengqiao-I section (issue 5).

Reads the geometry file inputs/tianshengqiao-i.toml (every number that shapes the model, with
its source) and writes a complete cfrd deck: nodes, quads with their zones and fill groups,
the E-B and slab materials, the fixed base, the wetted faces, the gauges and the history of
the paper's Table 2. The mesh (docs/tianshengqiao.md): body rows follow elevation (one per
slab element below the phase III top, one above); lines parallel to the upstream face bound
the IIA and IIIA bands; further lines parallel to the faces are born, going down from the
crest, wherever the central column grows wider than `split_width`, in a 3-to-1 quad
transition row; the slab lies on the cushion face, two layers thick, in Q4S quads whose
cross-lines are normal to the face (the geometry file's slab.element; --slab-element Q4: Q4
quads with horizontal cross-lines on the body's row lines, which lock in shear,
docs/tianshengqiao.md section 11.3). Refinement xR splits every x1 quad R x R by its
bilinear map, so each mesh holds the x1 mesh's lines, zones, groups and fill layers.
--face F: every row and the slab in F along the slope, the first --face-band columns behind
the face at xF, the rest at xR.

Interfaces (--interface): bonded (the slab shares the cushion's nodes), thin (thin-layer
quads between cushion and slab), joint (Goodman joints on matching node pairs), contact (a
slab mesh of its own, with CONTACT cards: the slab's inner faces slave, cast in place).

  python3 tools/tianshengqiao.py --all                 # every deck in inputs/ of this section
  python3 tools/tianshengqiao.py --refine 1 --deck inputs/tianshengqiao-x1.dat
  python3 tools/tianshengqiao.py --knee --interface joint --deck joint.dat  # at the knee
  python3 tools/tianshengqiao.py --refine 2 --report        # mesh quality only
"""

import argparse
import calendar
import copy
import datetime
import math
import re
import sys
import textwrap
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from cfrdtools.decks import FieldOverflow, fmt_alpha as fa, fmt_int as fi, fmt_real as fr, \
    free_real
from cfrdtools import plinth as pl

try:
    import tomllib                      # Python 3.11 and later
except ImportError:                     # pragma: no cover
    import tomli as tomllib             # the same parser from PyPI

GEOMETRY = Path(__file__).resolve().parent.parent / "inputs" / "tianshengqiao-i.toml"
GRAVITY_G = 9.81            # m/s2: density (kg/m3) * g / 1000 = unit weight (kN/m3)
GAMMA_W = 9.81              # kN/m3, unit weight of water
ZONES = ["IIA", "IIIA", "IIIB", "IIIC", "IIID"]     # material numbers 1..5; the slab is 6
SLAB_MATERIAL, THIN_MATERIAL = 6, 7
INTERFACES = ("bonded", "joint", "thin", "contact")
KNEE_DOC = "docs/accuracy-cost.md"


# Geometry-file entries the decks do not depend on (used only to choose a mesh), kept out of
# the decks' headers so that the decks in inputs/ stay what they are.
NOT_IN_HEADER = {("slab", "decay_length")}
FACES = (1, 2, 4, 8)
# The longest slab element along the slope that resolves the slab's bending, as a fraction of
# its decay length pi / lambda: a <= pi / (6 lambda) [choice, argued from the closed form:
# Q4S rectangles within about 2 % of Hetenyi's clamped beam at lambda a <= 0.52,
# analysis_slab/clamped_slab_moment; cfrd's summary checks the same, docs/theory.md s. 13].
RESOLUTION_FRACTION = 1.0 / 6.0


class Geometry:
    """Values of the geometry file; `sources` lists each with its source for the header."""
    creep = False   # --creep: CREEP cards, day dates, WAIT stages ([creep] of the file)
    # Rows of the top row of each slab phase but the last (the zone where a phase's slab top
    # separates, paper Figs. 11-12) split into this many mesh rows of equal height; the fill
    # layers, gauges and block tops stay on row_lines().
    top_rows = 1

    def __init__(self, path=GEOMETRY):
        self.path = Path(path)
        with open(self.path, "rb") as handle:
            self.raw = tomllib.load(handle)
        self.list_sources()

    def list_sources(self):
        self.sources = [(f"{g}.{k}", i["value"], i["source"], i.get("note", ""))
                        for g in ("section", "slab", "interface", "zones", "mesh", "increments")
                        for k, i in self.raw[g].items() if (g, k) not in NOT_IN_HEADER]
        self.sources += [(f"materials.{k}", i["label"], i["source"], "")
                         for k, i in self.raw["materials"].items()]

    def v(self, group, key):
        return self.raw[group][key]["value"]

    def knee(self, interface):
        """(refine, increments per fill layer and slab phase, water step in m) at the knee of
        docs/accuracy-cost.md for this interface: the geometry file's [knee] table."""
        prefix = "contact_" if interface == "contact" else ""
        return (self.v("knee", prefix + "refine"), self.v("knee", prefix + "increments"),
                float(self.v("knee", prefix + "water_rise")))

    def at_knee(self, interface):
        """A copy whose [increments] are the knee's; returns (refine, geometry)."""
        r, ninc, step = self.knee(interface)
        geo = copy.deepcopy(self)
        note = f"at the knee of {KNEE_DOC} ([knee] of the geometry file)"
        for key, value, what in (("fill_layer", ninc, "increments per FILL layer"),
                                 ("slab_phase", ninc, "increments per slab phase"),
                                 ("water_step", step, "m of reservoir rise per increment")):
            geo.raw["increments"][key] = {"value": value, "source": "choice",
                                          "note": f"{what}, {note}"}
        geo.list_sources()
        return r, geo

    crest = property(lambda self: self.v("section", "crest_elevation"))
    base = property(lambda self: self.crest - self.v("section", "height"))
    su = property(lambda self: self.v("section", "upstream_slope"))
    sd = property(lambda self: self.v("section", "downstream_slope"))

    def x_up(self, y):
        """x of the cushion face (upstream face of the body) at elevation y."""
        return self.su * (y - self.base)

    def x_down(self, y):
        """x of the downstream face at elevation y."""
        return self.x_up(self.crest) + self.v("section", "crest_width") + \
            self.sd * (self.crest - y)

    def slab_thickness(self, y):
        return self.v("slab", "t0") + self.v("slab", "rate") * (self.crest - y)

    def row_lines(self):
        """Elevations of the x1 row lines, base to crest."""
        lines, bottom = [self.base], self.base
        for top, n in zip(self.v("slab", "phase_tops"), self.v("slab", "phase_elements")):
            lines += [bottom + (top - bottom) * k / n for k in range(1, n + 1)]
            bottom = top
        return np.array(lines + ([self.crest] if self.crest > bottom + 1e-9 else []))

    def mesh_lines(self):
        """Elevations of the x1 mesh's row lines, and for each mesh band the row_lines()
        band it lies in: the top row of each phase but the last split in top_rows rows."""
        lines = self.row_lines()
        tops = self.v("slab", "phase_tops")[:-1]
        out, parent = [lines[0]], []
        for j in range(len(lines) - 1):
            split = self.top_rows if any(abs(lines[j + 1] - t) < 1e-6 for t in tops) else 1
            out += [lines[j] + (lines[j + 1] - lines[j]) * k / split for k in range(1, split + 1)]
            parent += [j] * split
        return np.array(out), parent


@dataclass
class Quad:
    nodes: tuple            # 4 node keys, counter-clockwise
    kind: str               # 'body', 'slab' or 'thin'
    band: int               # x1 row (0 = bottom row)
    material: int = 0       # 1..7
    group: str = ""         # fill group (B1R03, SLAB1, ...)
    wet_face4: bool = False  # face 4 (node 4 -> node 1) is on the reservoir side
    cover: str = ""         # group whose placement covers the wet face
    column: int = -1        # body: 0 = IIA band, 1 = IIIA band, else -1
    phase: int = 0          # slab and thin layer: slab phase 1..3
    transition: int = 0     # body: quad 1-4 of a 3-to-1 transition (4 = the top one), else 0
    ucol: int = -1          # body: column from the upstream face between two upstream lines
    dcol: int = -1          # body: column from the downstream face between two downstream lines
    born: int = -1          # body transition: the upstream column it starts (its quad 1)


@dataclass
class Mesh:
    coords: dict = field(default_factory=dict)     # node key -> (x, y)
    quads: list = field(default_factory=list)
    pairs: list = field(default_factory=list)      # joint: (cushion key, slab key) pairs

    def point(self, key, xy):
        if key not in self.coords:
            self.coords[key] = (float(xy[0]), float(xy[1]))
        return key


def build_x1(geo, interface="bonded", plinth=False, normal_rings=None):
    """The x1 mesh: body rows with 3-to-1 transitions, the slab on the cushion face; the
    slab's inner nodes are the cushion's (bonded), matching ones paired in mesh.pairs
    (joint), moved out by the thin layer's thickness (thin, with its quads), or on rows of
    the slab's own (contact: interface.contact_elements along the slope)."""
    # normal_rings: the slab's element ends normal to the face (rectangles along the slope,
    # where Q4S is exact in bending), not along the body's row lines (parallelograms skewed
    # by 54.5 deg, on which Q4S's shear stresses carry a part of the bending strain that
    # alternates from Gauss point to Gauss point, docs/theory.md section 3); default: for
    # the contact slab (its own mesh) and for a Q4S slab (the geometry file's slab.element,
    # issue 22). The toe's ring lies on the base either way.
    if normal_rings is None:
        normal_rings = interface == "contact" or geo.v("slab", "element") == "Q4S"
    mesh = Mesh()
    y, parent = geo.mesh_lines()
    nband = len(y) - 1
    unsplit = [parent.count(parent[j]) == 1 for j in range(nband)]
    split, frac = geo.v("mesh", "split_width"), geo.v("mesh", "transition_height")
    # Line families: an upstream line keeps a constant horizontal offset from the cushion
    # face, a downstream line from the downstream face; each (offset, band at whose bottom it
    # starts); the face, IIA and IIIA lines run from the base. A line is on row line j when
    # it starts at band j or above.
    wa, wb = geo.v("zones", "IIA_width"), geo.v("zones", "IIIA_width")
    a, b, births = [(0.0, nband), (wa, nband), (wa + wb, nband)], [(0.0, nband)], set()
    for j in range(nband - 1, -1, -1):
        gap = geo.x_down(y[j]) - geo.x_up(y[j]) - a[-1][0] - b[-1][0]
        # (a split row's bands are too low for a transition: it waits for the next row)
        if gap > split and unsplit[j]:
            # The new lines start one slope-run of the row from the old ones, so that each
            # ends right below the old line's top node (convex transition quads, angles no
            # smaller than the face's).
            h = y[j + 1] - y[j]
            births.add(j)
            a.append((a[-1][0] + geo.su * h, j))
            b.append((b[-1][0] + geo.sd * h, j))

    def lines_on(j):
        """Offsets (upstream, downstream) of the lines on row line j."""
        return [o for o, born in a if born >= j], [o for o, born in b if born >= j]

    def row_keys(j):
        """Node keys along row line j, upstream to downstream."""
        aa, bb = lines_on(j)
        return ([mesh.point(("u", round(o, 9), j), (geo.x_up(y[j]) + o, y[j])) for o in aa]
                + [mesh.point(("d", round(o, 9), j), (geo.x_down(y[j]) - o, y[j]))
                   for o in reversed(bb)])

    for j in range(nband):
        top, bot = row_keys(j + 1), row_keys(j)
        nu = len(lines_on(j + 1)[0]) - 1     # index of the last upstream line in both rows
        if j in births:
            # bottom: ... A_last, A_new, B_new, B_last ...; top: ... A_last, B_last ...
            assert len(bot) == len(top) + 2
            # Interior nodes at `frac` of the row height, shifted inwards from the vertical
            # through the new line's foot by `frac`/2 of its slope run.
            h = y[j + 1] - y[j]
            ym = y[j] + frac * h
            p1 = mesh.point(("p1", j), (mesh.coords[bot[nu + 1]][0] + 0.5 * frac * geo.su * h, ym))
            p2 = mesh.point(("p2", j), (mesh.coords[bot[nu + 2]][0] - 0.5 * frac * geo.sd * h, ym))
            mesh.quads += [Quad((bot[c], bot[c + 1], top[c + 1], top[c]), "body", j,
                                column=c if c < 2 else -1, ucol=c) for c in range(nu)]
            A, An, Bn, B = bot[nu:nu + 4]
            At, Bt = top[nu], top[nu + 1]
            mesh.quads += [Quad(nodes, "body", j, transition=k, born=nu) for k, nodes in
                           enumerate(((A, An, p1, At), (An, Bn, p2, p1), (Bn, B, Bt, p2),
                                      (p1, p2, Bt, At)), 1)]
            mesh.quads += [Quad((bot[c + 2], bot[c + 3], top[c + 1], top[c]), "body", j,
                                dcol=len(top) - 2 - c) for c in range(nu + 1, len(top) - 1)]
        else:
            assert len(bot) == len(top)
            mesh.quads += [Quad((bot[c], bot[c + 1], top[c + 1], top[c]), "body", j,
                                column=c if c < 2 else -1, ucol=c if c < nu else -1,
                                dcol=len(top) - 2 - c if c > nu else -1)
                           for c in range(len(top) - 1)]
    for q in mesh.quads:          # the upstream body face is wetted (cushion, or fill above)
        q.wet_face4 = q.column == 0
    # The slab: one element per body row up to the phase III top (contact: its own rows),
    # `layers` through its thickness.
    layers = geo.v("slab", "layers")
    factor = math.sqrt(1.0 + geo.su ** 2)   # horizontal width of a unit normal thickness
    tops = geo.v("slab", "phase_tops")
    thin = geo.v("interface", "thin_thickness") if interface == "thin" else 0.0
    if interface == "contact":
        rows, bottom = [geo.base], geo.base
        for phase, (top, n) in enumerate(zip(tops, geo.v("interface", "contact_elements")), 1):
            rows += [bottom + (top - bottom) * k / n for k in range(1, n)]
            # the top element split as the body's top row (mesh_lines)
            split = geo.top_rows if phase < len(tops) else 1
            rows += [rows[-1] + (top - rows[-1]) * k / split for k in range(1, split + 1)]
            bottom = top
        slab_rows = [(("c", k), rows[k]) for k in range(len(rows))]
    else:
        slab_rows = [(jj, y[jj]) for jj in range(nband + 1) if y[jj] <= tops[-1] + 1e-9]
    rings = []
    for tag, yy in slab_rows:
        xi, th, face = geo.x_up(yy), geo.slab_thickness(yy) * factor, ("u", 0.0, tag)
        if interface == "bonded":
            inner = face
        elif interface == "joint":
            inner = mesh.point(("j", tag), (xi, yy))
            mesh.pairs.append((face, inner))
        else:
            inner = mesh.point(("t" if interface == "thin" else "ci", tag),
                               (xi - thin * factor, yy))
        keys = [inner]
        for layer in range(1, layers + 1):
            if plinth and abs(yy - geo.base) < 1e-9:
                # --plinth: the slab's end cut normal to the face, on the plinth
                p = pl.toe_ring_point(geo, mesh.coords[inner], layer, layers)
            elif normal_rings and yy > geo.base + 1e-9:
                # Rings normal to the face (rectangles along the slope, no skew), but at
                # the toe, where the ring lies on the base.
                t = geo.slab_thickness(yy) * layer / layers
                p = (xi - thin * factor - t / factor, yy + t * geo.su / factor)
            else:
                p = (xi - thin * factor - th * layer / layers, yy)
            keys.append(mesh.point(("s", layer, tag), p))
        rings.append((tag, face, keys))
    for (tag0, face0, ring0), (tag1, face1, ring1), y1 in zip(rings, rings[1:],
                                                            [yy for _, yy in slab_rows[1:]]):
        band = tag0 if isinstance(tag0, int) else -1
        phase = next(k for k, top in enumerate(tops, 1) if y1 <= top + 1e-9)
        # nodes (outer bottom, inner bottom, inner top, outer top); face 4 is outside
        mesh.quads += [Quad((ring0[i + 1], ring0[i], ring1[i], ring1[i + 1]), "slab", band,
                            material=SLAB_MATERIAL, phase=phase, wet_face4=(i == layers - 1))
                       for i in range(layers)]
        if interface == "thin":
            mesh.quads.append(Quad((ring0[0], face0, face1, ring1[0]), "thin", band,
                                   material=THIN_MATERIAL, phase=phase))
    if plinth:
        pl.add_plinth(geo, mesh, rings[0][2], Quad)
    return mesh


def refine(mesh, r, split=None):
    """Split each quad into r x r by its bilinear map; shared edges share their nodes.
    split: a function of a quad giving (ns, nt), its divisions along its first edge (node 1
    -> 2) and its second (node 2 -> 3), instead of (r, r); the divisions of an edge must be
    the same from both its quads (checked: no hanging nodes)."""
    if r == 1 and split is None:
        return mesh
    out, divisions = Mesh(), {}         # x1 edge (smaller key, larger key) -> its divisions
    for qi, q in enumerate(mesh.quads):
        c = [np.array(mesh.coords[k]) for k in q.nodes]
        ns, nt = (r, r) if split is None else split(q)
        for n0, n1, nn in ((0, 1, ns), (1, 2, nt), (3, 2, ns), (0, 3, nt)):
            edge = tuple(sorted((q.nodes[n0], q.nodes[n1]), key=repr))
            if divisions.setdefault(edge, nn) != nn:
                raise SystemExit(f"refine: edge {edge} divided {divisions[edge]} and {nn}"
                                 " times by its two quads (a hanging node)")
        corners = [(0, 0), (ns, 0), (ns, nt), (0, nt)]

        def key(i, j):
            if (i, j) in corners:
                return q.nodes[corners.index((i, j))]
            # an edge point: by its end nodes and its position from the smaller key
            side = 0 if j == 0 else 1 if i == ns else 2 if j == nt else 3 if i == 0 else None
            if side is None:
                return ("i", qi, i, j)
            n0, n1, t, n = {0: (0, 1, i, ns), 1: (1, 2, j, nt), 2: (3, 2, i, ns),
                            3: (0, 3, j, nt)}[side]
            ka, kb = q.nodes[n0], q.nodes[n1]
            return ("e", ka, kb, t, n) if repr(ka) <= repr(kb) else ("e", kb, ka, n - t, n)

        for j in range(nt):
            for i in range(ns):
                ij = [(i, j), (i + 1, j), (i + 1, j + 1), (i, j + 1)]
                ks = [key(*p) for p in ij]
                for kk, (ii, jj) in zip(ks, ij):
                    if kk in out.coords:
                        continue
                    if kk[0] == "e":  # from the canonical end (the same rounding both sides)
                        pa, pb = np.array(mesh.coords[kk[1]]), np.array(mesh.coords[kk[2]])
                        out.coords[kk] = tuple(pa + (pb - pa) * (kk[3] / kk[4]))
                    elif kk[0] == "i":
                        s, t = ii / ns, jj / nt
                        out.coords[kk] = tuple((1 - s) * (1 - t) * c[0] + s * (1 - t) * c[1]
                                               + s * t * c[2] + (1 - s) * t * c[3])
                    else:
                        out.coords[kk] = mesh.coords[kk]
                out.quads.append(Quad(tuple(ks), q.kind, q.band, q.material, q.group,
                                      q.wet_face4 and i == 0, q.cover, q.column,
                                      phase=q.phase))
    return out


def face_split(r, face, band=0):
    """Divisions of the x1 quads for the face-resolved mesh (--face F): every body row and
    slab element in F along the slope, the body's columns in r, but the first `band` columns
    from the upstream face (1: IIA, 2: and IIIA, 3 and more: IIIB columns too) in F, and the
    slab in F through its thickness. A 3-to-1 transition's quads 1-3 border split rows on
    their sides: (r, F); its top quad borders row lines only: (r, r); where it starts an
    upstream column of the band, its quads 1 and 3 are (F, F), and the mirror downstream
    column is in F as well."""
    def split(q):
        if q.kind == "slab":
            return face, face           # (through the thickness, along the slope)
        if q.transition:
            if q.born < band:
                return (face, face) if q.transition in (1, 3) else (r, face)
            return (r, r) if q.transition == 4 else (r, face)
        return (face, face) if 0 <= q.ucol < band or 0 <= q.dcol < band - 2 else (r, face)
    return split


def centroid(mesh, q):
    return np.array([mesh.coords[k] for k in q.nodes]).mean(axis=0)


def assign_zones(geo, mesh):
    """Materials: IIA and IIIA by mesh column, IIIC by polygon, IIIB/IIID by the line."""
    (xa, ya), (xb, yb) = geo.v("zones", "IIIB_IIID_line")
    poly = geo.v("zones", "IIIC_polygon")
    for q in mesh.quads:
        if q.kind != "body":
            continue
        if q.column in (0, 1):
            q.material = q.column + 1
            continue
        cx, cy = centroid(mesh, q)
        inside = False                  # the centroid in the IIIC polygon (ray crossings)
        for (x1, y1), (x2, y2) in zip(poly, poly[1:] + poly[:1]):
            if (y1 > cy) != (y2 > cy) and cx < x1 + (cy - y1) * (x2 - x1) / (y2 - y1):
                inside = not inside
        q.material = 4 if inside else 3 if cx < xa + (cy - ya) * (xb - xa) / (yb - ya) else 5


def month_in(dates, k, n):
    """Date 'YYYY.MM' of the end of step k (0-based) of n spread over 'YYYY.MM-YYYY.MM'."""
    first, _, last = dates.partition("-")
    m0, m1 = (int(d[:4]) * 12 + int(d[5:7]) - 1 for d in (first, last or first))
    m = m0 + round((k + 1) * (m1 - m0) / n)
    return f"{m // 12}.{m % 12 + 1:02d}"


def creep_history(geo, stages):
    """The stages of a deck with creep (--creep): the months become days (YYYY-MM-DD), the
    k stages of one month at the ends of k equal parts of it, the last on its last day, a
    RESET on the day of the slab phase it prepares [choice]; then a WAIT stage a year to
    [creep] wait_until."""
    per_month, day_of = {}, {}
    for st in stages:
        if st[0] != "RESET":
            per_month.setdefault(st[3], []).append(st)
    for month, group in per_month.items():
        year, mon = int(month[:4]), int(month[5:7])
        days = calendar.monthrange(year, mon)[1]
        for i, st in enumerate(group):
            day_of[id(st)] = f"{year:04d}-{mon:02d}-" \
                             f"{max(1, round((i + 1) * days / len(group))):02d}"
    out = [st[:3] + (day_of[id(st if st[0] != "RESET" else
                           next(x for x in stages[k + 1:] if x[0] != "RESET"))],) + st[4:]
           for k, st in enumerate(stages)]
    last = datetime.date.fromisoformat(out[-1][3])
    until = datetime.date.fromisoformat(geo.v("creep", "wait_until"))
    year = last.year
    while True:
        end = min(datetime.date(year, 12, 31), until)
        if end > last:
            out.append(("WAIT", "", geo.v("creep", "wait_steps"), end.isoformat(),
                        f"time passes to {end.isoformat()} (creep) [choice]"))
        if end >= until:
            return out
        year += 1


def snap(y_lines, level):
    return float(y_lines[int(np.argmin(np.abs(y_lines - level)))])


def creep_notes(geo):
    """Header lines of a creep deck: each zone's creep parameters with their source."""
    return (["creep: Shen's exponential-decay law with Li's final strains (docs/theory.md"
             " section 15); time from the stage dates"]
            + [f"creep {zone}: alpha {c['alpha']:g}/day, b {c['b']:g}, mc {c['mc']:g},"
               f" d {c['d']:g}, l {c['l']:g} [{c['source']}] {c.get('note', '')}"
               for zone, c in geo.raw["creep"]["materials"].items()]
            + [f"creep.{key} = {item['value']} [{item['source']}] {item.get('note', '')}"
               for key in ("wait_until", "wait_steps") for item in [geo.raw["creep"][key]]])


def plan_history(geo, mesh):
    """Element groups and the stage list. Returns (stages, notes): stages are tuples
    (keyword, field2, ninc, date, label); notes describe snapped values for the header."""
    y = geo.row_lines()
    ym, parent = geo.mesh_lines()
    step, tops = geo.v("increments", "water_step"), geo.v("slab", "phase_tops")
    stages, notes, placed, level = [], [], set(), None
    body = [q for q in mesh.quads if q.kind == "body"]
    for event in geo.raw["history"]:
        if event["event"] == "fill":
            top = snap(y, event["top"])
            notes.append(f"block {event['name']} ({event['dates']}): top {event['top']:.1f} m"
                         f" -> row line {top:.2f} m; downstream edge {event['edge']:g} m at the"
                         f" top, temporary slope 1V:{event['slope']}H [{event['source']}]")
            layers = []
            for j in range(len(y) - 1):
                if y[j + 1] > top + 1e-6:
                    break
                name = f"{event['name']}R{j + 1:02d}"
                members = [q for q in body if parent[q.band] == j and id(q) not in placed
                           and centroid(mesh, q)[0] <= event["edge"] + event["slope"] *
                           (top - centroid(mesh, q)[1])]
                for q in members:
                    q.group = name
                    placed.add(id(q))
                if members:
                    layers.append((name, j))
            stages += [("FILL", name, geo.v("increments", "fill_layer"),
                        month_in(event["dates"], k, len(layers)),
                        f"block {event['name']} layer {y[j]:.1f}-{y[j + 1]:.1f} m")
                       for k, (name, j) in enumerate(layers)]
        elif event["event"] == "slab":
            phase, date = event["phase"], month_in(event["dates"], 0, 1)
            for q in mesh.quads:
                if q.kind in ("slab", "thin") and q.phase == phase:
                    q.group = f"SLAB{phase}"
            stages += [("RESET", "", 1, date, f"displacements zeroed before slab phase {phase}"),
                       ("FILL", f"SLAB{phase}", geo.v("increments", "slab_phase"), date,
                        f"slab phase {phase} to El. {tops[phase - 1]:.1f} m")]
        elif event["event"] == "water":
            start = geo.base if level is None else level
            n = max(1, math.ceil(abs(event["level"] - start) / step - 1e-9))
            stages.append(("WATER", event["level"], n, month_in(event["dates"], 0, 1),
                           f"reservoir to El. {event['level']:.1f} m [{event['source']}]"))
            notes.append(f"water {event['dates']}: El. {event['level']:.1f} m in {n} "
                         f"increments [{event['source']}] {event.get('note', '')}")
            level = event["level"]
    # Table 2's periods overlap: put the stages in calendar order (a stable sort keeps a
    # RESET with its slab phase and the order of the geometry file within a month).
    stages.sort(key=lambda st: st[3])
    missing = [q for q in body if id(q) not in placed]
    if missing:
        raise SystemExit(f"{len(missing)} body elements belong to no fill block: "
                         "the last block must reach the crest")
    # The cushion face under slab phase k is covered when that phase is placed.
    for q in (q for q in body if q.wet_face4):
        for phase, hi in enumerate(tops, 1):
            lo = tops[phase - 2] if phase > 1 else geo.base
            if lo - 1e-6 <= ym[q.band] and ym[q.band + 1] <= hi + 1e-6:
                q.cover = f"SLAB{phase}"
    return stages, notes


@dataclass
class Numbered:
    xy: np.ndarray          # (nnode, 2)
    conn: np.ndarray        # (nelem, 4), 1-based
    quads: list             # Quad per element, same order
    index: dict = None      # node key -> number
    pairs: list = None      # interface: (cushion node, slab node) numbers, bottom to top
    pjoint: list = None     # --plinth: (plinth node, slab node) numbers, face inwards


def node_pairs(geo, mesh, num, width=0.0):
    """Interface node pairs, bottom to top: every cushion face node with the slab node at
    its place (joint, width 0) or the thin layer's horizontal width upstream of it (thin)."""
    nodes = {kind: {k for q in mesh.quads if q.kind == kind for k in q.nodes}
             for kind in ("slab", "body")}
    at = {tuple(np.round(mesh.coords[k], 6)): k for k in nodes["slab"]}
    out = []
    for k in nodes["body"]:
        x, y = mesh.coords[k]
        s = at.get(tuple(np.round((x - width, y), 6)))
        if s is not None and (not width or abs(x - geo.x_up(y)) <= 1e-6):
            out.append((num.index[k], num.index[s]))
    return sorted(out, key=lambda p: num.xy[p[0] - 1, 1])


def number(mesh):
    """Nodes by elevation then x (the base nodes come first); elements by row then x."""
    keys = list(mesh.coords)
    pts = np.array([mesh.coords[k] for k in keys])
    order = np.lexsort((np.round(pts[:, 0], 6), np.round(pts[:, 1], 6)))
    index = {keys[k]: n + 1 for n, k in enumerate(order)}
    quads = sorted(mesh.quads, key=lambda q: (q.kind != "body", round(centroid(mesh, q)[1], 6),
                                              round(centroid(mesh, q)[0], 6)))
    return Numbered(pts[order], np.array([[index[k] for k in q.nodes] for q in quads]), quads,
                    index)


def describe(geo, r, num):
    """Counts, and per element det J at the corners (min/max ratio) and corner angles."""
    ratios, angles = [], []
    for c in num.conn:
        p = num.xy[c - 1]
        e1, e2 = np.roll(p, -1, axis=0) - p, np.roll(p, 1, axis=0) - p
        dets = e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0]
        if min(dets) <= 0:
            raise SystemExit(f"inverted or degenerate quad {c}")
        ratios.append(min(dets) / max(dets))
        angles += [math.degrees(math.atan2(d, float(a @ b))) for d, a, b in zip(dets, e1, e2)]
    kinds = [q.kind for q in num.quads]
    return {"refine": r, "nodes": len(num.xy), "elements": len(num.quads),
            "body": kinds.count("body"), "slab": kinds.count("slab"), "thin": kinds.count("thin"),
            "pairs": len(num.pairs or []), "jac_min": min(ratios), "jac_max": max(ratios),
            "angle_min": min(angles), "angle_max": max(angles)}


def gauge_nodes(geo, num):
    """Each gauge on the cushion face node nearest its elevation (on an x1 row line)."""
    y = geo.row_lines()
    face = [n for n in range(len(num.xy)) if abs(num.xy[n, 0] - geo.x_up(num.xy[n, 1])) < 1e-6]
    return [(min(face, key=lambda n: abs(num.xy[n, 1] - ys)) + 1, g["name"], g["elevation"], ys,
             g["source"]) for g in geo.raw["gauges"] for ys in [snap(y, g["elevation"])]]


# What docs/accuracy-cost.md measured for a deck at the knee and for the x1 decks (section 2,
# the `combined` rows and the x1 rows of the mesh knob; errors against the best estimate and
# against x8; the Q4S slab and the error control, redrawn for issue 21), quoted in the deck
# header. Other settings get no figures.
KNEE_FIGURES = {
    "bonded": "3.8 s; the settlement (its maximum, El. 709.3 m) 0.26 % from the best estimate;"
              " the gauge C1-H5 3.8 % off",
    "joint": "6.4 s; the settlement 0.06 % from the best estimate; the gauge C1-H5 6.1 % off;"
             " the openings not converged at any mesh",
    "thin": "3.7 s; the settlement 0.24 % from the best estimate; the gauge C1-H5 2.9 % off;"
            " the openings not converged at any mesh",
    "contact": "82 s; x1 and x2 do not resolve the 3.6 m openings; the phase I and II depths"
               " equal to x8, the widths 31 and 13 % from x8 (not converged); the settlement"
               " 0.03 % from x8",
}
X1_FIGURES = {
    "bonded": "0.7 s; the settlement 1.5 % (its maximum, on the mid-height row El. 709.3 m)"
              " from x8; the gauge C1-H5 17 % off, not converged",
    "joint": "0.9 s; the settlement 1.3 % from x8; the gauge C1-H5 17 % off; no opening at x1"
             " (x2-x8: 1-4 mm, not converged)",
    "thin": "0.9 s; the settlement 1.4 % from x8; the gauge C1-H5 13 % off; the openings not"
            " converged (widths 86-123 %, depths 100-134 % off the mesh reference)",
    "contact": "1.1 s; the settlement 1.2 % from x8; the gauge C1-H5 16 % off; no opening at"
               " x1 (the phase tops do not separate): the openings need x4",
}
KNEE_DECKS = {"bonded": "inputs/tianshengqiao.dat",
              "contact": "inputs/tianshengqiao-x4-contact.dat"}


def knee_lines(geo, r, interface):
    """Header lines: where the deck's settings sit against the knee of docs/accuracy-cost.md
    (mesh, increments per fill layer and slab phase, water step)."""
    def settings(r, ninc, step):
        return (f"mesh x{r}, {ninc} increment{'s' if ninc != 1 else ''} per layer, {step:g} m"
                f" water steps")
    ninc, ninc_slab = geo.v("increments", "fill_layer"), geo.v("increments", "slab_phase")
    ninc_text = ninc if ninc_slab == ninc else f"{ninc}/{ninc_slab}"
    step = float(geo.v("increments", "water_step"))
    kr, kinc, kstep = geo.knee(interface)
    knee = settings(kr, kinc, kstep)
    what = " for the contact openings" if interface == "contact" else ""
    if (r, ninc_text, step) == (kr, kinc, kstep):
        lines = [f"settings at the knee of {KNEE_DOC}: {knee}"]
        more = [what.strip() or f"for the {interface} method", KNEE_FIGURES[interface]]
    else:
        below = r <= kr and isinstance(ninc_text, int) and ninc <= kinc and step >= kstep
        mine = settings(r, ninc, step) if ninc_text == ninc else \
            f"mesh x{r}, {ninc_text} increments per layer/slab phase, {step:g} m water steps"
        lines = [f"{'below' if below else 'not'} the knee of {KNEE_DOC}: {mine}"]
        more = [f"the knee{what}: {knee}, " + (KNEE_DECKS.get(interface) or
                                                f"tools/tianshengqiao.py --knee --interface"
                                                f" {interface}")]
        if below and (r, ninc, step) == (1, 1, 10.0):
            more += [X1_FIGURES[interface], "the paper's resolution and the fast regression deck"]
    # a number stays with its unit on a line
    text = re.sub(r"(\d) (%|s\b|m\b)", "\\1\xa0\\2", "(" + "; ".join(more) + ")")
    return lines + ["  " + t.replace("\xa0", " ")
                    for t in textwrap.wrap(text, 90, break_on_hyphens=False)]


def write_deck(geo, r, num, stages, notes, path, solver="midpoint", interface="bonded",
               rule="LOBATTO", slab_type=None, mesh_label=None):
    plinth = bool(num.pjoint)
    nmat = (6 if interface in ("bonded", "contact") else 7) + (1 if plinth else 0)
    slab_type = slab_type or geo.v("slab", "element")
    gauges, info = gauge_nodes(geo, num), describe(geo, r, num)
    what = {"bonded": "slab bonded to the cushion", "thin": "thin layer under the slab",
            "joint": f"Goodman joints ({rule.lower()})", "contact": "slab in contact"}[interface]
    place = "Tianshengqiao-I 0+630" if plinth else "Tianshengqiao-I section 0+630"
    what += ", plinth" if plinth else ""
    title = f"TITLE     {place}, {mesh_label or f'x{r} mesh'}, {what}"
    if len(title) > 80:         # --plinth with --face: the joints' rule is in the deck
        title = re.sub(r" \((lobatto|gauss)\)", "", title)
    if len(title) > 80:         # --face with the bonded slab's longer name
        title = title.replace(" section 0+630", " 0+630")
    lines = [title,
             "* Written by tools/tianshengqiao.py from inputs/tianshengqiao-i.toml; do not edit:",
             "* edit the geometry file and rerun `python3 tools/tianshengqiao.py --all`.",
             "* Sources: [paper] Qian et al. 2013; [lit] published values for this dam, not in",
             "* the paper's text; [choice] modelling choices with no source."]
    add = lines.append
    lines += ["* " + t for t in knee_lines(geo, r, interface)]
    lines += [f"*   {key} = {value} [{source}]" + (f" {note}" if note else "")
              for key, value, source, note in geo.sources + (pl.sources(geo) if plinth else [])]
    if slab_type != geo.v("slab", "element"):
        lines += [f"*   slab element {slab_type} (--slab-element), not slab.element above"
                  + (": Q4 locks in shear, for comparison only" if slab_type == "Q4" else "")]
    lines += ["*   materials: E-B parameters of the paper's Table 3; unit weight = density * 9.81",
              "*     / 1000; Kur = 2 K [choice] (blank KUR); sigma3 floor 0.1 pa (default)"]
    lines += ["*   " + t for t in notes]
    lines += [f"*   gauge {name}: El. {elevation:.1f} m [{source}] -> cushion node {node} at"
              f" El. {ys:.2f} m" for node, name, elevation, ys, source in gauges]
    add(f"* mesh: {info['nodes']} nodes, {info['body']} body quads, {info['slab']} slab quads,"
        f" {max(len(num.pairs or []) - 1, 0)} interface elements;"
        f" det J ratio {info['jac_min']:.3f}-{info['jac_max']:.3f}, corner angles"
        f" {info['angle_min']:.1f}-{info['angle_max']:.1f} deg")
    add("CONTROL")
    add("*NNODE NELEM NMAT MODEL        PA    GAMMAW UNITS     NEWTOPSOLVER       TOLMAXIT")
    control = (fi(len(num.xy)) + fi(len(num.conn)) + fi(nmat) + fi(1)
               + fr(101.325) + fr(GAMMA_W) + fa("KN-M") + fi(0))
    # Newton: midpoint predictor, then iterations to 1e-10 (equilibrium at every stage); or
    # the paper's midpoint stiffness method
    add(control + (fi(3) + fr(1.0e-10) + fi(30) if solver == "newton" else fi(1)))
    lines += ["NODES", "*  N1   N2  INC        X1        Y1"]
    for n, (x, yv) in enumerate(num.xy, 1):
        try:
            add(fi(n) + " " * 10 + fr(x) + fr(yv))
        except FieldOverflow:   # F10 cannot hold it to 1e-7 (fine meshes): a free card
            add(f"&{n},,,{free_real(x)},{free_real(yv)}")
    lines += ["ELEMENTS", "*  NE    I    J    K    L  MAT NGEN NINC GROUP"]
    # The slab in Q4S quads (no parasitic shear in bending: its elements are 2-30 times
    # longer than thick and bend with the cushion; the Q4 slab locks, tianshengqiao.md 11.3).
    lines += [fi(e) + "".join(fi(v) for v in c) + fi(q.material or SLAB_MATERIAL) + " " * 10
              + fa(q.group)
              + ("Q4S" if q.kind == "slab" and slab_type == "Q4S" else "")
              for e, (c, q) in enumerate(zip(num.conn, num.quads), 1)]
    add("MATERIALS")
    for m, zone in enumerate(ZONES, 1):
        p = geo.raw["materials"][zone]
        lines += [fi(m) + fa("EB") + p["label"],
                  "*    GAMMA         K         N        RF        KB         M       KUR",
                  fr(round(p["density"] * GRAVITY_G / 1000.0, 6)) + "".join(
                      fr(p[k]) for k in ("K", "n", "Rf", "Kb", "m")),
                  "*     PHI0      DPHI         C   SIG3MIN",
                  fr(p["phi0"]) + fr(p["dphi"]) + fr(0.0)]
        if geo.creep:
            c = geo.raw["creep"]["materials"][zone]
            lines += ["*KEYWORD      ALPHA         B        MC         D         L",
                      fa("CREEP") + "".join(fr(c[k]) for k in ("alpha", "b", "mc", "d", "l"))]
    lines += [fi(SLAB_MATERIAL) + fa("ELASTIC") + "face slab, concrete",
              "".join(fr(geo.v("slab", k)) for k in ("youngs_modulus", "poisson_ratio",
                                                      "unit_weight", "tensile_strength"))]
    v = lambda key: geo.v("interface", key)        # noqa: E731
    if interface == "thin":
        lines += [fi(THIN_MATERIAL) + fa("ELASTIC") + "thin layer between slab and cushion",
                  fr(v("thin_youngs_modulus")) + fr(v("thin_poisson_ratio")) + fr(0.0)]
    elif interface == "joint":
        lines += [fi(THIN_MATERIAL) + fa("GOODMAN") + "slab-cushion joint, paper Table 4",
                  "*      KNC       KNT        K1        N1       RF1       PHI     SNMIN CUT",
                  "".join(fr(v("goodman_" + k)) for k in ("kn_compression", "kn_tension", "k1",
                                                         "n1", "rf1", "phi"))
                  + " " * 10 + fi(v("goodman_cutoff"))]
    if plinth:
        lines += [fi(nmat) + fa("PJOINT") + "perimetric joint, slab on plinth",
                  "*      KNC       KNT        KS",
                  "".join(fr(geo.v("plinth", "pjoint_" + k)) for k in ("kn_compression",
                                                                       "kn_tension", "ks"))]
    tops = geo.v("slab", "phase_tops")
    if interface in ("joint", "thin"):
        # One line of node pairs from the toe up: cushion node (bottom), slab node (top);
        # the element above each pair belongs to the slab phase that places it.
        lines += ["INTERFACE", "*LINE   NB   NT NGEN INCB INCT  MAT TYPE      RULE      GROUP"]
        pairs = num.pairs
        for k, (b, t) in enumerate(pairs):
            y_next = num.xy[pairs[min(k + 1, len(pairs) - 1)][0] - 1, 1]
            phase = next(i for i, top in enumerate(tops, 1) if y_next <= top + 1e-6)
            add(fi(1) + fi(b) + fi(t) + " " * 15 + fi(THIN_MATERIAL)
                + fa("JOINT" if interface == "joint" else "THIN")
                + fa(rule if interface == "joint" else "") + fa(f"SLAB{phase}"))
    if plinth:
        # The perimetric joint: (plinth node, slab node) pairs from the face inwards, placed
        # with slab phase I.
        if interface not in ("joint", "thin"):
            lines += ["INTERFACE", "*LINE   NB   NT NGEN INCB INCT  MAT TYPE      RULE      GROUP"]
        lines += [fi(pl.PJOINT_LINE) + fi(b) + fi(t) + " " * 15 + fi(nmat) + fa("JOINT")
                  + fa("LOBATTO") + fa("SLAB1") for b, t in num.pjoint]
        lines += ["PLINTH", "*         GROUP", " " * 10 + fa(pl.PLINTH_GROUP)]
    # The slab's section forces and fibre stresses (docs/results.md) for every method.
    lines += ["SLAB", "*         GROUP"] + [" " * 10 + fa(f"SLAB{phase}")
                                            for phase in range(1, len(tops) + 1)]
    if interface == "contact":
        # The slab's inner faces (slave) and the body's upstream faces (master): the faces
        # whose two nodes lie on the cushion face line; independent nodes on either side.
        lines += ["CONTACT", "*KEYWORD  NAME       ELEM FACE"]
        on_face = [abs(x - geo.x_up(yv)) < 1e-6 for x, yv in num.xy]
        lines += [fa("SURFACE") + fa(surface) + fi(e) + fi(f + 1)
                  for surface, kind in (("SLABFACE", "slab"), ("CUSHION", "body"))
                  for e, (c, q) in enumerate(zip(num.conn, num.quads), 1) if q.kind == kind
                  for f in range(4) if on_face[c[f] - 1] and on_face[c[(f + 1) % 4] - 1]]
        lines += ["*KEYWORD  SLAVE     MASTER          MU       TOL SCHEME    SEARCH     CAST",
                  fa("PAIR") + fa("SLABFACE") + fa("CUSHION") + fr(v("contact_friction"))
                  + fr(v("contact_tolerance")) + fa("MORTAR") + fa("LINEAR") + fi(1)]
    base = np.nonzero(np.abs(num.xy[:, 1] - geo.base) < 1e-9)[0] + 1
    assert plinth or np.all(np.diff(base) == 1)
    lines += ["BOUNDARY", "*  N1   N2  INC   IX   IY"]
    lines += [fi(a) + fi(b) + fi(1) * 3 for a, b in pl.runs(pl.fixed_nodes(num, geo))] \
        if plinth else [fi(base[0]) + fi(base[-1]) + fi(1) * 3]
    lines += ["RESERVOIR", "* ELEM FACE COVER"] + [fi(e) + fi(4) + fa(q.cover) for e, q in
                                                    enumerate(num.quads, 1) if q.wet_face4]
    lines += ["GAUGES", "* NODE NAME      LABEL"] + [
        fi(node) + fa(name) + f"cushion face, El. {ys:.2f} m" for node, name, _, ys, _ in gauges]
    lines += ["STAGES", "*KEYWORD GROUP/LEVEL NINC DATE      LABEL"] + [
        fa(keyword) + (fr(field2) if keyword == "WATER" else fa(field2)) + fi(ninc) + fa(date)
        + label[:45] for keyword, field2, ninc, date, label in stages] + ["END"]
    for n, line in enumerate(lines, 1):
        if not line.startswith("*") and len(line) > 80:
            raise SystemExit(f"deck line {n} longer than 80 columns: {line}")
    Path(path).write_text("\n".join(lines) + "\n")
    return info


def generate(r, geo=None, interface="bonded", face=None, face_band=6, plinth=False,
             solver_note=None, normal_rings=None):
    """(geometry, numbered mesh, stages, notes) of the xr mesh, or with face the face-
    resolved one (face_split: rows and slab in `face` divisions, the body's columns at r, the
    first face_band in `face`)."""
    geo = geo or Geometry()
    mesh = build_x1(geo, interface, plinth, normal_rings)
    assign_zones(geo, mesh)
    stages, notes = plan_history(geo, mesh)
    if geo.creep:
        stages, notes = creep_history(geo, stages), notes + creep_notes(geo)
    if face is not None:
        fine = refine(mesh, r, pl.split(face_split(r, face, face_band), r, face) if plinth
                      else face_split(r, face, face_band))
        notes = notes + [f"face-resolved mesh (--face {face} --face-band {face_band}): every"
                         f" x1 row and slab element in {face} along the slope, the first"
                         f" {face_band} body columns from the upstream face at x{face}, the"
                         f" other columns at x{r}"]
    else:
        fine = refine(mesh, r, pl.split(None, r, r)) if plinth else refine(mesh, r)
    if plinth:
        stages = [("FILL", pl.PLINTH_GROUP, 1, stages[0][3], "plinth on the rock")] + stages
        notes = notes + [f"plinth: {geo.v('plinth', 'width'):g} m upstream of the slab's toe,"
                         f" {geo.v('plinth', 'thickness'):g} m thick on rock below the base, the"
                         " slab's concrete (material 6); the slab's end cut normal to the face"
                         f" on it through the PJOINT joint of INTERFACE line {pl.PJOINT_LINE};"
                         " no water on the plinth [choice]"]
        if solver_note:
            notes.append(solver_note)
    if interface == "thin":
        # The layer is one element thick at every refinement: the INTERFACE cards make its
        # quads from the cushion and slab node pairs, so the refined layer goes.
        layer_keys = {k for q in fine.quads if q.kind == "thin" for k in q.nodes}
        fine.quads = [q for q in fine.quads if q.kind != "thin"]
        used = {k for q in fine.quads for k in q.nodes}
        fine.coords = {k: v for k, v in fine.coords.items() if k in used or k not in layer_keys}
    num = number(fine)
    num.pairs = node_pairs(geo, fine, num) if interface == "joint" else node_pairs(
        geo, fine, num, geo.v("interface", "thin_thickness") * math.sqrt(1.0 + geo.su ** 2)) \
        if interface == "thin" else []
    num.pjoint = pl.joint_pairs(num, geo) if plinth else []
    return geo, num, stages, notes


def slab_lengths(num):
    """Each slab element's length along the slope (its longer mid-line, cfrd's slab axis) and
    its slab phase, as two arrays."""
    out, phases = [], []
    for q, c in zip(num.quads, num.conn):
        if q.kind != "slab":
            continue
        p = num.xy[c - 1]
        out.append(max(np.linalg.norm(p[1] + p[2] - p[0] - p[3]),
                       np.linalg.norm(p[2] + p[3] - p[0] - p[1])) / 2.0)
        phases.append(q.phase)
    return np.array(out), np.array(phases)


def set_contact_elements(geo, counts, note):
    """The contact slab's elements along the slope per phase at x1 (in place of the geometry
    file's interface.contact_elements), with the header's note."""
    geo.raw["interface"]["contact_elements"] = {"value": list(counts), "source": "choice",
                                                "note": note}
    geo.list_sources()


def auto_face(r, geo, interface, face_band, plinth, solver_note, normal_rings,
              contact_counts_given=False):
    """--face auto: the smallest face factor F in {r..8} whose slab elements are all at most
    pi / (6 lambda) long along the slope (pi / lambda: [slab] decay_length of the geometry
    file for this interface). The contact slab, meshed on its own, gets at face 8 the fewest
    elements per phase that meet the rule (its count raised phase by phase from the geometry
    file's), unless --contact-elements set them. Otherwise 8, with a warning, when no face
    meets it. Returns (F or None when F = r, the generate() tuple, the header note)."""
    decay = float(geo.v("slab", "decay_length")[interface])
    limit = RESOLUTION_FRACTION * decay

    def attempt(f):
        made = generate(r, geo, interface, None if f == r else f, face_band, plinth,
                        solver_note, normal_rings)
        return made, *slab_lengths(made[1])

    for f in (f for f in FACES if f >= r):
        made, lengths, phases = attempt(f)
        if lengths.max() <= limit:
            break
    raised = ""
    if lengths.max() > limit and interface == "contact" and not contact_counts_given:
        geo = copy.deepcopy(geo)
        counts = list(geo.v("interface", "contact_elements"))
        cap = [8 * n for n in counts]      # a guard: the rule is met far below it
        while lengths.max() > limit and all(n < c for n, c in zip(counts, cap)):
            for k in range(len(counts)):
                if lengths[phases == k + 1].max(initial=0.0) > limit:
                    counts[k] += 1
            set_contact_elements(geo, counts, "slab elements along the slope per phase in"
                                 " the contact mesh: the fewest from the geometry file's"
                                 " that meet a <= pi / (6 lambda) at face factor 8 (--face"
                                 " auto)")
            made, lengths, phases = attempt(f)
        raised = f"; contact slab elements per phase {','.join(map(str, counts))}"
    longest = float(lengths.max())
    met = longest <= limit
    note = (f"--face auto: face factor {f}{raised}, the slab's elements at most {longest:.3f} m"
            f" along the slope {'<=' if met else '>'} pi / (6 lambda) = {limit:.3f} m (pi /"
            f" lambda = {decay:g} m, [slab] decay_length of the geometry file, {interface})"
            + ("" if met else f": NOT met even at face factor {f}, the finest --face gives"))
    if not met:
        print(f"warning: --face auto: the {interface} slab's elements are up to {longest:.3f} m"
              f" long at face factor {f} (x{r} body), more than pi / (6 lambda) = {limit:.3f} m:"
              f" the slab's bending is not resolved by the rule (docs/tianshengqiao.md"
              f" s. 11.5); writing face factor {f}", file=sys.stderr)
    return (None if f == r else f), made, note


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--refine", type=int, default=None, choices=[1, 2, 4, 8],
                    help="mesh refinement (default 1)")
    ap.add_argument("--deck", help="write the cfrd deck here")
    ap.add_argument("--knee", action="store_true",
                    help=f"the settings at the knee of {KNEE_DOC} for --interface (the geometry"
                         " file's [knee]: mesh, increments per layer and slab phase, water"
                         " step) in place of --refine and [increments]")
    ap.add_argument("--all", action="store_true",
                    help="write inputs/tianshengqiao-x1.dat and -x2.dat (bonded), the x1 joint,"
                         " thin and contact decks, and the decks at the knee:"
                         " inputs/tianshengqiao.dat (bonded) and"
                         " inputs/tianshengqiao-x4-contact.dat")
    ap.add_argument("--interface", default="bonded", choices=list(INTERFACES),
                    help="slab-cushion interface: bonded (shared nodes), thin (thin-layer"
                         " quads), joint (Goodman joints on node pairs) or contact (the slab"
                         " meshed on its own, CONTACT cards)")
    ap.add_argument("--geometry", default=str(GEOMETRY))
    ap.add_argument("--solver", default=None, choices=["midpoint", "newton"],
                    help="midpoint stiffness (the paper's; the default) or Newton to 1e-10"
                         " (the default with --plinth: the midpoint method goes out of"
                         " balance once the perimetric joint opens)")
    ap.add_argument("--report", action="store_true", help="print the mesh quality")
    ap.add_argument("--plinth", action="store_true",
                    help="a concrete plinth on the rock at the slab's toe and a perimetric"
                         " joint (PJOINT) between it and the slab's end ([plinth] of the"
                         " geometry file; docs/tianshengqiao.md s. 10)")
    ap.add_argument("--slab-element", choices=["Q4", "Q4S"], default=None,
                    help="element type of the slab (default: the geometry file's slab.element,"
                         " Q4S cut normal to the face, for every interface); Q4 writes the"
                         " decks before issue 22 for comparison: Q4 quads on the body's row"
                         " lines (contact: normal to the face), which lock in shear and"
                         " under-report the slab's bending near the toe (docs/tianshengqiao.md"
                         " s. 11.3)")
    ap.add_argument("--rule", default="LOBATTO", choices=["LOBATTO", "GAUSS"],
                    help="integration rule of the joints (--interface joint)")
    ap.add_argument("--top-rows", type=int, default=None,
                    help="split the top row of slab phases I and II into this many mesh rows"
                         " (x1; refined with the rest)")
    ap.add_argument("--face", default=None, choices=[str(f) for f in FACES] + ["auto"],
                    help="face-resolved mesh (issue 7 experiment): every body row and the slab"
                         " divided in FACE per x1 row and element, the body's columns at the"
                         " --refine level; auto: the smallest FACE from the --refine level to"
                         " 8 whose slab elements are at most pi / (6 lambda) long along the"
                         " slope (pi / lambda: the geometry file's [slab] decay_length for"
                         " --interface; the rule cfrd's summary checks, docs/theory.md s. 13;"
                         " contact: at 8, the fewest slab elements per phase that meet it,"
                         " unless --contact-elements is given; a warning and 8 when even 8"
                         " does not meet it: bonded, docs/tianshengqiao.md s. 11.5)")
    ap.add_argument("--contact-elements", default=None, metavar="N1,N2,N3",
                    help="--interface contact: the slab's own elements along the slope per"
                         " phase at x1 in place of the geometry file's contact_elements (for"
                         " the study of docs/tianshengqiao.md s. 11.5: 11,9,6 with --face 8"
                         " or --refine 8 meets a <= pi / (6 lambda), which 8,8,4 does not)")
    ap.add_argument("--face-band", type=int, default=6,
                    help="with --face: the first N body columns from the upstream face (1: IIA,"
                         " 2: IIA and IIIA, more: IIIB columns of about 11.6 m at x1; default 6,"
                         " 54 m) divided in FACE too")
    ap.add_argument("--creep", action="store_true",
                    help="time-dependent rockfill deformation: a CREEP card for every zone"
                         " ([creep] of the geometry file), stage dates in days and WAIT stages"
                         " to [creep] wait_until (docs/tianshengqiao.md s. 9)")
    args = ap.parse_args(argv)
    if args.solver is None:
        args.solver = "newton" if args.plinth else "midpoint"
    base = Geometry(args.geometry)
    base.creep = args.creep
    if args.top_rows is not None:
        base.top_rows = args.top_rows
    if args.contact_elements is not None:
        counts = [int(n) for n in args.contact_elements.split(",")]
        if len(counts) != len(base.v("slab", "phase_tops")) or min(counts) < 1:
            ap.error("--contact-elements: one count of at least 1 per slab phase, e.g. 11,9,6")
        set_contact_elements(base, counts, "slab elements along the slope per phase in the"
                             " contact mesh, set by --contact-elements in place of the"
                             " geometry file's")
    if args.plinth and args.all:
        ap.error("--plinth writes one deck: leave out --all (the decks in inputs/ have none)")
    if args.knee and args.refine is not None:
        ap.error("--knee sets the mesh: leave out --refine")
    if args.all:
        root = Path(__file__).resolve().parent.parent
        jobs = [(r, root / f"inputs/tianshengqiao-x{r}.dat", "bonded", False) for r in (1, 2)]
        jobs += [(1, root / f"inputs/tianshengqiao-x1-{m}.dat", m, False)
                 for m in ("joint", "thin", "contact")]
        jobs += [(None, root / deck, m, True) for m, deck in KNEE_DECKS.items()]
    else:
        jobs = [(args.refine or 1, Path(args.deck) if args.deck else None, args.interface,
                 args.knee)]
    slab_element = args.slab_element or base.v("slab", "element")
    for r, path, interface, knee in jobs:
        r, geo = base.at_knee(interface) if knee else (r, base)
        # Q4S slabs (the default, or --slab-element Q4S) get element ends normal to the
        # face: Q4S is not generated on skewed slab elements (issue 22). The contact slab's
        # own mesh is normal to the face with either element.
        solver_note = ("midpoint method: out of balance once the perimetric joint opens"
                       " (relative residual up to 7 in the last water stage); use --solver"
                       " newton (docs/tianshengqiao.md s. 10)" if args.solver == "midpoint"
                       else None)
        normal_rings = interface == "contact" or slab_element == "Q4S"
        if args.face == "auto":
            face, (geo, num, stages, notes), auto_note = auto_face(
                r, geo, interface, args.face_band, args.plinth, solver_note, normal_rings,
                args.contact_elements is not None)
            notes = notes + [auto_note]
        else:
            face = None if args.face is None else int(args.face)
            geo, num, stages, notes = generate(r, geo, interface, face, args.face_band,
                                               args.plinth, solver_note, normal_rings)
        if path is not None:
            info = write_deck(geo, r, num, stages, notes, path, args.solver, interface,
                              args.rule, slab_element,
                              None if face is None else f"x{r} body, x{face} face")
        else:
            info = describe(geo, r, num)
        if args.report or path is None:
            print(f"x{r}: {info['nodes']} nodes, {info['elements']} quads ({info['body']} body, "
                  f"{info['slab']} slab, {info['thin']} thin layer; {info['pairs']} interface"
                  f" node pairs); det J min/max ratio {info['jac_min']:.3f}-"
                  f"{info['jac_max']:.3f}; corner angles {info['angle_min']:.1f}-"
                  f"{info['angle_max']:.1f} deg" + (f" -> {path}" if path else ""))


if __name__ == "__main__":
    main()
