#!/usr/bin/env python3
"""Mesh generator and deck writer for the Tianshengqiao-I section (issue 5).

Reads the geometry file inputs/tianshengqiao-i.toml (every number that shapes the model,
with its source) and writes a complete cfrd deck: nodes, quads with their zones and fill
groups, the E-B and slab materials, the fixed base, the wetted faces of the reservoir, the
observation points and the construction and impounding history of the paper's Table 2.

The mesh (docs/tianshengqiao.md):
  * rows of the dam body follow elevation: one row per slab element along the slope below
    the phase III top, one row above it to the crest (24 rows at x1);
  * mesh lines parallel to the upstream face bound the IIA and IIIA bands (exact zones);
    further lines parallel to the upstream and to the downstream face are born, going down
    from the crest, wherever the central column grows wider than `split_width`: the row
    where they are born is a 3-to-1 quad transition, so the body is quads only;
  * the slab lies on the cushion face, two element layers through its thickness, one
    element per body row along the slope; its cross-lines are horizontal (the face's
    horizontal thickness is t sqrt(1 + s^2) for the normal thickness t);
  * refinement xR splits every x1 quad into R x R by its bilinear map, so each refined mesh
    holds the x1 mesh's lines, zones, groups and fill layers exactly.

Interfaces (--interface): bonded (the slab shares the cushion's nodes; the default),
thin (a row of thin-layer quads between cushion and slab), joint (Goodman joints between
matching node pairs on the interface) and contact (a slab mesh of its own, nodes not
matching the cushion's, with CONTACT cards: the slab's inner faces slave, the body's
upstream faces master, cast in place).

--face F (issue 7 experiment, default off): the face-resolved mesh, the x1 mesh divided quad
by quad instead of R x R: every row and the slab in F along the slope, the first --face-band
columns behind the cushion face at xF, the other columns at the level R (face_split).

CLI:
  python3 tools/tianshengqiao.py --all                 # every deck in inputs/ of this section
  python3 tools/tianshengqiao.py --refine 1 --deck inputs/tianshengqiao-x1.dat
  python3 tools/tianshengqiao.py --knee --interface joint --deck joint.dat  # at the knee
  python3 tools/tianshengqiao.py --refine 2 --report        # mesh quality only
"""

import argparse
import calendar
import datetime
import copy
import math
import re
import textwrap
try:
    import tomllib                      # Python 3.11 and later
except ImportError:                     # pragma: no cover
    import tomli as tomllib             # the same parser from PyPI
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from embankment import fmt_int, fmt_real, fmt_alpha, free_real, FieldOverflow

GEOMETRY = Path(__file__).resolve().parent.parent / "inputs" / "tianshengqiao-i.toml"
GRAVITY_G = 9.81            # m/s2: density (kg/m3) * g / 1000 = unit weight (kN/m3)
GAMMA_W = 9.81              # kN/m3, unit weight of water
ZONES = ["IIA", "IIIA", "IIIB", "IIIC", "IIID"]     # material numbers 1..5; the slab is 6
SLAB_MATERIAL = 6
KNEE_DOC = "docs/accuracy-cost.md"


# --------------------------------------------------------------------------------------
# The geometry file
# --------------------------------------------------------------------------------------

class Geometry:
    """Values of the geometry file; `choices` lists every [choice] for the deck header."""

    def __init__(self, path=GEOMETRY):
        self.path = Path(path)
        with open(self.path, "rb") as handle:
            self.raw = tomllib.load(handle)
        self.list_sources()

    def list_sources(self):
        self.choices = []
        self.sources = []
        for group in ("section", "slab", "interface", "zones", "mesh", "increments"):
            for key, item in self.raw[group].items():
                self.sources.append((f"{group}.{key}", item["value"], item["source"],
                                     item.get("note", "")))
        for key, item in self.raw["materials"].items():
            self.sources.append((f"materials.{key}", item["label"], item["source"], ""))

    creep = False   # --creep: CREEP cards, day dates, WAIT stages ([creep] of the file)

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
        inc = geo.raw["increments"]
        inc["fill_layer"] = {"value": ninc, "source": "choice",
                             "note": "increments per FILL layer, " + note}
        inc["slab_phase"] = {"value": ninc, "source": "choice",
                             "note": "increments per slab phase, " + note}
        inc["water_step"] = {"value": step, "source": "choice",
                             "note": "m of reservoir rise per increment, " + note}
        geo.list_sources()
        return r, geo

    @property
    def crest(self):
        return self.v("section", "crest_elevation")

    @property
    def base(self):
        return self.crest - self.v("section", "height")

    @property
    def su(self):
        return self.v("section", "upstream_slope")

    @property
    def sd(self):
        return self.v("section", "downstream_slope")

    def x_up(self, y):
        """x of the cushion face (upstream face of the body) at elevation y."""
        return self.su * (y - self.base)

    def x_down(self, y):
        """x of the downstream face at elevation y."""
        top_right = self.x_up(self.crest) + self.v("section", "crest_width")
        return top_right + self.sd * (self.crest - y)

    def slab_thickness(self, y):
        return self.v("slab", "t0") + self.v("slab", "rate") * (self.crest - y)

    def row_lines(self):
        """Elevations of the x1 row lines, base to crest."""
        tops = self.v("slab", "phase_tops")
        counts = self.v("slab", "phase_elements")
        lines = [self.base]
        bottom = self.base
        for top, n in zip(tops, counts):
            lines += [bottom + (top - bottom) * k / n for k in range(1, n + 1)]
            bottom = top
        if self.crest > bottom + 1e-9:
            lines.append(self.crest)
        return np.array(lines)

    # Rows of the top row of each slab phase but the last (the zone where a phase's slab top
    # separates, paper Figs. 11-12) split into this many mesh rows of equal height; the fill
    # layers, gauges and block tops stay on row_lines().
    top_rows = 1

    def mesh_lines(self):
        """Elevations of the x1 mesh's row lines, and for each mesh band the row_lines()
        band it lies in: row_lines() with the top row of each phase but the last split
        into top_rows rows."""
        lines = self.row_lines()
        tops = self.v("slab", "phase_tops")[:-1]
        out, parent = [lines[0]], []
        for j in range(len(lines) - 1):
            split = self.top_rows if any(abs(lines[j + 1] - t) < 1e-6 for t in tops) else 1
            for k in range(1, split + 1):
                out.append(lines[j] + (lines[j + 1] - lines[j]) * k / split)
                parent.append(j)
        return np.array(out), parent


