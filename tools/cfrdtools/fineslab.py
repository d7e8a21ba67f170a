"""The hard cases of issue 20 (docs/robustness.md, docs/theory.md section 14): a slab much
finer than the body it rests on. The decks (fine-stick, fine-slip, fine-smooth*, cast-swap,
the incipient-slip variants) and their checks, for tools/hard_cases.py: friction per master
segment with the card's roles (ROLES ASIS) and the roles swapped (ROLES AUTO: the coarser
side carries the multipliers)."""
import os

import h5py
import numpy as np

from cfrdtools import results, runner
from cfrdtools.hardcase import (Deck, Derived, Run, balance_check, check, common, elastic,
                                finished, pressures)

# Slab on a cushion block, flat (liftoff, drawdown, mechanism): block 4 x 1 m (4 x 2 quads),
# slab 4 x 0.25 m (8 x 1 quads, non-matching 2 : 1), slab bottom = slave.
SLAB = (3.0e7, 0.2, 24.0)
CUSHION = (5.0e4, 0.3, 21.0)

# A stiff slab (32 Q4 along 4 m, the slave) on a soft foundation of 2 elements (the master):
# each master face under 16 slave faces, mu 0.5, 100 kPa on the slab (N = 400 kN/m).
FINE_MU, FINE_P, FINE_NX = 0.5, 100.0, 32


def fine_slave(title, faces=2, nx=FINE_NX, roles="ASIS"):
    """roles ASIS: the fine slab stays the slave (friction per master segment); AUTO: the
    roles are swapped, the foundation carries the multipliers (docs/theory.md section 14)."""
    d = Deck(title)
    d.materials = elastic(1, "foundation", *CUSHION[:2]) + elastic(2, "slab", *SLAB[:2])
    bg, be = d.rect(0.0, 0.0, 4.0, 1.0, faces, 1, 1, "BASE")
    sg, se = d.rect(0.0, 1.0, 4.0, 0.25, nx, 1, 2, "SLAB")
    d.fix(bg[0], 1, 1)
    d.loads[""] = pressures(se[0], FINE_P)
    d.contact = [f"&SURFACE, SLABBOT, {se[0][0]}, 1, {len(se[0]) - 1}, 1",
                 f"&SURFACE, BASETOP, {be[-1][0]}, 3, {len(be[-1]) - 1}, 1",
                 f"&PAIR, SLABBOT, BASETOP, {FINE_MU!r}, 0.0, MORTAR, LINEAR, 0, {roles}"]
    d.base_top, d.slab_faces = bg[-1], se[0]
    return d, sg


def case_fine_slave():
    """Friction with a slave 16 times finer than its master (issue 20): a stiff slab pressed
    on a soft foundation of two elements, then pushed along it by half the Coulomb force
    (it must stick: closed form T < mu N), or dragged 5 cm (it must slip with mu N); as
    given (ROLES ASIS: friction per master segment) and with the roles swapped (-swap)."""
    decks = {}
    for tag, roles in (("", "ASIS"), ("-swap", "AUTO")):
        swap = "" if roles == "ASIS" else ", roles swapped"
        stick, sg = fine_slave("hard case: fine slave on a coarse master, stick" + swap,
                               roles=roles)
        push = 0.5 * FINE_MU * FINE_P * 4.0 / len(sg[1])
        stick.loads["PUSH"] = [f"&FORCE, {sg[1][0]}, {sg[1][-1]}, 1, {push!r}, 0.0"]
        stick.stages = ["&LOAD, , 1, , pressed", "&LOAD, PUSH, 2, , pushed by mu N / 2"]
        slip, sg = fine_slave("hard case: fine slave on a coarse master, slip" + swap,
                              roles=roles)
        slip.fix([sg[0][0], sg[1][0]], 1, 0, ux=0.05)
        slip.stages = ["&LOAD, , 5, , pressed and dragged 5 cm"]
        decks.update({f"fine-stick{tag}.dat": stick, f"fine-slip{tag}.dat": slip})
    return decks


