"""The plinth and the perimetric joint of the Tianshengqiao-I decks (tools/tianshengqiao.py
--plinth; issue 22, docs/tianshengqiao.md section 10).

The slab's end at the toe is cut normal to the face (its toe ring runs from the inner toe
node up the face normal) and rests on a concrete plinth through a PJOINT joint. The plinth
lies on rock excavated `thickness` below the base: quads one element thick at every
refinement (each has its bottom side on the fixed rock), one under each slab layer at the
joint and `upstream_elements` more upstream, their top level with the slab's outer toe.
The plinth's nodes at the joint coincide with the slab's toe nodes; the pairs (plinth
node, slab node) run from the face inwards, so that the slab lies on the left of the line
(the joint's n points up the slope into the slab, t into the dam)."""

import numpy as np

PLINTH_GROUP = "PLINTH"
PJOINT_LINE = 2


def sources(geo):
    """(key, value, source, note) of the [plinth] values, for the deck header."""
    return [(f"plinth.{k}", i["value"], i["source"], i.get("note", ""))
            for k, i in geo.raw["plinth"].items()]


def toe_ring_point(geo, inner, layer, layers):
    """The slab's toe-ring node `layer` (0 = inner) on the face normal through the inner
    toe node `inner` (x, y)."""
    factor = np.hypot(1.0, geo.su)
    t = geo.slab_thickness(inner[1]) * layer / layers
    return (inner[0] - t / factor, inner[1] + t * geo.su / factor)


def add_plinth(geo, mesh, ring, quad_type):
    """Plinth quads (kind 'plinth', material 0: the writer gives the slab's concrete) under
    the slab's toe ring `ring` (node keys, inner first; band -1) and upstream of it (band
    -2), added to mesh."""
    hp, width = geo.v("plinth", "thickness"), geo.v("plinth", "width")
    nup = geo.v("plinth", "upstream_elements")
    rock = geo.base - hp
    top = [mesh.point(("pt", k), mesh.coords[key]) for k, key in enumerate(ring)]
    bottom = [mesh.point(("pb", k), (mesh.coords[key][0], rock)) for k, key in enumerate(ring)]
    x_out, y_out = mesh.coords[ring[-1]]
    for k in range(len(ring) - 1):      # under the joint: (b k+1, b k, t k, t k+1)
        mesh.quads.append(quad_type((bottom[k + 1], bottom[k], top[k], top[k + 1]), "plinth",
                                    -1, group=PLINTH_GROUP))
    left_b, left_t = bottom[-1], top[-1]
    for j in range(1, nup + 1):          # upstream, right to left
        x = x_out - width * j / nup
        b = mesh.point(("pb", "u", j), (x, rock))
        t = mesh.point(("pt", "u", j), (x, y_out))
        mesh.quads.append(quad_type((b, left_b, left_t, t), "plinth", -2,
                                    group=PLINTH_GROUP))
        left_b, left_t = b, t


def split(base, r, through):
    """The refinement of a plinth quad: `through` along its first side (the slab layer's
    divisions under the joint, r upstream), one element thick; other quads as `base`."""
    def f(q):
        if q.kind == "plinth":
            return (through if q.band == -1 else r), 1
        return base(q) if base else (r, r)
    return f


def joint_pairs(num, geo):
    """(plinth node, slab node) numbers at the joint, from the face inwards: every plinth
    node above the rock that coincides with a slab node, by x ascending."""
    nodes = {kind: {int(n) for c, q in zip(num.conn, num.quads) if q.kind == kind for n in c}
             for kind in ("plinth", "slab")}
    at = {tuple(np.round(num.xy[n - 1], 6)): n for n in nodes["slab"]}
    rock = geo.base - geo.v("plinth", "thickness")
    pairs = [(p, at[tuple(np.round(num.xy[p - 1], 6))]) for p in nodes["plinth"]
             if num.xy[p - 1, 1] > rock + 1e-6 and tuple(np.round(num.xy[p - 1], 6)) in at]
    return sorted(pairs, key=lambda pair: num.xy[pair[0] - 1, 0])


def fixed_nodes(num, geo):
    """The nodes on rock: the plinth's bottom, and the body's base nodes that are not the
    slab's (a bonded slab's inner toe node rests on the plinth)."""
    kinds = {}
    for c, q in zip(num.conn, num.quads):
        for n in c:
            kinds.setdefault(int(n), set()).add(q.kind)
    rock = geo.base - geo.v("plinth", "thickness")
    return sorted(n for n, k in kinds.items()
                  if abs(num.xy[n - 1, 1] - rock) < 1e-9 and "plinth" in k
                  or abs(num.xy[n - 1, 1] - geo.base) < 1e-9 and "body" in k and "slab" not in k)


def runs(numbers):
    """Consecutive runs (first, last) of sorted node numbers."""
    out = []
    for n in numbers:
        if out and n == out[-1][1] + 1:
            out[-1][1] = n
        else:
            out.append([n, n])
    return [tuple(r) for r in out]