# --------------------------------------------------------------------------------------
# The mesh
# --------------------------------------------------------------------------------------

@dataclass
class Quad:
    nodes: tuple            # 4 node keys, counter-clockwise
    kind: str               # 'body' or 'slab'
    band: int               # x1 row (0 = bottom row)
    material: int = 0       # 1..6
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


INTERFACES = ("bonded", "joint", "thin", "contact")
THIN_MATERIAL = 7


def build_x1(geo, interface="bonded"):
    """The x1 mesh: body rows with 3-to-1 transitions, the slab on the cushion face.

    interface: 'bonded' (the slab shares the cushion's nodes), 'joint' (matching nodes on
    both sides of the interface, paired in mesh.pairs, for zero-thickness joint elements),
    'thin' (a layer of quads of the thin-layer thickness between cushion and slab, the slab
    moved out by it), 'contact' (the slab meshed on its own, with slab.contact_elements
    along the slope: nodes that do not match the cushion's)."""
    mesh = Mesh()
    y, parent = geo.mesh_lines()
    nband = len(y) - 1
    unsplit = [parent.count(parent[j]) == 1 for j in range(nband)]
    bands_top = nband - 1
    split = geo.v("mesh", "split_width")
    frac = geo.v("mesh", "transition_height")
    # Line families: an upstream line keeps a constant horizontal offset from the cushion
    # face, a downstream line from the downstream face. Each line is (offset, band at whose
    # bottom it starts); the face, IIA and IIIA lines run from the base (band -1 never ends
    # them). A line is on row line j when it starts at band j or above.
    never = nband
    a = [(0.0, never), (geo.v("zones", "IIA_width"), never),
         (geo.v("zones", "IIA_width") + geo.v("zones", "IIIA_width"), never)]
    b = [(0.0, never)]
    births = set()                   # bands whose bottom starts a new line of each family
    for j in range(bands_top, -1, -1):
        width = geo.x_down(y[j]) - geo.x_up(y[j])
        gap = width - a[-1][0] - b[-1][0]
        # (a split row's bands are too low for a transition: it waits for the next row)
        if gap > split and unsplit[j]:
            # The new lines start one slope-run of the row from the old ones, so that each
            # ends right below the old line's top node (transition quads stay convex with
            # angles no smaller than the face's).
            h = y[j + 1] - y[j]
            births.add(j)
            a.append((a[-1][0] + geo.su * h, j))
            b.append((b[-1][0] + geo.sd * h, j))

    def lines_on(j):
        """Offsets (upstream, downstream) of the lines on row line j."""
        return ([off for off, born in a if born >= j], [off for off, born in b if born >= j])

    def row_keys(j, aa, bb):
        """Node keys and points along row line j, upstream to downstream."""
        yy = y[j]
        keys = []
        for off in aa:
            keys.append(mesh.point(("u", round(off, 9), j), (geo.x_up(yy) + off, yy)))
        for off in reversed(bb):
            keys.append(mesh.point(("d", round(off, 9), j), (geo.x_down(yy) - off, yy)))
        return keys

    for j in range(nband):
        aa_top, bb_top = lines_on(j + 1)
        aa_bot, bb_bot = lines_on(j)
        top = row_keys(j + 1, aa_top, bb_top)
        bot = row_keys(j, aa_bot, bb_bot)
        if j in births:
            # bottom: ... A_last, A_new, B_new, B_last ...; top: ... A_last, B_last ...
            ia = len(aa_top) - 1        # index of A_last in both rows
            assert len(bot) == len(top) + 2
            # Interior nodes at `frac` of the row height, shifted inwards from the
            # vertical through the new line's foot by `frac`/2 of its slope run.
            h = y[j + 1] - y[j]
            ym = y[j] + frac * h
            xa_new = mesh.coords[bot[ia + 1]][0]
            xb_new = mesh.coords[bot[ia + 2]][0]
            p1 = mesh.point(("p1", j), (xa_new + 0.5 * frac * geo.su * h, ym))
            p2 = mesh.point(("p2", j), (xb_new - 0.5 * frac * geo.sd * h, ym))
            for c in range(ia):
                mesh.quads.append(Quad((bot[c], bot[c + 1], top[c + 1], top[c]), "body", j,
                                       column=c if c < 2 else -1, ucol=c))
            A, An, Bn, B = bot[ia], bot[ia + 1], bot[ia + 2], bot[ia + 3]
            At, Bt = top[ia], top[ia + 1]
            for k, nodes in enumerate(((A, An, p1, At), (An, Bn, p2, p1), (Bn, B, Bt, p2),
                                       (p1, p2, Bt, At)), 1):
                mesh.quads.append(Quad(nodes, "body", j, transition=k, born=ia))
            for c in range(ia + 1, len(top) - 1):
                mesh.quads.append(Quad((bot[c + 2], bot[c + 3], top[c + 1], top[c]), "body", j,
                                       dcol=len(top) - 2 - c))
        else:
            assert len(bot) == len(top)
            nu = len(aa_top) - 1            # columns between two upstream lines
            for c in range(len(top) - 1):
                mesh.quads.append(Quad((bot[c], bot[c + 1], top[c + 1], top[c]), "body", j,
                                       column=c if c < 2 else -1, ucol=c if c < nu else -1,
                                       dcol=len(top) - 2 - c if c > nu else -1))
    # The upstream body face is wetted (cushion, or fill above the slab).
    for q in mesh.quads:
        if q.kind == "body" and q.column == 0:
            q.wet_face4 = True
    # The slab: one element per body row up to the phase III top (contact: its own rows),
    # `layers` through its thickness.
    layers = geo.v("slab", "layers")
    factor = math.sqrt(1.0 + geo.su ** 2)   # horizontal width of a unit normal thickness
    tops = geo.v("slab", "phase_tops")
    thin = geo.v("interface", "thin_thickness") if interface == "thin" else 0.0

    def phase_of(y_top):
        return next(k for k, top in enumerate(tops, 1) if y_top <= top + 1e-9)

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
        xi = geo.x_up(yy)
        th = geo.slab_thickness(yy) * factor
        face = ("u", 0.0, tag)
        if interface == "bonded":
            inner = face
        elif interface == "joint":
            inner = mesh.point(("j", tag), (xi, yy))
            mesh.pairs.append((face, inner))
        elif interface == "thin":
            inner = mesh.point(("t", tag), (xi - thin * factor, yy))
        else:
            inner = mesh.point(("ci", tag), (xi, yy))
        keys = [inner]
        for layer in range(1, layers + 1):
            if interface == "contact" and yy > geo.base + 1e-9:
                # The contact slab's own mesh: rings normal to the face (rectangles along
                # the slope, no skew), but at the toe, where the ring lies on the base.
                t = geo.slab_thickness(yy) * layer / layers
                keys.append(mesh.point(("s", layer, tag), (xi - t / factor,
                                                           yy + t * geo.su / factor)))
                continue
            keys.append(mesh.point(("s", layer, tag), (xi - thin * factor - th * layer / layers, yy)))
        rings.append((tag, yy, face, keys))
    for (tag0, y0, face0, ring0), (tag1, y1, face1, ring1) in zip(rings, rings[1:]):
        band = tag0 if isinstance(tag0, int) else -1
        phase = phase_of(y1)
        for layer in range(layers):
            # nodes (outer bottom, inner bottom, inner top, outer top); face 4 is outside
            mesh.quads.append(Quad((ring0[layer + 1], ring0[layer], ring1[layer], ring1[layer + 1]),
                                   "slab", band, material=SLAB_MATERIAL, phase=phase,
                                   wet_face4=(layer == layers - 1)))
        if interface == "thin":
            mesh.quads.append(Quad((ring0[0], face0, face1, ring1[0]), "thin", band,
                                   material=THIN_MATERIAL, phase=phase))
    return mesh