# The issue-20 pressure criterion where it is meaningful: a stiff slab of 16 faces (the
# fine-stick slab's) on a foundation of ONE element (16 slave faces per master face), one
# smooth piece (base fixed, sides on rollers, nothing staged), under a linearly varying
# pressure (100 kPa at x = 0 to 25 kPa at x = 4 m, the shape of water on a face).
SMOOTH_P, SMOOTH_NX = (100.0, 25.0), 16


def smooth_deck(mu, faces, nx, title=None, held=None, roles="ASIS"):
    """The fine-smooth slab (nx faces) on a foundation of `faces` elements (sides on rollers)
    under the linear load, friction mu (mu 0: the slab's bottom left node held horizontally,
    at ux = held if given)."""
    d, sg = fine_slave(title or f"hard case: fine slave, {faces}-face foundation, linear "
                       f"load, mu {mu}" + ("" if roles == "ASIS" else ", roles swapped"),
                       faces=faces, nx=nx, roles=roles)
    d.contact[-1] = d.contact[-1].replace(f"{FINE_MU!r}, 0.0, MORTAR", f"{mu!r}, 0.0, MORTAR")
    d.fix([d.base_top[0], d.base_top[-1]], 1, 0)        # the foundation's sides on rollers
    if mu == 0.0:
        d.fix([sg[0][0]], 1, 0, ux=held)
    p = [SMOOTH_P[0] + (SMOOTH_P[1] - SMOOTH_P[0]) * i / nx for i in range(nx + 1)]
    d.loads[""] = [f"&PRESSURE, {e}, 3, {p[i]!r}, {p[i + 1]!r}"
                   for i, e in enumerate(d.slab_faces)]
    d.stages = ["&LOAD, , 2, , pressed by 100-25 kPa"]
    return d, sg


def case_fine_smooth():
    """Pressures that do not alternate (issue 20): the fine slave on a coarse, smooth,
    one-piece foundation under a smoothly varying pressure, frictionless (the slab's bottom
    left node held horizontally: a mechanism otherwise, its reaction zero) and with friction
    (held by friction alone); and the friction case on a foundation of two elements
    (fine-smooth-two-faces, 32 slave faces), whose pressure departs from the line at the
    master node between them (reported, not asserted: docs/theory.md section 14); all with
    ROLES ASIS (friction per master segment), and the friction cases with the roles swapped
    (-swap: the foundation carries the multipliers)."""
    return {name: smooth_deck(mu, faces, faces * SMOOTH_NX, roles=roles)[0]
            for name, mu, faces, roles in
            (("fine-smooth.dat", 0.0, 1, "ASIS"), ("fine-smooth-friction.dat", FINE_MU, 1, "ASIS"),
             ("fine-smooth-two-faces.dat", FINE_MU, 2, "ASIS"),
             ("fine-smooth-friction-swap.dat", FINE_MU, 1, "AUTO"),
             ("fine-smooth-two-faces-swap.dat", FINE_MU, 2, "AUTO"))}


def case_cast_swap():
    """CAST with the roles swapped (issue 20): a foundation of two elements settles under its
    weight, then a slab of 32 faces is cast on it (FILL). The slab is 16 times finer, so the
    foundation carries the multipliers and the slab's nodes, now the master's, must be put on
    the settled face when placed (docs/theory.md section 14, "Roles"); without that they
    would float above it by the settlement and the slab, held by nothing else, would fall."""
    d = Deck("hard case: fine slab cast on a settled coarse foundation, roles swapped")
    d.materials = elastic(1, "foundation", *CUSHION) + elastic(2, "slab", *SLAB)
    bg, be = d.rect(0.0, 0.0, 4.0, 1.0, 2, 1, 1, "BASE")
    sg, se = d.rect(0.0, 1.0, 4.0, 0.25, FINE_NX, 1, 2, "SLAB")
    d.fix(bg[0], 1, 1)
    d.fix([bg[1][0], bg[1][-1]], 1, 0)                 # the foundation's sides on rollers
    d.contact = [f"&SURFACE, SLABBOT, {se[0][0]}, 1, {len(se[0]) - 1}, 1",
                 f"&SURFACE, BASETOP, {be[-1][0]}, 3, {len(be[-1]) - 1}, 1",
                 f"&PAIR, SLABBOT, BASETOP, {FINE_MU!r}, 0.0, MORTAR, LINEAR, 1"]
    d.stages = ["&FILL, BASE, 1, , foundation settles", "&FILL, SLAB, 2, , slab cast on it"]
    return {"cast-swap.dat": d}


