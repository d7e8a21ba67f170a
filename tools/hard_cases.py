#!/usr/bin/env python3
"""Hard cases stay stable (issue 9, section 2; docs/robustness.md): small decks in
test/hard_cases/, each run by cfrd and checked against a reference named in its check, or
expected to stop with the full diagnostic (stage, increment, iteration, residual, the node at
fault), exit status 1, no NaN or Inf in any output and the results of an earlier run intact.

  python3 tools/hard_cases.py --write                 (re-make the decks in test/hard_cases/)
  python3 tools/hard_cases.py --cfrd bin/cfrd [--workdir DIR] [--only NAME] [--table]

The fine-slab cases of issue 20 (a slab much finer than its body) live in
tools/cfrdtools/fineslab.py. --table prints the rows of the table in docs/robustness.md (outcome, cutbacks, contact
iterations per case); --refinement, instead of the checks, the table of docs/theory.md section
14 (fine-smooth-two-faces on finer foundations, measured).
"""
import math
import os
import sys
import tomllib

import numpy as np

from cfrdtools import runner
from cfrdtools.checks import parser
from cfrdtools.hardcase import (DECKS, Deck, Generated, Run, balance_check, check, common,
                                diagnostic, elastic, oedometric, pressures, rel)
from cfrdtools.fineslab import (CUSHION, SLAB, case_cast_swap, case_fine_slave,
                                case_fine_smooth, case_incipient_newton, check_cast_swap,
                                check_fine_slip, check_fine_smooth, check_fine_stick,
                                check_incipient_asis, check_incipient_newton,
                                check_incipient_rpim, check_incipient_slip, master_refinement)

# Confined column (all ux = 0): cushion 2 m (E 1e4), interface, slab 0.5 m, 1000 kPa on top.
COLUMN_E, COLUMN_NU, COLUMN_P = 1.0e4, 0.3, 1000.0
EB = ["&{k}, EB, rockfill", "&21.0, 1000.0, 0.35, 0.85, 500.0, 0.2, 2000.0", "&50.0, 8.0, 0.0"]


def slab_on_block(title, mu, clamp=True, gravity=None):
    d = Deck(title)
    d.materials = elastic(1, "cushion", *CUSHION) + elastic(2, "slab", *SLAB)
    bg, be = d.rect(0.0, 0.0, 4.0, 1.0, 4, 2, 1, "CUSHION")
    sg, se = d.rect(0.0, 1.0, 4.0, 0.25, 8, 1, 2, "SLAB")
    d.fix(bg[0], 1, 1)
    if clamp:
        d.fix([sg[0][0], sg[1][0]], 1, 1)
    d.contact = [f"&SURFACE, SLABBOT, {se[0][0]}, 1, {len(se[0]) - 1}, 1",
                 f"&SURFACE, BLOCKTOP, {be[-1][0]}, 3, {len(be[-1]) - 1}, 1",
                 f"&PAIR, SLABBOT, BLOCKTOP, {mu!r}, 0.0, MORTAR"]
    if gravity:
        d.loads[""].append(f"&GRAVITY, ALL, {gravity[0]!r}, {gravity[1]!r}")
    return d, se


def case_liftoff():
    """Full lift-off of the slab and re-closure, frictionless (path-independent); the
    reference: the slab alone (no block, no contact) under the net uplift."""
    d, se = slab_on_block("hard case: slab lift-off and re-closure", 0.0)
    d.loads.update({"": pressures(se[0], 100.0), "UP": pressures(se[0], -200.0),
                    "DOWN": pressures(se[0], 200.0)})
    d.stages = ["&LOAD, , 2, , pressed", "&LOAD, UP, 4, , lifted off",
                "&LOAD, DOWN, 4, , pressed again"]
    a = Deck("hard case: the lifted slab alone (reference of liftoff)")
    a.materials = elastic(1, "slab", *SLAB)
    ag, ae = a.rect(0.0, 1.0, 4.0, 0.25, 8, 1, 1, "SLAB")
    a.fix([ag[0][0], ag[1][0]], 1, 1)
    a.loads[""] = pressures(ae[0], -100.0)
    return {"liftoff.dat": d, "liftoff-slab-alone.dat": a}