def refine(mesh, r, split=None):
    """Split each quad into r x r by its bilinear map; shared edges share their nodes.

    split: optional function of a quad giving (ns, nt), its divisions along its first edge
    (node 1 -> 2) and its second (node 2 -> 3), instead of (r, r); the divisions of an edge
    must be the same from both its quads (checked: no hanging nodes)."""
    if r == 1 and split is None:
        return mesh
    out = Mesh()
    divisions = {}                  # x1 edge (smaller key, larger key) -> its divisions
    for qi, q in enumerate(mesh.quads):
        corners = [np.array(mesh.coords[k]) for k in q.nodes]
        ns, nt = (r, r) if split is None else split(q)
        for n0, n1, nn in ((0, 1, ns), (1, 2, nt), (3, 2, ns), (0, 3, nt)):
            edge = tuple(sorted((q.nodes[n0], q.nodes[n1]), key=repr))
            if divisions.setdefault(edge, nn) != nn:
                raise SystemExit(f"refine: edge {edge} divided {divisions[edge]} and {nn}"
                                 " times by its two quads (a hanging node)")

        def key(i, j):
            # corner
            if (i, j) in ((0, 0), (ns, 0), (ns, nt), (0, nt)):
                return q.nodes[[(0, 0), (ns, 0), (ns, nt), (0, nt)].index((i, j))]
            # edge: identified by its end nodes and the position from the smaller key
            edges = {0: (0, 1, i, ns), 1: (1, 2, j, nt), 2: (3, 2, i, ns), 3: (0, 3, j, nt)}
            side = (0 if j == 0 else 1 if i == ns else 2 if j == nt else 3 if i == 0
                    else None)
            if side is not None:
                n0, n1, t, n = edges[side]
                ka, kb = q.nodes[n0], q.nodes[n1]
                if repr(ka) <= repr(kb):
                    return ("e", ka, kb, t, n)
                return ("e", kb, ka, n - t, n)
            return ("i", qi, i, j)

        def xy(i, j):
            s, t = i / ns, j / nt
            return ((1 - s) * (1 - t) * corners[0] + s * (1 - t) * corners[1]
                    + s * t * corners[2] + (1 - s) * t * corners[3])

        for j in range(nt):
            for i in range(ns):
                ks = [key(i, j), key(i + 1, j), key(i + 1, j + 1), key(i, j + 1)]
                for kk, (ii, jj) in zip(ks, [(i, j), (i + 1, j), (i + 1, j + 1), (i, j + 1)]):
                    if kk not in out.coords:
                        # points on an edge come from the canonical end (same rounding)
                        if kk[0] == "e":
                            pa, pb = np.array(mesh.coords[kk[1]]), np.array(mesh.coords[kk[2]])
                            out.coords[kk] = tuple(pa + (pb - pa) * (kk[3] / kk[4]))
                        elif kk[0] == "i":
                            out.coords[kk] = tuple(xy(ii, jj))
                        else:
                            out.coords[kk] = mesh.coords[kk]
                out.quads.append(Quad(tuple(ks), q.kind, q.band, q.material, q.group,
                                      q.wet_face4 and i == 0, q.cover, q.column))
    return out


def face_split(r, face, band=0):
    """Divisions of the x1 quads for the face-resolved mesh (--face F): every body row and
    every slab element along the slope in F, the body's columns in r (the level), but the
    first `band` columns from the upstream face (1: IIA, 2: IIA and IIIA, 3 and more: IIIB
    columns too) in F, and the slab in F through its thickness too (the xF slab).

    A 3-to-1 transition's quads 1-3 border the split rows on their sides: (r, F); its top
    quad borders row lines only: (r, r). Where a transition starts an upstream column of
    the band, its quads 1 and 3 are (F, F) and 2 and 4 (r, F), and the downstream column it
    starts (the mirror one) is in F as well."""
    def split(q):
        if q.kind == "slab":
            return face, face           # (through the thickness, along the slope)
        if q.transition:
            if q.born < band:
                return (face, face) if q.transition in (1, 3) else (r, face)
            return (r, r) if q.transition == 4 else (r, face)
        if 0 <= q.ucol < band or 0 <= q.dcol < band - 2:
            return face, face
        return r, face
    return split


# --------------------------------------------------------------------------------------
# Zones, groups, history
# --------------------------------------------------------------------------------------