def case_incipient_newton():
    """incipient-slip.dat (the Tianshengqiao-I fine slab, 64 / 64 / 32 slave faces per phase
    on the x1 body, midpoint) solved by Newton to 1e-10 (the CONTROL line of
    `tools/tianshengqiao.py --solver newton`), so that its balance can be checked."""
    control = " 1133  920    6    1   101.325      9.81KN-M          0    1\n"
    pair = "PAIR      SLABFACE  CUSHION        0.577     0.001MORTAR    LINEAR        1\n"
    return {"incipient-slip-newton.dat": Derived(
        "incipient-slip.dat", "* incipient-slip.dat with Newton to 1e-10 (written by "
        "tools/hard_cases.py --write, issue 20)\n",
        [(control, control[:-2] + "31.0000E-10   30\n")]),
        "incipient-slip-asis.dat": Derived(
        "incipient-slip.dat", "* incipient-slip.dat with ROLES ASIS: the fine slab stays the "
        "slave, friction per master segment (written by tools/hard_cases.py --write)\n",
        [(pair, pair[:-1] + " ASIS\n")]),
        "incipient-slip-rpim.dat": Derived(
        "incipient-slip.dat", "* incipient-slip.dat with SEARCH RPIM: the roles swapped, the "
        "curve runs through the slab's nodes (written by tools/hard_cases.py --write)\n",
        [(pair, pair.replace("LINEAR", "RPIM  "))])}


def shear_alternation(stage):
    """Sign changes of the shear traction between adjacent slave nodes of a surface (its
    group, in the order of s) that are both closed and loaded (p above 1e-3 of the largest
    pressure, |q| above 1e-3 of the largest shear), and the number of such adjacent pairs:
    tractions that alternate from node to node change sign at about every pair; one sign per
    master segment (docs/theory.md section 14) changes it at most where a closed run of slave
    nodes passes a master node."""
    st, p, q, s, grp = (stage["c_status"], -stage["c_sigma_n"], stage["c_tau"], stage["c_s"],
                        stage["c_group"])
    loaded = (st != 0) & (p > 1e-3 * max(p.max(), 1e-300)) & \
        (np.abs(q) > 1e-3 * max(np.abs(q).max(), 1e-300))
    changes = pairs = 0
    for g in np.unique(grp):
        idx = np.where(grp == g)[0]
        idx = idx[np.argsort(s[idx])]
        for a, b in zip(idx[:-1], idx[1:]):
            if loaded[a] and loaded[b]:
                pairs += 1
                changes += int(q[a] * q[b] < 0)
    return changes, pairs


def notch_free_curvature(stage):
    """The issue's pressure measure on the notch-free parts: max |p_(i-1) - 2 p_i + p_(i+1)|
    over the largest pressure, at nodes whose two neighbours on either side are closed."""
    st, p, s, grp = stage["c_status"], -stage["c_sigma_n"], stage["c_s"], stage["c_group"]
    worst = 0.0
    for g in np.unique(grp):
        idx = np.where(grp == g)[0]
        idx = idx[np.argsort(s[idx])]
        for k in range(2, len(idx) - 2):
            if all(st[idx[k + d]] != 0 for d in (-2, -1, 0, 1, 2)):
                worst = max(worst, abs(p[idx[k - 1]] - 2 * p[idx[k]] + p[idx[k + 1]]))
    return worst / max(p.max(), 1e-300)