def case_long_slip():
    """A block dragged 3 m (3 master element lengths) along a base, pressed by 100 kPa."""
    d = Deck("hard case: slip of three element lengths")
    d.materials = elastic(1, "base", 1.0e5, 0.3) + elastic(2, "block", 1.0e5, 0.3)
    bg, be = d.rect(0.0, 0.0, 8.0, 1.0, 8, 1, 1, "BASE")
    kg, ke = d.rect(1.0, 1.0, 2.0, 1.0, 4, 2, 2, "BLOCK")
    d.fix(bg[0], 1, 1)
    d.fix(kg[-1], 1, 0, ux=3.0)
    d.loads[""] = pressures(ke[-1], 100.0)
    d.contact = [f"&SURFACE, BLOCKBOT, {ke[0][0]}, 1, {len(ke[0]) - 1}, 1",
                 f"&SURFACE, BASETOP, {be[0][0]}, 3, {len(be[0]) - 1}, 1",
                 "&PAIR, BLOCKBOT, BASETOP, 0.4, 0.0, MORTAR"]
    d.stages = ["&LOAD, , 30, , dragged 3 m"]
    return {"long-slip.dat": d}


def column(title, interface, thickness=0.0):
    d = Deck(title)
    kn = 1.0e6 * COLUMN_E
    d.materials = (elastic(1, "cushion", COLUMN_E, COLUMN_NU)
                   + elastic(2, "slab", 1.0e5 * COLUMN_E, 0.2))
    d.materials += ["&3, GOODMAN, joint kn = 1e6 E_cushion", f"&{kn!r}, {kn!r}, 1000.0, 0.5, "
                    "0.8, 35.0"] if interface == "JOINT" else elastic(3, "thin layer", COLUMN_E,
                                                                      COLUMN_NU)
    cg, ce = d.rect(0.0, 0.0, 1.0, 2.0, 1, 2, 1, "CUSHION")
    sg, se = d.rect(0.0, 2.0 + thickness, 1.0, 0.5, 1, 1, 2, "SLAB")
    d.fix(cg[0], 1, 1)
    d.fix([n for row in cg[1:] + sg for n in row], 1, 0)
    d.loads[""] = pressures([se[0][0]], COLUMN_P)
    d.interface = [f"&1, {cg[-1][0]}, {sg[0][0]}, 1, 1, 1, 3, {interface}"]
    return d


def rockfill(title, control, materials, rows, groups):
    """A 6 m wide block of 3 x rows quads of the EB rockfill in fill groups, a pull at the
    crest (load set PULL)."""
    d = Deck(title)
    d.control, d.materials = control, materials
    grid, elems = d.rect(0.0, 0.0, 6.0, 2.0 * rows, 3, rows, 1, groups[0][0])
    for j, (group, mat) in enumerate(groups):
        for e in elems[j]:
            d.elems[e - 1] = d.elems[e - 1][:4] + (mat, group, "")
    d.fix(grid[0], 1, 1)
    d.loads["PULL"] = [f"&FORCE, {grid[-1][-1]}, , , 150.0, 0.0"]
    return d, grid


def case_rockfill():
    """Rockfill at zero confinement (each new top layer) and in tension (a pull at the
    crest), Newton to 1e-8."""
    d, _ = rockfill("hard case: rockfill at zero and tensile confinement",
                    "&, , , 1, 101.325, 9.81, KN-M, 0, 3, 1.0e-8, 30",
                    [c.format(k=1) for c in EB], 3, [(f"L{j}", 1) for j in (1, 2, 3)])
    d.stages = ["&FILL, L1, 2", "&FILL, L2, 2", "&FILL, L3, 2", "&LOAD, PULL, 4, , crest pull"]
    return {"rockfill-tension.dat": d}


def case_drawdown():
    """The reservoir raised 10 m over the slab and drawn down below it (frictionless: the
    elastic state returns)."""
    d, se = slab_on_block("hard case: reservoir filling and drawdown", 0.0, gravity=(0.0, -1.0))
    d.reservoir = [f"&{e}, 3" for e in se[0]]
    d.stages = ["&LOAD, , 1, , own weight", "&WATER, 11.25, 5, , filled 10 m over the slab",
                "&WATER, 0.5, 5, , drawn down below the slab"]
    return {"drawdown.dat": d}