def point_in_polygon(x, y, poly):
    inside = False
    n = len(poly)
    for k in range(n):
        (x1, y1), (x2, y2) = poly[k], poly[(k + 1) % n]
        if (y1 > y) != (y2 > y):
            xc = x1 + (y - y1) * (x2 - x1) / (y2 - y1)
            if x < xc:
                inside = not inside
    return inside


def centroid(mesh, q):
    pts = np.array([mesh.coords[k] for k in q.nodes])
    return pts.mean(axis=0)


def assign_zones(geo, mesh):
    """Materials: IIA and IIIA by mesh column, IIIC by polygon, IIIB/IIID by the line."""
    (xa, ya), (xb, yb) = geo.v("zones", "IIIB_IIID_line")
    poly = geo.v("zones", "IIIC_polygon")
    for q in mesh.quads:
        if q.kind != "body":
            continue
        if q.column == 0:
            q.material = 1
            continue
        if q.column == 1:
            q.material = 2
            continue
        cx, cy = centroid(mesh, q)
        if point_in_polygon(cx, cy, poly):
            q.material = 4
        else:
            x_line = xa + (cy - ya) * (xb - xa) / (yb - ya)
            q.material = 3 if cx < x_line else 5


def month_in(dates, k, n):
    """Date 'YYYY.MM' of the end of step k (0-based) of n spread over 'YYYY.MM-YYYY.MM'."""
    first, _, last = dates.partition("-")
    last = last or first
    m0 = int(first[:4]) * 12 + int(first[5:7]) - 1
    m1 = int(last[:4]) * 12 + int(last[5:7]) - 1
    m = m0 + round((k + 1) * (m1 - m0) / n)
    return f"{m // 12}.{m % 12 + 1:02d}"


def creep_history(geo, stages):
    """The stages of a deck with creep (--creep): time matters, so the months of the stages
    become days (YYYY-MM-DD): the k stages of one month, in their order, at the ends of k
    equal parts of it, the last on its last day; a RESET on the day of the slab phase it
    prepares [choice]. Then WAIT stages, one a year, to [creep] wait_until."""
    dated = [st for st in stages if st[0] != "RESET"]
    per_month = {}
    for st in dated:
        per_month.setdefault(st[3], []).append(st)
    day_of = {}
    for month, group in per_month.items():
        year, mon = int(month[:4]), int(month[5:7])
        days = calendar.monthrange(year, mon)[1]
        for i, st in enumerate(group):
            day_of[id(st)] = f"{year:04d}-{mon:02d}-{max(1, round((i + 1) * days / len(group))):02d}"
    out = []
    for k, st in enumerate(stages):
        if st[0] == "RESET":
            follower = next(x for x in stages[k + 1:] if x[0] != "RESET")
            out.append(st[:3] + (day_of[id(follower)],) + st[4:])
        else:
            out.append(st[:3] + (day_of[id(st)],) + st[4:])
    last = datetime.date.fromisoformat(out[-1][3])
    until = datetime.date.fromisoformat(geo.v("creep", "wait_until"))
    steps = geo.v("creep", "wait_steps")
    year = last.year
    while True:
        end = min(datetime.date(year, 12, 31), until)
        if end > last:
            out.append(("WAIT", "", steps, end.isoformat(),
                        f"time passes to {end.isoformat()} (creep) [choice]"))
        if end >= until:
            break
        year += 1
    return out


def snap(y_lines, level):
    return float(y_lines[int(np.argmin(np.abs(y_lines - level)))])


def creep_notes(geo):
    """Header lines of a creep deck: each zone's creep parameters with their source."""
    lines = ["creep: Shen's exponential-decay law with Li's final strains (docs/theory.md"
             " section 15); time from the stage dates"]
    for zone, c in geo.raw["creep"]["materials"].items():
        lines.append(f"creep {zone}: alpha {c['alpha']:g}/day, b {c['b']:g}, mc {c['mc']:g},"
                     f" d {c['d']:g}, l {c['l']:g} [{c['source']}] {c.get('note', '')}")
    for key in ("wait_until", "wait_steps"):
        item = geo.raw["creep"][key]
        lines.append(f"creep.{key} = {item['value']} [{item['source']}] {item.get('note', '')}")
    return lines


def plan_history(geo, mesh):
    """Element groups and the stage list. Returns (stages, notes): stages are tuples
    (keyword, field2, ninc, date, label); notes describe snapped values for the header."""
    y = geo.row_lines()
    ym, parent = geo.mesh_lines()
    ninc_layer = geo.v("increments", "fill_layer")
    ninc_slab = geo.v("increments", "slab_phase")
    step = geo.v("increments", "water_step")
    tops = geo.v("slab", "phase_tops")
    stages, notes = [], []
    placed = set()
    level = None
    body = [q for q in mesh.quads if q.kind == "body"]
    for event in geo.raw["history"]:
        kind = event["event"]
        if kind == "fill":
            top = snap(y, event["top"])
            notes.append(f"block {event['name']} ({event['dates']}): top {event['top']:.1f} m"
                         f" -> row line {top:.2f} m; downstream edge {event['edge']:g} m at the"
                         f" top, temporary slope 1V:{event['slope']}H [{event['source']}]")
            layers = []
            for j in range(len(y) - 1):
                if y[j + 1] > top + 1e-6:
                    break
                name = f"{event['name']}R{j + 1:02d}"
                members = []
                for q in body:
                    if parent[q.band] != j or id(q) in placed:
                        continue
                    cx, cy = centroid(mesh, q)
                    if cx <= event["edge"] + event["slope"] * (top - cy):
                        members.append(q)
                if not members:
                    continue
                for q in members:
                    q.group = name
                    placed.add(id(q))
                layers.append((name, j))
            for k, (name, j) in enumerate(layers):
                stages.append(("FILL", name, ninc_layer, month_in(event["dates"], k, len(layers)),
                               f"block {event['name']} layer {y[j]:.1f}-{y[j + 1]:.1f} m"))
        elif kind == "slab":
            phase = event["phase"]
            lo = tops[phase - 2] if phase > 1 else geo.base
            hi = tops[phase - 1]
            name = f"SLAB{phase}"
            for q in mesh.quads:
                if q.kind in ("slab", "thin") and q.phase == phase:
                    q.group = name
            stages.append(("RESET", "", 1, month_in(event["dates"], 0, 1),
                           f"displacements zeroed before slab phase {phase}"))
            stages.append(("FILL", name, ninc_slab, month_in(event["dates"], 0, 1),
                           f"slab phase {phase} to El. {hi:.1f} m"))
        elif kind == "water":
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
    for q in mesh.quads:
        if q.kind == "body" and q.wet_face4:
            for phase, hi in enumerate(tops, 1):
                lo = tops[phase - 2] if phase > 1 else geo.base
                if lo - 1e-6 <= ym[q.band] and ym[q.band + 1] <= hi + 1e-6:
                    q.cover = f"SLAB{phase}"
    return stages, notes