def multiplier_curvature(stage):
    """The same measure at the multipliers' own nodes (the slave's, from the restart state:
    the cushion's where the roles were swapped), in order along the surface (the direction of
    the nodes' largest spread), at nodes whose two neighbours on either side are closed."""
    if "m_p" not in stage:
        return 0.0
    on = np.where((stage["m_supported"] == 1) & (stage["m_node"] > 0))[0]
    if len(on) < 5:
        return 0.0
    xy = np.column_stack([stage["m_x"][on], stage["m_y"][on]])
    axis = np.linalg.svd(xy - xy.mean(axis=0))[2][0]
    o = on[np.argsort(xy @ axis)]
    p, st = stage["m_p"][o], stage["m_status"][o]
    worst = max((abs(p[k - 1] - 2 * p[k] + p[k + 1]) for k in range(2, len(o) - 2)
                 if all(st[k + d] != 0 for d in (-2, -1, 0, 1, 2))), default=0.0)
    return worst / max(p.max(), 1e-300)


def node_coulomb(stage, mu):
    """The largest excess of |q| over mu p at a closed multiplier node, over mu times the
    stage's largest pressure (Coulomb per node: <= 0 up to round-off)."""
    if "m_p" not in stage or not np.any(stage["m_status"] != 0):
        return 0.0
    closed = stage["m_status"] != 0
    return float(np.max(np.abs(stage["m_q"][closed]) - mu * stage["m_p"][closed]) /
                 (mu * max(stage["m_p"].max(), 1e-300)))


def fine_slab(cfrd, work, name, deck, balance, swapped=True):
    """The Tianshengqiao-I fine-slab deck: all 45 stages, no NaN, the shear tractions not
    alternating (shear_alternation at most 0.1 at every stage), with Newton the balance.
    With the roles swapped (docs/theory.md section 14): the issue's criterion on the
    reported pressures along the slab (0.05), Coulomb per node at the multipliers' nodes
    (1e-9 of mu max p), and the second difference at the multipliers' nodes (reported)."""
    r = Run(cfrd, work, deck)
    if not common(name, r, 0):
        return r, "did not run"
    check(name + "/stages", len(r.stages) == 45, f"{len(r.stages)} stages of 45 completed")
    worst, at, changes, pairs = 0.0, 0, 0, 0
    for k, stage in enumerate(r.stages, 1):
        c, n = shear_alternation(stage)
        if n and c / n >= worst:
            worst, at, changes, pairs = c / n, k, c, n
    check(name + "/shear-alternation", worst <= 0.1, f"sign changes of the shear traction "
          f"between neighbouring loaded closed slave nodes: at most {changes} of {pairs} "
          f"(stage {at}; 0.1; alternating tractions give about 1)")
    curvature = max(notch_free_curvature(stage) for stage in r.stages)
    outcome = f"completes 45 stages; shear sign changes {changes} of {pairs} neighbours " \
              f"(stage {at}); pressure second difference on notch-free parts up to " \
              f"{curvature:.3f} of the peak"
    if not swapped:
        return r, outcome + " (reported, not asserted)" + (balance_check(name, r) if balance
                                                            else "")
    listing = open(r.deck[:-4] + ".out").read()
    check(name + "/listing", "roles swapped: the card's slave SLABFACE is much finer than its "
          "master CUSHION" in listing, "the listing names the pair whose roles were swapped "
          "and why (docs/theory.md section 14)")
    check(name + "/second-difference", curvature <= 0.05, f"|p_(i-1) - 2 p_i + p_(i+1)| "
          f"along the slab at nodes with two closed neighbours on either side, the largest "
          f"over the stages: {curvature:.4f} of the stage's peak (issue 20: 0.05)")
    excess = max(node_coulomb(stage, 0.577) for stage in r.stages)
    check(name + "/coulomb", excess <= 1e-9, f"Coulomb per multiplier node: the largest "
          f"|q| - mu p at a closed node {excess:.1e} of mu max p (1e-9)")
    at_nodes = max(multiplier_curvature(stage) for stage in r.stages)
    return r, outcome + f" (0.05); at the multipliers' (cushion) nodes {at_nodes:.3f} " \
        f"(reported); Coulomb per node {excess:.0e}" + (balance_check(name, r) if balance else "")