def case_mechanism():
    """A frictionless slab held by nothing on an inclined gravity: it would slide away."""
    d, _ = slab_on_block("hard case: frictionless slab, a mechanism", 0.0, clamp=False,
                         gravity=(-0.5, -math.sqrt(0.75)))
    d.stages = ["&LOAD, , 2, , own weight"]
    return {"mechanism.dat": d}


def case_no_converge():
    """Newton allowed one iteration per increment (MAXIT 1) to 1e-12, well above round-off,
    when a pull puts the top of a rockfill layer in tension (the E-B law's kinks: the
    stress-level cap, the sigma3 floor): one iteration is not enough, whatever the cutback,
    so the run stops on purpose. (A tolerance below round-off no longer does: the
    convergence test accepts the round-off of the assembled forces, issue 20.)"""
    d, grid = rockfill("hard case: cannot converge on purpose",
                       "&, , , 1, 101.325, 9.81, KN-M, 0, 3, 1.0e-12, 1",
                       elastic(1, "rock", 2.0e6, 0.25, 24.0) + [c.format(k=2) for c in EB], 2,
                       [("ROCK", 1), ("FILL", 2)])
    d.loads[""] = [f"&FORCE, {grid[1][-1]}, , , 0.0, -10.0"]
    d.stages = ["&LOAD, , 1, , rock loaded (linear)", "&FILL, FILL, 1, , rockfill layer",
                "&LOAD, PULL, 1, , crest pull"]
    return {"no-converge.dat": d}


def case_rpim_bend():
    """A slab against the face of a body placed in two layers (issue 20): the second layer's
    nodes start at their design place while the first layer's top has settled, so the face in
    x + u bends at the layer boundary, however fine the mesh. The RPIM curve must not run
    across such a bend (docs/theory.md section 14): chains hold only faces whose nodes were
    placed at one search. Layer 1 has one face (a chain of one segment: the straight face);
    layer 2 two faces, the lower from the settled boundary node (straight, no chain) and the
    upper one alone. So RPIM's master geometry is the faces', and its results those of the
    LINEAR search on the same deck; a curve through the bend would move them."""
    decks = {}
    for search in ("LINEAR", "RPIM"):
        d = Deck(f"hard case: slab on a face placed in two layers, {search}")
        d.materials = elastic(1, "body", 5.0e3, 0.3, 20.0) + elastic(2, "slab", *SLAB)
        rows = [0.0, 1.0, 1.5, 2.0]                      # layer 1: 0-1 m; layer 2: 1-2 m
        for y in rows:
            for x in (0.0, 1.0, 2.0):
                d.nodes.append((x, y))
        for j in range(3):
            for i in range(2):
                a = 1 + 3 * j + i
                d.elems.append((a, a + 1, a + 4, a + 3, 1, "L1" if j == 0 else "L2", ""))
        first = len(d.nodes) + 1                         # slab: x -0.3..0, 6 rows, Q4S
        for k in range(7):
            d.nodes += [(-0.3, 2.0 * k / 6), (0.0, 2.0 * k / 6)]
        for k in range(6):
            a = first + 2 * k
            d.elems.append((a, a + 1, a + 3, a + 2, 2, "SLAB", "Q4S"))
        d.fix([1, 2, 3], 1, 1)
        d.fix([first, first + 1], 1, 1)
        d.loads[""] = [f"&PRESSURE, {e}, 4, 50.0, 50.0" for e in range(7, 13)]
        d.contact = ["&SURFACE, SLABR, 7, 2, 5, 1", "&SURFACE, BODYL, 1, 4, 2, 2",
                     f"&PAIR, SLABR, BODYL, 0.0, 0.0, MORTAR, {search}"]
        d.stages = ["&FILL, L1, 1, , layer 1", "&FILL, L2, 1, , layer 2",
                    "&FILL, SLAB, 1, , slab", "&LOAD, , 2, , slab pressed on the face"]
        decks[f"rpim-bend-{search.lower()}.dat"] = d
    return decks


def case_rpim_x1():
    """The Tianshengqiao-I contact deck at x1 with the master curve by RPIM (the paper's Step
    3; rpim-x1 of the hard decks below), midpoint and Newton to 1e-10."""
    return {f"rpim-x1{tag}.dat": Generated(
        f"* tools/tianshengqiao.py --refine 1 --interface contact --solver {solver}, SEARCH "
        "RPIM (written by tools/hard_cases.py --write, issue 20)\n", "--refine", 1,
        "--interface", "contact", "--solver", solver)
        for tag, solver in (("", "midpoint"), ("-newton", "newton"))}