# --------------------------------------------------------------------------------------
# Numbering, quality, deck
# --------------------------------------------------------------------------------------

@dataclass
class Numbered:
    xy: np.ndarray          # (nnode, 2)
    conn: np.ndarray        # (nelem, 4), 1-based
    quads: list             # Quad per element, same order
    index: dict = None      # node key -> number
    pairs: list = None      # joint: (cushion node, slab node) numbers, bottom to top


def interface_pairs(mesh, num):
    """Joint mesh: every slab node on the interface with the cushion node at its place."""
    slab_nodes = {k for q in mesh.quads if q.kind == "slab" for k in q.nodes}
    body_nodes = {k for q in mesh.quads if q.kind == "body" for k in q.nodes}
    at = {}
    for k in body_nodes:
        at[tuple(np.round(mesh.coords[k], 6))] = k
    out = []
    for k in slab_nodes:
        b = at.get(tuple(np.round(mesh.coords[k], 6)))
        if b is not None:
            out.append((num.index[b], num.index[k]))
    return sorted(out, key=lambda p: num.xy[p[0] - 1, 1])


def thin_pairs(geo, mesh, num):
    """Thin layer: every cushion face node under the slab with the slab node the layer's
    horizontal width upstream of it, bottom to top."""
    width = geo.v("interface", "thin_thickness") * math.sqrt(1.0 + geo.su ** 2)
    slab_nodes = {k for q in mesh.quads if q.kind == "slab" for k in q.nodes}
    at = {tuple(np.round(mesh.coords[k], 6)): k for k in slab_nodes}
    body_nodes = {k for q in mesh.quads if q.kind == "body" for k in q.nodes}
    out = []
    for k in body_nodes:
        x, y = mesh.coords[k]
        if abs(x - geo.x_up(y)) > 1e-6:
            continue
        s = at.get(tuple(np.round((x - width, y), 6)))
        if s is not None:
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
    conn = np.array([[index[k] for k in q.nodes] for q in quads])
    return Numbered(pts[order], conn, quads, index)


def quality(num):
    """Per element: det J at the corners and the corner angles (degrees)."""
    ratios, angles = [], []
    for c in num.conn:
        p = num.xy[c - 1]
        dets, angs = [], []
        for k in range(4):
            a, b, d = p[k], p[(k + 1) % 4], p[(k - 1) % 4]
            e1, e2 = b - a, d - a
            cross = e1[0] * e2[1] - e1[1] * e2[0]
            dets.append(cross)
            angs.append(math.degrees(math.atan2(cross, float(e1 @ e2))))
        if min(dets) <= 0:
            raise SystemExit(f"inverted or degenerate quad {c}")
        ratios.append(min(dets) / max(dets))
        angles += angs
    return np.array(ratios), np.array(angles)


def element_area(p):
    x, y = p[:, 0], p[:, 1]
    return 0.5 * (np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1)))


def describe(geo, r, num):
    ratios, angles = quality(num)
    nbody = sum(q.kind == "body" for q in num.quads)
    nslab = sum(q.kind == "slab" for q in num.quads)
    nthin = sum(q.kind == "thin" for q in num.quads)
    return {"refine": r, "nodes": len(num.xy), "elements": len(num.quads), "body": nbody,
            "slab": nslab, "thin": nthin, "pairs": len(num.pairs or []),
            "jac_min": ratios.min(), "jac_max": ratios.max(),
            "angle_min": angles.min(), "angle_max": angles.max()}


def gauge_nodes(geo, num):
    """Each gauge on the cushion face node nearest its elevation (on an x1 row line)."""
    y = geo.row_lines()
    out = []
    face = [n for n in range(len(num.xy))
            if abs(num.xy[n, 0] - geo.x_up(num.xy[n, 1])) < 1e-6]
    for g in geo.raw["gauges"]:
        ys = snap(y, g["elevation"])
        node = min(face, key=lambda n: abs(num.xy[n, 1] - ys))
        out.append((node + 1, g["name"], g["elevation"], ys, g["source"]))
    return out


# What docs/accuracy-cost.md measured for a deck at the knee and for the x1 decks (section 2,
# the `combined` rows and the x1 rows of the mesh knob; errors against the best estimate and
# against x8), quoted in the deck header. Other settings get no figures.
KNEE_FIGURES = {
    "bonded": "3.7 s; the mid-height settlement (El. 709.3 m) 0.08 % and the overall maximum"
              " 0.85 % from the best estimate; the gauge C1-H5 13 % off (it needs x8)",
    "joint": "4.4 s; the mid-height settlement 0.04 % and the overall maximum 0.86 % from the"
             " best estimate; the gauge C1-H5 23 % off; the openings not converged at any mesh",
    "thin": "4.1 s; the mid-height settlement 0.26 % and the overall maximum 0.52 % from the"
            " best estimate; the gauge C1-H5 11 % off; the openings not converged at any mesh",
    "contact": "16 s; x1 and x2 do not resolve the 3.6 m openings; the phase I and II widths"
               " 4.8 and 2.7 % from x8, the depths equal; the mid-height settlement 0.03 % from"
               " x8; 2 increments per layer and 5 m water steps (28 s) widen phase I by 6 %",
}
X1_FIGURES = {
    "bonded": "0.5 s; the settlement 1.5 % (mid-height row, El. 709.3 m) and 2.3 % (overall"
              " maximum) from x8; the gauge C1-H5 8 % off, not converged",
    "joint": "0.6 s; the settlement 1.5 % (mid-height row) and 2.4 % (overall maximum) from x8;"
             " the gauge C1-H5 14 % off; the openings not converged (widths 90-100 %, depths"
             " 100-300 % off x8)",
    "thin": "0.5 s; the settlement 1.4 % (mid-height row) and 2.2 % (overall maximum) from x8;"
            " the gauge C1-H5 6 % off; the openings not converged (widths 40-100 %, depths"
            " 215-220 % off x8)",
    "contact": "0.6 s; the settlement 1.3 % (mid-height row) and 2.3 % (overall maximum) from"
               " x8; the gauge C1-H5 15 % off; no opening at x1 (the phase tops do not"
               " separate): the openings need x4",
}
KNEE_DECKS = {"bonded": "inputs/tianshengqiao.dat",
              "contact": "inputs/tianshengqiao-x4-contact.dat"}