def check_incipient_slip(cfrd, work):
    return fine_slab(cfrd, work, "incipient-slip", "incipient-slip.dat", False)


def check_incipient_newton(cfrd, work):
    return fine_slab(cfrd, work, "incipient-newton", "incipient-slip-newton.dat", True)


def check_incipient_rpim(cfrd, work):
    return fine_slab(cfrd, work, "incipient-rpim", "incipient-slip-rpim.dat", False)


def check_incipient_asis(cfrd, work):
    return fine_slab(cfrd, work, "incipient-asis", "incipient-slip-asis.dat", False, False)


def check_fine_stick(cfrd, work, name="fine-stick"):
    r, s = finished(cfrd, work, name, name + ".dat")
    if s is None:
        return r, "did not run"
    closed, slipping = int(np.count_nonzero(s["c_status"])), int(np.sum(s["c_status"] == 2))
    push = 0.5 * FINE_MU * FINE_P * 4.0
    check(name + "/stick", slipping == 0 and closed >= 30, f"pushed by T = mu N / 2 = "
          f"{push:.0f} kN/m: {closed} of 33 slave nodes closed, {slipping} slip (closed form, "
          f"Coulomb on the slab: T < mu N = {2 * push:.0f} kN/m, it sticks; without friction "
          f"per master segment 15 nodes slip)")
    fx = float(s["reaction"][:3, 0].sum())           # the foundation's base
    e = abs(fx + push) / push
    check(name + "/statics", e <= 1e-9, f"the foundation's horizontal reaction {fx:.6f} "
          f"kN/m against -T (statics): {e:.1e} (1e-9)")
    changes, pairs = shear_alternation(s)
    return r, f"converged; {slipping} of {closed} closed nodes slip (T = mu N / 2), " \
              f"shear sign changes {changes} of {pairs}"


def check_fine_slip(cfrd, work, name="fine-slip"):
    r, s = finished(cfrd, work, name, name + ".dat")
    if s is None:
        return r, "did not run"
    nb = 6                                        # foundation nodes first, then the slab's
    fx = float(s["reaction"][nb, 0] + s["reaction"][nb + FINE_NX + 1, 0])
    expect = FINE_MU * FINE_P * 4.0
    e = abs(fx - expect) / expect
    # the deformed foundation's faces tilt the contact normals (as long-slip)
    tilt = float(np.max(np.abs(s["displacement"][:nb]))) / (4.0 / 2)
    closed = s["c_status"] != 0
    check(name + "/friction", e <= tilt and np.all(s["c_status"][closed] == 2) and
          np.all(s["c_slip"][closed] > 0.0), f"drag force {fx:.4f} kN/m against mu N = "
          f"{expect:.0f} (Coulomb, closed form): {e:.1e} (the foundation's tilt, max |u| / "
          f"2 m = {tilt:.1e}); {int(closed.sum())} closed slave nodes, all slipping forward")
    return r, f"converged; drag force {e:.0e} from mu N, every closed node slips"


def surface_profile(stage):
    """The slave nodes of a one-surface pair in order along s: pressure p, shear q, status,
    and the node's tributary length w (half its faces, reference coordinates)."""
    o = np.argsort(stage["c_s"])
    xy = np.column_stack([stage["c_x"], stage["c_y"]])[o]
    faces = np.linalg.norm(np.diff(xy, axis=0), axis=1)
    w = np.zeros(len(o))
    w[:-1] += faces / 2
    w[1:] += faces / 2
    return -stage["c_sigma_n"][o], stage["c_tau"][o], stage["c_status"][o], w, o