CASE_DECKS = (case_liftoff, case_long_slip, lambda: {"contrast.dat": column(
    "hard case: kn / E = 1e6, E slab / E cushion = 1e5", "JOINT")}, lambda: {
    "thin-0001.dat": column("hard case: thin layer of aspect ratio 0.001", "THIN", 0.001)},
    case_rockfill, case_drawdown, case_mechanism, case_no_converge, case_rpim_bend, case_cast_swap,
    case_fine_slave, case_fine_smooth, case_incipient_newton, case_rpim_x1)


def check_liftoff(cfrd, work):
    r, a = Run(cfrd, work, "liftoff.dat"), Run(cfrd, work, "liftoff-slab-alone.dat")
    if not common("liftoff", r, 0) or a.status != 0:
        return r, "did not run"
    s1, s2, s3 = r.stages
    nb = 15                                         # block nodes first, then the slab's
    p1 = np.max(np.abs(s1["c_sigma_n"]))
    e_open = np.max(np.abs(s2["c_sigma_n"])) / p1
    check("liftoff/zero-contact", e_open <= 1e-9 and p1 > 10.0,
          f"lifted: |sigma_n| {e_open:.1e} of the pressed state's {p1:.1f} kPa (1e-9), "
          f"{np.count_nonzero(s2['c_status'] == 0)} of {len(s2['c_status'])} nodes open")
    e_block = np.max(np.abs(s2["displacement"][:nb])) / np.max(np.abs(s1["displacement"][:nb]))
    check("liftoff/block-unloaded", e_block <= 1e-9, f"lifted: the unloaded elastic block's "
          f"displacement {e_block:.1e} of the pressed one (closed form: zero; 1e-9)")
    e_slab = rel(s2["displacement"][nb:], a.stages[0]["displacement"])
    check("liftoff/slab-alone", e_slab <= 1e-9, f"lifted: slab displacements against the slab "
          f"alone under the net uplift (liftoff-slab-alone.dat): {e_slab:.1e} (1e-9)")
    e_back = max(rel(s3["displacement"], s1["displacement"]), rel(s3["c_sigma_n"], s1["c_sigma_n"]))
    check("liftoff/re-closure", e_back <= 1e-8, f"re-closed: displacements and sigma_n against "
          f"the first pressed stage (frictionless, linear: path-independent): {e_back:.1e} (1e-8)")
    return r, f"converged; zero contact {e_open:.0e}, slab alone {e_slab:.0e}, " \
              f"re-closure {e_back:.0e}"


def check_long_slip(cfrd, work):
    r = Run(cfrd, work, "long-slip.dat")
    if not common("long-slip", r, 0):
        return r, "did not run"
    s = r.stages[-1]
    fx = s["reaction"][np.arange(28, 33), 0].sum()       # the block's top row (0-based)
    expect = 0.4 * 100.0 * 2.0
    e = abs(fx - expect) / expect
    # Coulomb on a flat base; the deformed base tilts the contact normals by up to its
    # largest displacement over its element length (1 m), which the updated geometry sees.
    tilt = float(np.max(np.abs(s["displacement"][:18])))
    check("long-slip/friction", e <= tilt, f"drag force {fx:.6f} kN/m against mu p B = "
          f"{expect} (Coulomb, closed form): {e:.1e} (the base's tilt, max |u_base| / 1 m = "
          f"{tilt:.1e})")
    closed = s["c_status"] != 0
    slip = s["c_slip"][closed]
    check("long-slip/distance", np.all(s["c_status"][closed] == 2) and closed.sum() == 5 and
          np.all(np.abs(slip - 3.0) < 0.01), f"{closed.sum()} of 5 slave nodes closed and "
          f"slipping, slip {slip.min():.4f}-{slip.max():.4f} m against the 3 m dragged less the"
          f" block's shear (0.01 m)")
    return r, f"converged; drag force {e:.0e}, slip {slip.min():.3f}-{slip.max():.3f} m"