def settings_text(r, ninc, step):
    return (f"mesh x{r}, {ninc} increment{'s' if ninc != 1 else ''} per layer, {step:g} m"
            f" water steps")


def knee_lines(geo, r, interface):
    """Header lines: where the deck's settings sit against the knee of docs/accuracy-cost.md
    (mesh, increments per fill layer and slab phase, water step)."""
    ninc = geo.v("increments", "fill_layer")
    if geo.v("increments", "slab_phase") != ninc:
        ninc_text = f"{ninc}/{geo.v('increments', 'slab_phase')}"
    else:
        ninc_text = ninc
    step = float(geo.v("increments", "water_step"))
    kr, kinc, kstep = geo.knee(interface)
    knee = settings_text(kr, kinc, kstep)
    what = " for the contact openings" if interface == "contact" else ""
    mine = settings_text(r, ninc, step) if ninc_text == ninc else \
        f"mesh x{r}, {ninc_text} increments per layer/slab phase, {step:g} m water steps"
    deck = KNEE_DECKS.get(interface) or \
        f"tools/tianshengqiao.py --knee --interface {interface}"
    if (r, ninc_text, step) == (kr, kinc, kstep):
        lines = [f"settings at the knee of {KNEE_DOC}: {knee}"]
        more = [what.strip() or f"for the {interface} method", KNEE_FIGURES[interface]]
    else:
        below = r <= kr and isinstance(ninc_text, int) and ninc <= kinc and step >= kstep
        lines = [f"{'below' if below else 'not'} the knee of {KNEE_DOC}: {mine}"]
        more = [f"the knee{what}: {knee}, {deck}"]
        if below and (r, ninc, step) == (1, 1, 10.0):
            more += [X1_FIGURES[interface],
                     "the paper's resolution and the fast regression deck"]
    # a number stays with its unit on a line
    text = re.sub(r"(\d) (%|s\b|m\b)", "\\1\xa0\\2", "(" + "; ".join(more) + ")")
    lines += ["  " + t.replace("\xa0", " ")
              for t in textwrap.wrap(text, 90, break_on_hyphens=False)]
    return lines