def last_contact(h5):
    """The contact datasets (c_ keys) and the reactions of the last stage of a results file."""
    with h5py.File(h5, "r") as f:
        g = list(results.stages(f))[-1]
        stage = {"c_" + k: g["contact"][k][...] for k in g["contact"]}
        stage["reaction"] = g["reaction"][...]
    return stage


def smooth_two_faces_sheared(cfrd, work, s, at_axis, faces=2):
    """The shear of the frictional fine-smooth-two-faces run s as loads on the same deck
    frictionless (rollers, the slab's bottom left node held horizontally where the run put
    it, so that the couplings of the second increment are built at the same geometry): on the slab's
    bottom nodes w_j q_j, on the foundation's top nodes -sum_j N_k(x_j) w_j q_j (the mortar
    matrix M_jk of the slave's dual multipliers: every slave face lies inside one master
    face, where N_k is linear; per master segment q_j = beta_j q_G, docs/theory.md section
    14); with at_axis, half of each slab force on its bottom node and half on the top node
    above it, the same forces without their moment about the slab's axis. Returns the
    pressure profile along the slab and the held node's horizontal reaction."""
    p, q, st, w, o = surface_profile(s)
    x, nodes = s["c_x"][o], s["c_node"][o]
    d, sg = smooth_deck(0.0, faces, len(nodes) - 1, "fine-smooth-two-faces, frictionless, "
                        "sheared" + (" at the slab's axis" if at_axis else ""),
                        held=float(s["displacement"][nodes[0] - 1, 0]))
    above = dict(zip(sg[0], sg[1]))
    for node, f in zip(nodes, w * q):
        share = [(int(node), float(f) / 2), (above[int(node)], float(f) / 2)] if at_axis \
            else [(int(node), float(f))]
        d.loads[""] += [f"&FORCE, {n}, {n}, 1, {fx!r}, 0.0" for n, fx in share]
    xm, h = np.linspace(0.0, 4.0, faces + 1), 4.0 / faces   # the foundation's top nodes
    for k, node in enumerate(d.base_top):
        hat = np.clip(1.0 - np.abs(x - xm[k]) / h, 0.0, 1.0)
        d.loads[""].append(f"&FORCE, {node}, {node}, 1, {float(-np.sum(hat * w * q))!r}, 0.0")
    stage = last_contact(runner.run_text(cfrd, os.path.join(
        work, "fine-smooth-two-faces-sheared" + ("-axis" if at_axis else "") + ".dat"), d.text()))
    return surface_profile(stage)[0], float(stage["reaction"][sg[0][0] - 1, 0])