def column_check(cfrd, work, name, deck, interface_gap):
    r = Run(cfrd, work, deck)
    if not common(name, r, 0):
        return r, "did not run"
    u = r.stages[-1]["displacement"][:, 1]
    jump = u[6] - u[5]                              # slab bottom - cushion top (node 7, 6)
    e_jump = abs(jump - interface_gap) / abs(interface_gap)
    check(name + "/interface", e_jump <= 1e-6, f"interface closure {jump:.6e} m against "
          f"{interface_gap:.6e} (1-D closed form): {e_jump:.1e} (1e-6)")
    top = -(COLUMN_P * 2.0 / oedometric(COLUMN_E, COLUMN_NU) + COLUMN_P * 0.5 /
            oedometric(1.0e5 * COLUMN_E, 0.2)) + interface_gap
    e_top = abs(u[-1] - top) / abs(top)
    check(name + "/settlement", e_top <= 1e-10, f"top settlement {u[-1]:.9e} m against "
          f"{top:.9e} (1-D closed form): {e_top:.1e} (1e-10)")
    return r, f"converged; interface {e_jump:.0e}, settlement {e_top:.0e}"


def check_rockfill(cfrd, work):
    r = Run(cfrd, work, "rockfill-tension.dat")
    if not common("rockfill", r, 0):
        return r, "did not run"
    s = r.stages[-1]
    tension = int(np.count_nonzero(s["principal"][:, 0] > 0.0))
    level = float(np.max(s["stress_level"]))
    check("rockfill/tension-and-cap", tension >= 1 and abs(level - 0.99) < 1e-12,
          f"{tension} elements in tension (largest principal stress > 0), stress level "
          f"{level:.6f}: capped at the law's 0.99 (docs/theory.md section 8)")
    e = float(np.max(np.abs(s["reaction_sum"] + s["applied"])) / np.max(np.abs(s["applied"])))
    check("rockfill/equilibrium", e <= 1e-6, f"reactions balance the weight and the pull "
          f"(statics; Newton to 1e-8): {e:.1e} (1e-6)")
    return r, f"converged; {tension} elements in tension, stress level capped 0.99, " \
              f"equilibrium {e:.0e}"


def check_drawdown(cfrd, work):
    r = Run(cfrd, work, "drawdown.dat")
    if not common("drawdown", r, 0):
        return r, "did not run"
    s1, s2, s3 = r.stages
    wet, water = 9.81 * 10.0 * 4.0, -(s2["applied"][1] - s1["applied"][1])
    e_w = abs(water - wet) / wet
    check("drawdown/water", e_w <= 1e-12, f"the water on the slab {water:.6f} kN/m against "
          f"gamma_w 10 m x 4 m = {wet:.3f} (closed form): {e_w:.1e} (1e-12)")
    e = max(rel(s3["displacement"], s1["displacement"]), rel(s3["c_sigma_n"], s1["c_sigma_n"]))
    # Frictionless and linear, the state returns, up to the contact geometry updated at the
    # deformed coordinates every increment (docs/theory.md section 14): an effect of the
    # order of the largest displacement over the slab element length (0.5 m).
    bound = float(np.max(np.abs(s2["displacement"]))) / 0.5
    check("drawdown/unloaded", e <= bound, f"drawn down: displacements and sigma_n against the"
          f" state before filling (frictionless, linear: path-independent up to the geometry "
          f"updates, max |u| / h = {bound:.1e}): {e:.1e}")
    return r, f"converged; water {e_w:.0e}, return to the state before filling {e:.0e} " \
              f"(bound {bound:.0e})"


def check_mechanism(cfrd, work):
    r = Run(cfrd, work, "mechanism.dat")
    common("mechanism", r, 1)
    diagnostic("mechanism", r, ["stage 1", "increment 2", "singular", "MU = 0",
                                "the first node", "mechanism"])
    return r, "error: singular, frictionless slave nodes named as a mechanism"


def check_no_converge(cfrd, work):
    earlier = b"results of an earlier run of no-converge.dat\n"
    r = Run(cfrd, work, "no-converge.dat", earlier=earlier)
    common("no-converge", r, 1)
    diagnostic("no-converge", r, ["stage 3", "increment 1", "Newton iterations",
                                  "relative residual", "at node", "cut back 6 times"])
    kept = open(r.h5, "rb").read() == earlier
    check("no-converge/earlier-results", kept and len(r.stages) == 2, f"DECK.h5 of the earlier"
          f" run untouched ({kept}), the completed stages in DECK.incomplete.h5 "
          f"({len(r.stages)} of 2)")
    return r, "error after 6 cutbacks of increment 1, stages 1-2 kept"