def write_deck(geo, r, num, stages, notes, path, solver="midpoint", interface="bonded",
               rule="LOBATTO", slab_type=None, mesh_label=None):
    if slab_type is None:
        slab_type = "Q4S" if interface == "contact" else "Q4"
    gauges = gauge_nodes(geo, num)
    info = describe(geo, r, num)
    lines = []
    add = lines.append
    what = {"bonded": "slab bonded to the cushion",
            "thin": "thin layer under the slab",
            "joint": f"Goodman joints ({rule.lower()})",
            "contact": "slab in contact"}[interface]
    add(f"TITLE     Tianshengqiao-I section 0+630, {mesh_label or f'x{r} mesh'}, {what}")
    add("* Written by tools/tianshengqiao.py from inputs/tianshengqiao-i.toml; do not edit:")
    add("* edit the geometry file and rerun `python3 tools/tianshengqiao.py --all`.")
    add("* Sources: [paper] Qian et al. 2013; [lit] published values for this dam, not in")
    add("* the paper's text; [choice] modelling choices with no source.")
    for text in knee_lines(geo, r, interface):
        add("* " + text)
    for key, value, source, note in geo.sources:
        text = f"*   {key} = {value} [{source}]" + (f" {note}" if note else "")
        add(text)
    add("*   materials: E-B parameters of the paper's Table 3; unit weight = density * 9.81")
    add("*     / 1000; Kur = 2 K [choice] (blank KUR); sigma3 floor 0.1 pa (default)")
    for text in notes:
        add("*   " + text)
    for node, name, elevation, ys, source in gauges:
        add(f"*   gauge {name}: El. {elevation:.1f} m [{source}] -> cushion node {node} at"
            f" El. {ys:.2f} m")
    add(f"* mesh: {info['nodes']} nodes, {info['body']} body quads, {info['slab']} slab quads,"
        f" {max(len(num.pairs or []) - 1, 0)} interface elements;"
        f" det J ratio {info['jac_min']:.3f}-{info['jac_max']:.3f}, corner angles"
        f" {info['angle_min']:.1f}-{info['angle_max']:.1f} deg")
    add("CONTROL")
    add("*NNODE NELEM NMAT MODEL        PA    GAMMAW UNITS     NEWTOPSOLVER       TOLMAXIT")
    nmat = 6 if interface in ("bonded", "contact") else 7
    control = (fmt_int(len(num.xy)) + fmt_int(len(num.conn)) + fmt_int(nmat) + fmt_int(1)
               + fmt_real(101.325) + fmt_real(GAMMA_W) + fmt_alpha("KN-M") + fmt_int(0))
    if solver == "newton":
        # midpoint predictor, then Newton iterations to 1e-10 (equilibrium at every stage)
        control += fmt_int(3) + fmt_real(1.0e-10) + fmt_int(30)
    else:
        control += fmt_int(1)   # the paper's midpoint stiffness method
    add(control)
    add("NODES")
    add("*  N1   N2  INC        X1        Y1")
    for n, (x, yv) in enumerate(num.xy, 1):
        try:
            add(fmt_int(n) + " " * 10 + fmt_real(x) + fmt_real(yv))
        except FieldOverflow:
            # a coordinate that F10 cannot hold to 1e-7 (fine meshes): a free-format card
            add(f"&{n},,,{free_real(x)},{free_real(yv)}")
    add("ELEMENTS")
    add("*  NE    I    J    K    L  MAT NGEN NINC GROUP")
    for e, (c, q) in enumerate(zip(num.conn, num.quads), 1):
        # The slab of the contact deck in Q4S quads (no parasitic shear in bending: its
        # elements are 20-30 times longer than thick and bend with the cushion).
        etype = "Q4S" if (q.kind == "slab" and slab_type == "Q4S") else ""
        add(fmt_int(e) + "".join(fmt_int(v) for v in c) + fmt_int(q.material) + " " * 10
            + fmt_alpha(q.group) + (fmt_alpha(etype).rstrip() if etype else ""))
    add("MATERIALS")
    for m, zone in enumerate(ZONES, 1):
        p = geo.raw["materials"][zone]
        add(fmt_int(m) + fmt_alpha("EB") + p["label"])
        add("*    GAMMA         K         N        RF        KB         M       KUR")
        add(fmt_real(round(p["density"] * GRAVITY_G / 1000.0, 6)) + fmt_real(p["K"])
            + fmt_real(p["n"]) + fmt_real(p["Rf"]) + fmt_real(p["Kb"]) + fmt_real(p["m"]))
        add("*     PHI0      DPHI         C   SIG3MIN")
        add(fmt_real(p["phi0"]) + fmt_real(p["dphi"]) + fmt_real(0.0))
        if geo.creep:
            c = geo.raw["creep"]["materials"][zone]
            add("*KEYWORD      ALPHA         B        MC         D         L")
            add(fmt_alpha("CREEP") + "".join(fmt_real(c[k]) for k in ("alpha", "b", "mc", "d",
                                                                        "l")))
    add(fmt_int(SLAB_MATERIAL) + fmt_alpha("ELASTIC") + "face slab, concrete")
    add(fmt_real(geo.v("slab", "youngs_modulus")) + fmt_real(geo.v("slab", "poisson_ratio"))
        + fmt_real(geo.v("slab", "unit_weight")))
    if interface == "thin":
        add(fmt_int(THIN_MATERIAL) + fmt_alpha("ELASTIC") + "thin layer between slab and cushion")
        add(fmt_real(geo.v("interface", "thin_youngs_modulus"))
            + fmt_real(geo.v("interface", "thin_poisson_ratio")) + fmt_real(0.0))
    elif interface == "joint":
        add(fmt_int(THIN_MATERIAL) + fmt_alpha("GOODMAN") + "slab-cushion joint, paper Table 4")
        add("*      KNC       KNT        K1        N1       RF1       PHI     SNMIN CUT")
        add("".join(fmt_real(geo.v("interface", key)) for key in
                    ("goodman_kn_compression", "goodman_kn_tension", "goodman_k1", "goodman_n1",
                     "goodman_rf1", "goodman_phi")) + " " * 10
            + fmt_int(geo.v("interface", "goodman_cutoff")))
    if interface in ("joint", "thin"):
        # One line of node pairs from the toe up: cushion node (bottom), slab node (top);
        # the element above each pair belongs to the slab phase that places it.
        add("INTERFACE")
        add("*LINE   NB   NT NGEN INCB INCT  MAT TYPE      RULE      GROUP")
        tops = geo.v("slab", "phase_tops")
        pairs = num.pairs
        for k, (b, t) in enumerate(pairs):
            y_next = num.xy[pairs[min(k + 1, len(pairs) - 1)][0] - 1, 1]
            phase = next(i for i, top in enumerate(tops, 1) if y_next <= top + 1e-6)
            add(fmt_int(1) + fmt_int(b) + fmt_int(t) + " " * 15 + fmt_int(THIN_MATERIAL)
                + fmt_alpha("JOINT" if interface == "joint" else "THIN")
                + fmt_alpha(rule if interface == "joint" else "") + fmt_alpha(f"SLAB{phase}"))
        add("SLAB")
        add("*         GROUP")
        for phase in range(1, len(tops) + 1):
            add(" " * 10 + fmt_alpha(f"SLAB{phase}"))
    if interface == "contact":
        add("SLAB")
        add("*         GROUP")
        for phase in range(1, len(geo.v("slab", "phase_tops")) + 1):
            add(" " * 10 + fmt_alpha(f"SLAB{phase}"))
        # The slab's inner faces (slave) and the body's upstream faces (master): the faces
        # whose two nodes lie on the cushion face line; independent nodes on either side.
        add("CONTACT")
        add("*KEYWORD  NAME       ELEM FACE")
        for surface, kind in (("SLABFACE", "slab"), ("CUSHION", "body")):
            for e, (c, q) in enumerate(zip(num.conn, num.quads), 1):
                if q.kind != kind:
                    continue
                for f in range(4):
                    a, b = c[f] - 1, c[(f + 1) % 4] - 1
                    if all(abs(num.xy[n, 0] - geo.x_up(num.xy[n, 1])) < 1e-6 for n in (a, b)):
                        add(fmt_alpha("SURFACE") + fmt_alpha(surface) + fmt_int(e)
                            + fmt_int(f + 1))
        add("*KEYWORD  SLAVE     MASTER          MU       TOL SCHEME    SEARCH     CAST")
        add(fmt_alpha("PAIR") + fmt_alpha("SLABFACE") + fmt_alpha("CUSHION")
            + fmt_real(geo.v("interface", "contact_friction"))
            + fmt_real(geo.v("interface", "contact_tolerance")) + fmt_alpha("MORTAR")
            + fmt_alpha("LINEAR") + fmt_int(1))
    add("BOUNDARY")
    add("*  N1   N2  INC   IX   IY")
    base = np.nonzero(np.abs(num.xy[:, 1] - geo.base) < 1e-9)[0] + 1
    assert np.all(np.diff(base) == 1)
    add(fmt_int(base[0]) + fmt_int(base[-1]) + fmt_int(1) + fmt_int(1) + fmt_int(1))
    add("RESERVOIR")
    add("* ELEM FACE COVER")
    for e, q in enumerate(num.quads, 1):
        if q.wet_face4:
            add(fmt_int(e) + fmt_int(4) + fmt_alpha(q.cover))
    add("GAUGES")
    add("* NODE NAME      LABEL")
    for node, name, elevation, ys, source in gauges:
        add(fmt_int(node) + fmt_alpha(name) + f"cushion face, El. {ys:.2f} m")
    add("STAGES")
    add("*KEYWORD GROUP/LEVEL NINC DATE      LABEL")
    for keyword, field2, ninc, date, label in stages:
        f2 = fmt_real(field2) if keyword == "WATER" else fmt_alpha(field2)
        add(fmt_alpha(keyword) + f2 + fmt_int(ninc) + fmt_alpha(date) + label[:45])
    add("END")
    text = "\n".join(lines) + "\n"
    for n, line in enumerate(lines, 1):
        if not line.startswith("*") and len(line) > 80:
            raise SystemExit(f"deck line {n} longer than 80 columns: {line}")
    Path(path).write_text(text)
    return info