def check_fine_smooth(cfrd, work):
    """fine-smooth (frictionless) and fine-smooth-friction: the issue's criterion, the second
    difference of the pressure at every interior slave node under 5 % of the peak, and
    statics: the foundation's base carries the applied load, the total normal force of the
    contact is that load (up to the geometry's update), no closed node slips."""
    out = []
    load = (SMOOTH_P[0] + SMOOTH_P[1]) / 2 * 4.0               # closed form: 250 kN/m
    for name, faces in (("fine-smooth", 1), ("fine-smooth-friction", 1),
                        ("fine-smooth-two-faces", 2), ("fine-smooth-friction-swap", 1),
                        ("fine-smooth-two-faces-swap", 2)):
        r, s = finished(cfrd, work, name, name + ".dat")
        if s is None:
            return r, "did not run"
        p, q, st, w, o = surface_profile(s)
        d2 = np.abs(p[:-2] - 2 * p[1:-1] + p[2:]) / p.max()
        swapped = name.endswith("-swap")
        if swapped:
            # the multipliers at the foundation's nodes, the slab's reported by interpolation
            excess = node_coulomb(s, FINE_MU)
            check(name + "/second-difference", d2.max() <= 0.05 and np.all(st != 0) and
                  excess <= 1e-9, f"roles swapped (the foundation carries the multipliers): "
                  f"|p_(i-1) - 2 p_i + p_(i+1)| along the slab at its {len(d2)} interior nodes "
                  f"up to {d2.max():.4f} of the peak {p.max():.2f} kPa (issue 20: 0.05); "
                  f"{int(np.sum(st != 0))} of {len(st)} closed; Coulomb per multiplier node "
                  f"{excess:.1e} of mu max p (1e-9)")
        elif faces == 1:
            check(name + "/second-difference", d2.max() <= 0.05 and np.all(st != 0),
                  f"|p_(i-1) - 2 p_i + p_(i+1)| at the {len(d2)} interior slave nodes up to "
                  f"{d2.max():.4f} of the peak {p.max():.2f} kPa (issue 20: 0.05; the load is "
                  f"linear, the master straight); {int(np.sum(st != 0))} of {len(st)} closed")
        fy = float(s["reaction"][:faces + 1, 1].sum())     # the foundation's base nodes
        e_base = abs(fy - load) / load
        # the couplings are built at the deformed coordinates of the increment's start:
        # lengths and normals move by the slave faces' strain and rotation (squared)
        u = s["displacement"][s["c_node"][o] - 1]
        du = np.diff(u, axis=0) / np.diff(s["c_x"][o])[:, None]
        bound = float(np.max(np.abs(du[:, 0])) + np.max(du[:, 1] ** 2))
        e_n = abs(float(np.sum(w * p)) - load) / load
        slips = int(np.sum(st == 2)) if "friction" in name else 0
        check(name + "/statics", e_base <= 1e-9 and e_n <= bound and slips == 0,
              f"foundation base reaction {fy:.9f} kN/m against the load (100 + 25) / 2 x 4 m = "
              f"{load:.0f} (statics): {e_base:.1e} (1e-9); total normal force sum w_j p_j "
              f"against it {e_n:.1e} (the faces' strain + rotation^2, {bound:.1e})"
              + (f"; {slips} closed nodes slip (no tangential load: stick)"
                 if "friction" in name else ""))
        if faces > 1 and not swapped:
            # the pressure peaks at the master node (reported): why, by superposition
            ps, _ = smooth_two_faces_sheared(cfrd, work, s, False)
            e_sup = float(np.max(np.abs(ps - p)) / p.max())
            check(name + "/superposition", e_sup <= 1e-4, f"the same deck frictionless, its "
                  f"slab and foundation loaded by the run's shear forces: pressures against "
                  f"the run's {e_sup:.1e} of the peak (1e-4: a linear problem with the same "
                  f"active set, but for the couplings built at the deformed geometry, strains "
                  f"of {bound:.0e})")
            pa, held = smooth_two_faces_sheared(cfrd, work, s, True)
            da = np.abs(pa[:-2] - 2 * pa[1:-1] + pa[2:]) / pa.max()
            check(name + "/without-moment", da.max() <= 0.05 and abs(held) <= 1e-6 * load,
                  f"the same shear forces at the slab's axis (half on each of its nodes, no "
                  f"moment): second difference {da.max():.4f} of the peak (issue 20: 0.05) "
                  f"against {d2.max():.4f} with the shear on the slab's underside, where the "
                  f"contact puts it (reported, not asserted: the slab, bent by the shear's "
                  f"moment, bears on the coarse master's node); the held node's reaction "
                  f"{held:.1e} kN/m (1e-6 of the load: the shear is self-equilibrated)")
        at = float(s["c_x"][o][1 + int(np.argmax(d2))])
        out.append(f"{name}: second difference {d2.max():.3f} of the peak (x {at:g} m"
                   + (", the master node: reported)" if faces > 1 and not swapped else ")")
                   + f", normal force {e_n:.0e}")
    return r, "converged; " + "; ".join(out)