def check_rpim_bend(cfrd, work):
    r = Run(cfrd, work, "rpim-bend-rpim.dat")
    ref = Run(cfrd, work, "rpim-bend-linear.dat")
    common("rpim-bend", r, 0)
    if r.status != 0 or ref.status != 0:
        return r, "did not run"
    s, t = r.stages[-1], ref.stages[-1]
    # The bend at node 4 (y 1): the face nodes 1 (y 0), 4 and 7 (y 1.5) at x + u after
    # layer 2 (node 7 since its placement, nodes 1 and 4 since layer 1's; no RESET).
    u = r.stages[1]["displacement"]
    xf = np.array([[0.0, 0.0], [0.0, 1.0], [0.0, 1.5]]) + u[[0, 3, 6]]
    t0, t1 = xf[1] - xf[0], xf[2] - xf[1]
    bend = abs(math.atan2(t0[0], t0[1]) - math.atan2(t1[0], t1[1]))
    p = np.max(np.abs(t["c_sigma_n"]))
    e = max(rel(s["displacement"], t["displacement"]), rel(s["c_sigma_n"], t["c_sigma_n"]),
            rel(s["c_gap"], t["c_gap"]) if np.max(np.abs(t["c_gap"])) > 0 else 0.0)
    check("rpim-bend/as-linear", e <= 1e-9 and p > 1.0 and bend > 1e-3,
              f"RPIM against the LINEAR search on the same deck (no chain crosses the layer "
              f"bend of {bend:.1e} rad; every chain straight): displacements, sigma_n, gaps "
              f"{e:.1e} (1e-9); largest pressure {p:.1f} kPa")
    return r, f"converged; RPIM = LINEAR {e:.0e} across a bend of {bend:.0e} rad"


def slab_pressure_bound(stage, toml=os.path.join(runner.ROOT, "inputs", "tianshengqiao-i.toml")):
    """The Tianshengqiao-I slab's pressure bound at each slave node's elevation y: the water
    over it (gamma_w 9.81, the stage's reservoir level) plus the slab's own weight across its
    thickness t = t0 + rate (crest - y) (the geometry file's [slab], unit weight 24)."""
    with open(toml, "rb") as fh:
        g = tomllib.load(fh)
    slab, crest = g["slab"], g["section"]["crest_elevation"]["value"]
    y = stage["c_y"]
    level = -np.inf if stage["reservoir_empty"] else stage["water_level"]
    t = slab["t0"]["value"] + slab["rate"]["value"] * (crest - y)
    return 9.81 * np.maximum(level - y, 0.0) + slab["unit_weight"]["value"] * t


def check_rpim_x1(cfrd, work, name, deck, balance):
    """rpim-x1 (midpoint) and rpim-x1-newton: all 45 stages, no NaN, the contact pressure at
    every slave node but the toe face's two below 10 times the water and slab-weight bound at
    its elevation (slab_pressure_bound), with Newton the balance to 1e-8 at every stage."""
    r = Run(cfrd, work, deck)
    if not common(name, r, 0):
        return r, "did not run"
    check(name + "/stages", len(r.stages) == 45, f"{len(r.stages)} stages of 45 completed")
    worst, at, toe = 0.0, 0, 0.0
    for k, stage in enumerate(r.stages, 1):
        p, away = -stage["c_sigma_n"], np.argsort(stage["c_y"])[2:]
        ratio = float(np.max(p[away] / slab_pressure_bound(stage)[away]))
        worst, at = max((worst, at), (ratio, k))
        toe = max(toe, float(np.max(p)))
    check(name + "/pressure-bound", worst <= 10.0, f"contact pressure away from the toe face "
          f"(every slave node but the lowest two) up to {worst:.2f} times gamma_w (H - y) + "
          f"gamma_c t(y) (stage {at}; 10)")
    outcome = f"completes 45 stages; pressure up to {worst:.2f} x the water + slab weight " \
              f"bound away from the toe, {toe / 1000:.0f} MPa at the toe (reported)"
    return r, outcome + (balance_check(name, r) if balance else "")