def generate(r, geo=None, interface="bonded", face=None, face_band=6):
    """face: the face-resolved mesh (face_split): rows and slab in `face` divisions per x1
    row and slab element, the body's columns at the level r (the first face_band in
    `face`); None: the plain xr mesh."""
    geo = geo or Geometry()
    mesh = build_x1(geo, interface)
    assign_zones(geo, mesh)
    stages, notes = plan_history(geo, mesh)
    if geo.creep:
        stages = creep_history(geo, stages)
        notes = notes + creep_notes(geo)
    if face is not None:
        fine = refine(mesh, r, face_split(r, face, face_band))
        notes = notes + [f"face-resolved mesh (--face {face} --face-band {face_band}): every"
                         f" x1 row and slab element in {face} along the slope, the first"
                         f" {face_band} body columns from the upstream face at x{face}, the"
                         f" other columns at x{r}"]
    else:
        fine = refine(mesh, r)
    if interface == "thin":
        # The layer is one element thick at every refinement: the INTERFACE cards make its
        # quads from the cushion and slab node pairs, so the refined layer goes.
        layer_keys = {k for q in fine.quads if q.kind == "thin" for k in q.nodes}
        fine.quads = [q for q in fine.quads if q.kind != "thin"]
        used = {k for q in fine.quads for k in q.nodes}
        fine.coords = {k: v for k, v in fine.coords.items() if k in used or k not in layer_keys}
    num = number(fine)
    if interface == "joint":
        num.pairs = interface_pairs(fine, num)
    elif interface == "thin":
        num.pairs = thin_pairs(geo, fine, num)
    else:
        num.pairs = []
    return geo, num, stages, notes


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--refine", type=int, default=None, choices=[1, 2, 4, 8],
                        help="mesh refinement (default 1)")
    parser.add_argument("--deck", help="write the cfrd deck here")
    parser.add_argument("--knee", action="store_true",
                        help=f"the settings at the knee of {KNEE_DOC} for --interface (the"
                             " geometry file's [knee]: mesh, increments per layer and slab"
                             " phase, water step) in place of --refine and [increments]")
    parser.add_argument("--all", action="store_true",
                        help="write inputs/tianshengqiao-x1.dat and -x2.dat (bonded), the"
                             " x1 joint, thin and contact decks, and the decks at the knee:"
                             " inputs/tianshengqiao.dat (bonded) and"
                             " inputs/tianshengqiao-x4-contact.dat")
    parser.add_argument("--interface", default="bonded", choices=list(INTERFACES),
                        help="slab-cushion interface: bonded (shared nodes), thin (thin-layer"
                             " quads), joint (Goodman joints on node pairs) or contact (the"
                             " slab meshed on its own, CONTACT cards)")
    parser.add_argument("--geometry", default=str(GEOMETRY))
    parser.add_argument("--solver", default="midpoint", choices=["midpoint", "newton"],
                        help="midpoint stiffness (the paper's) or Newton to 1e-10")
    parser.add_argument("--report", action="store_true", help="print the mesh quality")
    parser.add_argument("--slab-element", choices=["Q4", "Q4S"], default=None,
                        help="element type of the slab (default: Q4S for contact, Q4 else)")
    parser.add_argument("--rule", default="LOBATTO", choices=["LOBATTO", "GAUSS"],
                        help="integration rule of the joints (--interface joint)")
    parser.add_argument("--top-rows", type=int, default=None,
                        help="split the top row of slab phases I and II into this many mesh"
                             " rows (x1; refined with the rest)")
    parser.add_argument("--face", type=int, default=None, choices=[1, 2, 4, 8],
                        help="face-resolved mesh (issue 7 experiment): every body row and"
                             " the slab divided in FACE per x1 row and element, the body's"
                             " columns at the --refine level")
    parser.add_argument("--face-band", type=int, default=6,
                        help="with --face: the first N body columns from the upstream face"
                             " (1: IIA, 2: IIA and IIIA, more: IIIB columns of about 11.6 m"
                             " at x1; default 6, 54 m) divided in FACE too")
    parser.add_argument("--creep", action="store_true",
                        help="time-dependent rockfill deformation: a CREEP card for every"
                             " zone ([creep] of the geometry file), stage dates in days and"
                             " WAIT stages to [creep] wait_until (docs/tianshengqiao.md s. 9)")
    args = parser.parse_args(argv)
    geo = Geometry(args.geometry)
    geo.creep = args.creep
    if args.top_rows is not None:
        geo.top_rows = args.top_rows
    if args.knee and args.refine is not None:
        parser.error("--knee sets the mesh: leave out --refine")
    refine = args.refine or 1
    jobs = []
    if args.all:
        root = Path(__file__).resolve().parent.parent
        inputs = root / "inputs"
        jobs = [(r, inputs / f"tianshengqiao-x{r}.dat", "bonded", False) for r in (1, 2)]
        jobs += [(1, inputs / f"tianshengqiao-x1-{m}.dat", m, False) for m in ("joint", "thin",
                                                                               "contact")]
        jobs += [(None, root / deck, m, True) for m, deck in KNEE_DECKS.items()]
    elif args.deck:
        jobs = [(refine, Path(args.deck), args.interface, args.knee)]
    else:
        jobs = [(refine, None, args.interface, args.knee)]
    base = geo
    for r, path, interface, knee in jobs:
        geo = base
        if knee:
            r, geo = base.at_knee(interface)
        geo, num, stages, notes = generate(r, geo, interface, args.face, args.face_band)
        if path is not None:
            label = None if args.face is None else f"x{r} body, x{args.face} face"
            info = write_deck(geo, r, num, stages, notes, path, args.solver, interface,
                              args.rule, args.slab_element, label)
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