def check_cast_swap(cfrd, work):
    r, s = finished(cfrd, work, "cast-swap", "cast-swap.dat")
    if s is None:
        return r, "did not run"
    p, q, st, w, o = surface_profile(s)
    weight = SLAB[2] * 0.25 * 4.0                       # 24 kN/m
    total = CUSHION[2] * 1.0 * 4.0 + weight
    fy = float(s["reaction"][:3, 1].sum())              # the foundation's base nodes
    e_base = abs(fy - total) / total
    e_n = abs(float(np.sum(w * p)) - weight) / weight
    settled = float(-np.min(s["displacement"][3:6, 1]))  # the foundation's top, slab included
    # the couplings are built at the geometry of the increment's start: the face moves by
    # the increment's displacement, at most the settlement, over its 4 m (as drawdown's)
    bound = settled / 4.0
    gap = float(np.max(np.abs(s["c_gap"])))
    check("cast-swap/cast", np.all(st != 0) and int(np.sum(st == 2)) == 0 and e_base <= 1e-9
          and e_n <= bound, f"{int(np.sum(st != 0))} of {len(st)} slab nodes closed, "
          f"{int(np.sum(st == 2))} slip (cast on the settled face, no tangential load); the base "
          f"reaction {fy:.9f} kN/m against the weights 84 + 24 = {total:.0f} (statics): "
          f"{e_base:.1e} (1e-9); the contact's normal force sum w p against the slab's weight "
          f"{weight:.0f} kN/m: {e_n:.1e} (the geometry's update, settlement / 4 m = {bound:.1e})")
    return r, f"converged; all {len(st)} slab nodes closed, none slips; pressure " \
              f"{p.min():.4f}-{p.max():.4f} kPa against gamma t = {weight / 4.0:.0f} (the " \
              f"foundation in 1-D compression; reported); contact force " \
              f"{e_n:.0e} from the slab's weight; largest |gap| {gap:.1e} m (the face settled " \
              f"{settled:.1e} m)"


def master_refinement(cfrd, work):
    """Issue 20's criterion on the fine-smooth deck with friction as the foundation is
    refined (docs/theory.md section 14; measured, not asserted): the slab of 32 faces on 1-32
    master faces, and 16 slave faces per master face on 4-16 master faces. Per run: the
    largest |second difference| d of the pressure over the peak and where; d h / 2 / L (h the
    slave face, L = 4 m), the force of a one-node spike of that d per p_max L; the same d
    frictionless; the sign changes of the second difference between adjacent interior nodes
    where both exceed 1e-3 of the peak (pressures alternating from node to node change it at
    every pair) and how many lie within two slave faces of a master node."""
    rows = ["| master faces | slave faces | law | d (x m) | d h / 2L | d frictionless | "
            "sign changes (near a master node) |", "|---" * 7 + "|"]
    for faces, nx in [(f, 32) for f in (1, 2, 4, 8, 16, 32)] + \
            [(f, 16 * f) for f in (4, 8, 16)]:
        out = []
        for mu in (FINE_MU, 0.0):
            d, _ = smooth_deck(mu, faces, nx)
            p, _, st, _, o = surface_profile(last_contact(runner.run_text(
                cfrd, os.path.join(work, f"refine-{faces}-{nx}-{mu}.dat"), d.text())))
            out.append(((p[:-2] - 2 * p[1:-1] + p[2:]) / p.max(), int(np.sum(st == 0))))
        (d2, opened), (d0, _) = out
        both = (np.abs(d2[:-1]) > 1e-3) & (np.abs(d2[1:]) > 1e-3)
        change = np.where((d2[:-1] * d2[1:] < 0) & both)[0] + 1     # slave nodes i, i + 1
        r = nx // faces
        at_master = [i for i in change if min(i % r, r - i % r, (i + 1) % r,
                                              r - (i + 1) % r) <= 2]
        k = int(np.argmax(np.abs(d2)))
        rows.append(f"| {faces} | {nx} | {'per master segment' if nx >= 3 * faces else 'per node'}"
                    f" | {np.abs(d2).max():.3f} ({4.0 * (k + 1) / nx:g}) | "
                    f"{np.abs(d2).max() * 4.0 / nx / 8.0:.4f} | {np.abs(d0).max():.4f} | "
                    f"{len(change)} of {int(both.sum())} ({len(at_master)}) |"
                    + (f" {opened} open" if opened else ""))
    return rows