CASES = [("liftoff", "full lift-off of the slab and re-closure", check_liftoff),
         ("long-slip", "slip of 3 master element lengths", check_long_slip),
         ("contrast", "kn / E_cushion = 1e6, E_slab / E_cushion = 1e5", lambda c, w: column_check(
             c, w, "contrast", "contrast.dat", -COLUMN_P / (1.0e6 * COLUMN_E))),
         ("thin", "thin layer, aspect ratio 0.001", lambda c, w: column_check(
             c, w, "thin", "thin-0001.dat", -COLUMN_P * 0.001 / oedometric(COLUMN_E, COLUMN_NU))),
         ("rockfill", "E-B at zero and tensile confinement, stress level capped",
          check_rockfill),
         ("drawdown", "reservoir filling and drawdown", check_drawdown),
         ("mechanism", "frictionless slab held by nothing", check_mechanism),
         ("no-converge", "Newton tolerance below round-off", check_no_converge),
         ("incipient-slip", "Tianshengqiao fine slab (incipient slip at stage 15), midpoint",
          check_incipient_slip),
         ("incipient-newton", "the same deck with Newton to 1e-10", check_incipient_newton),
         ("incipient-asis", "the same deck, midpoint, ROLES ASIS (friction per master segment)",
          check_incipient_asis),
         ("incipient-rpim", "the same deck, midpoint, SEARCH RPIM (the roles swapped: the "
          "curve through the slab's nodes)", check_incipient_rpim),
         ("fine-stick", "fine slave on a coarse master pushed by mu N / 2", check_fine_stick),
         ("fine-slip", "fine slave on a coarse master dragged", check_fine_slip),
         ("fine-stick-swap", "the same pushed, roles swapped (the master carries the "
          "multipliers)", lambda c, w: check_fine_stick(c, w, "fine-stick-swap")),
         ("fine-slip-swap", "the same dragged, roles swapped",
          lambda c, w: check_fine_slip(c, w, "fine-slip-swap")),
         ("fine-smooth", "fine slave, 16 faces per master face, linear load, mu 0 and 0.5 "
          "on one face, 0.5 on two", check_fine_smooth),
         ("cast-swap", "fine slab cast (CAST 1) on a settled coarse foundation, roles swapped",
          check_cast_swap),
         ("rpim-bend", "RPIM master face placed in two layers (a bend at the boundary)",
          check_rpim_bend),
         ("rpim-x1", "Tianshengqiao-I contact deck at x1, SEARCH RPIM, midpoint",
          lambda c, w: check_rpim_x1(c, w, "rpim-x1", "rpim-x1.dat", False)),
         ("rpim-x1-newton", "the same deck with Newton to 1e-10",
          lambda c, w: check_rpim_x1(c, w, "rpim-x1-newton", "rpim-x1-newton.dat", True))]


def main(argv=None):
    ap = parser(__doc__, cfrd="bin/cfrd", workdir="build/hard-cases")
    ap.add_argument("--write", action="store_true")
    ap.add_argument("--only")
    ap.add_argument("--table", action="store_true")
    ap.add_argument("--refinement", action="store_true",
                    help="measure fine-smooth-two-faces at finer foundations (a table)")
    args = ap.parse_args(argv)
    if args.refinement:
        os.makedirs(args.workdir, exist_ok=True)
        print("\n".join(master_refinement(args.cfrd, args.workdir)))
        return 0
    if args.write:
        os.makedirs(DECKS, exist_ok=True)
        for make in CASE_DECKS:
            for name, deck in make().items():
                open(os.path.join(DECKS, name), "w").write(deck.text())
                print("wrote", os.path.join(DECKS, name))
        return 0
    os.makedirs(args.workdir, exist_ok=True)
    rows = []
    for name, what, case in CASES:
        if args.only and args.only != name:
            continue
        found = check.guard(name, case, args.cfrd, args.workdir)
        if found is None:           # a check that cannot run is a failure, never a skip
            continue
        run, outcome = found
        cut = sum(s["cutbacks"] for s in run.stages)
        if "cut back " in run.stderr:
            cut = f"{cut} + {run.stderr.split('cut back ')[1].split()[0]} (failing increment)"
        rows.append(f"| {name} | {what} | {outcome} | {cut} | "
                    f"{sum(s['contact_iterations'] for s in run.stages)} |")
    if args.table:
        print("\n".join(rows))
    return check.status


if __name__ == "__main__":
    sys.exit(main())
