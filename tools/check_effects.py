#!/usr/bin/env python3
"""Checks of the EFFECTS card (issue 9, section 3): each effect switched off against a closed
form, scipy's E-B integration or an equivalent deck.

  effects/linear-rockfill   ROCKFILL LINEAR: one plane-strain element of IIIB at 500 kPa
                            under deviator steps, eps_y = (1 - nu^2) q / E with E = K pa and
                            nu from B = Kb pa (1e-9); one factorisation in the run
  effects/unload-off        UNLOAD OFF: unloading follows the loading curve back (scipy's
                            E-B integration, 5e-3), no past maximum kept; ON: Kur (> 10 %)
  effects/water-off         the x1 joint deck with WATER OFF: WATER stages solve nothing and
                            move nothing; the load is the weight, sum of gamma * area (1e-9)
  effects/phases-off        the slab placed at its last phase only: stages, active elements,
                            and the load before and after it (shoelace, 1e-9)
  effects/bonded            the x1 joint deck with INTERFACE BONDED against the bonded x1 deck
                            (shared nodes): displacements at every stage (1e-9); no interface
                            results stored
  effects/friction-off      the x1 contact deck frictionless: zero shear tractions
  effects/slip-small        the x1 contact deck: one search per FILL stage placing contact
                            faces, none otherwise; no contact search in a deck without CONTACT

  python3 tools/check_effects.py --cfrd build/debug-bin/cfrd --workdir DIR   (PASS/FAIL lines)
"""

import os
import sys

import numpy as np

import eb_reference  # the independent E-B integration
from cfrdtools import results, runner
from cfrdtools.checks import Checks, parser
from cfrdtools.decks import groups, unit_weights, with_effects

check = Checks("effects")
stages = results.stages


def run(workdir, cfrd, name, text):
    return results.open_results(runner.run_text(cfrd, os.path.join(workdir, name + ".dat"), text))


def element_weights(h5, deck_text):
    """gamma * area of every element (kN/m): the shoelace area of its corners."""
    gamma = unit_weights(deck_text)
    xy, conn = h5["mesh/coordinates"][...], h5["mesh/connectivity"][...] - 1
    x, y = xy[conn, 0], xy[conn, 1]
    area = 0.5 * np.abs(np.sum(x * np.roll(y, -1, axis=1) - np.roll(x, -1, axis=1) * y, axis=1))
    return area * np.array([gamma.get(int(m), 0.0) for m in h5["mesh/material"][...]])


def placed_weight(weights, g):
    return float(np.sum(weights * (g["active"][...] != 0)))


def single_element(work, cfrd):
    """ROCKFILL LINEAR and UNLOAD OFF on one plane-strain element of IIIB at 500 kPa."""
    mat, s3, pa = "IIIB", 500.0, eb_reference.PA
    k, kb = eb_reference.TABLE3[mat][2], eb_reference.TABLE3[mat][5]
    qf = eb_reference.failure_deviator(mat, s3)
    base = eb_reference.cfrd_deck(mat, s3, 0.1 * qf, 9, 40)

    def with_card(deck, **switch):       # the one-element deck has no CONTROL group
        return with_effects(deck.replace("NODES", "CONTROL\nNODES", 1), **switch)
    # Linear: E = K pa, B = Kb pa bounded to [E/3, E/0.06], nu = (3B - E)/(6B); the deviator
    # steps at constant sigma_x in plane strain: d eps_y = (1 - nu^2) dq / E.
    e = k * pa
    b = min(max(kb * pa, e / 3.0), e / (3.0 * (1.0 - 2.0 * eb_reference.NU_MAX)))
    nu = (3.0 * b - e) / (6.0 * b)
    st = stages(run(work, cfrd, "linear", with_card(base, ROCKFILL="LINEAR")))
    eps = np.array([-s["displacement"][2, 1] for s in st[2:]])
    err = float(np.max(np.abs(eps / ((1.0 - nu * nu) * 0.1 * qf * np.arange(1, 10) / e) - 1.0)))
    factorisations = sum(int(s.attrs["factorisations"]) for s in st)
    check("linear-rockfill", err < 1e-9 and factorisations == 1, f"eps_y of 9 deviator steps "
          f"against (1 - nu^2) q / E, E = {e:.0f} kPa, nu = {nu:.4f}: max rel. error {err:.1e} "
          f"(tol 1e-9); {factorisations} factorisation(s) in the run (expected 1: a linear "
          f"model)")
    # Unload without Kur: 9 steps up to 0.9 qf, 6 down to 0.3 qf.
    deck = base.replace("STAGES\n", f"LOADS     UNSHEAR\n&PRESSURE, 1, 3, {-0.1 * qf!r}\n"
                        "STAGES\n", 1).replace("END\n", "".join(
                            f"&LOAD, UNSHEAR, 40, , unloading step {i + 1}\n" for i in range(6))
                                               + "END\n", 1)
    got = {}
    for switch in ("OFF", "ON"):
        last = stages(run(work, cfrd, f"unload-{switch.lower()}",
                          with_card(deck, UNLOAD=switch)))[-1]
        got[switch] = (-last["displacement"][2, 1],
                       float(np.max(np.abs(last["history_gauss"][..., 0]))))
    ref = eb_reference.integrate(mat, s3, np.array([0.0, 0.3 * qf]), "plane-strain")[0][1]
    err_off, err_on = abs(got["OFF"][0] / ref - 1.0), abs(got["ON"][0] / ref - 1.0)
    check("unload-off", err_off < 5e-3 and got["OFF"][1] == 0.0 and err_on > 0.1,
          f"eps_y after unloading to 0.3 qf: {got['OFF'][0]:.6e} against the loading curve's "
          f"{ref:.6e} (scipy ODE): rel. error {err_off:.1e} (tol 5e-3); past maximum of the "
          f"stress state kept: {got['OFF'][1]:g} (expected 0); with UNLOAD ON the strain is "
          f"{err_on:.0%} off it (Kur, expected > 10 %)")


def water_off(work, cfrd, joint):
    text = with_effects(joint, WATER="OFF")
    h5 = run(work, cfrd, "x1-joint-water-off", text)
    st, weights = stages(h5), element_weights(h5, text)
    water = [i for i, s in enumerate(st) if s.attrs["kind"] == b"WATER"]
    bad = [i + 1 for i in water if int(st[i].attrs["factorisations"]) +
           int(st[i].attrs["increments"])]
    moved = max((float(np.max(np.abs(st[i]["displacement"][...] - st[i - 1]["displacement"][
        ...]))) for i in water), default=0.0)
    load, total = st[-1].attrs["applied_load"], placed_weight(weights, st[-1])
    err = max(abs(load[1] + total), abs(load[0])) / total
    check("water-off", not bad and moved == 0.0 and err < 1e-9, f"{len(water)} WATER stages: "
          f"{len(bad)} with increments or factorisations (expected 0), largest displacement "
          f"change {moved:g} m (expected 0); the final load ({load[0]:.6g}, {load[1]:.6g}) kN/m "
          f"against the weight {total:.6f} kN/m (sum of gamma * shoelace area): rel. error "
          f"{err:.1e} (tol 1e-9)")


def phases_off(work, cfrd, joint):
    st0 = stages(run(work, cfrd, "x1-joint-water-off-ref", with_effects(joint, WATER="OFF")))
    text = with_effects(joint, WATER="OFF", PHASES="OFF")
    h5 = run(work, cfrd, "x1-joint-phases-off", text)
    st, weights = stages(h5), element_weights(h5, text)
    slab = np.zeros(len(weights), bool)
    slab[results.last_stage(h5)["slab/element"][...] - 1] = True
    slab[h5["mesh/interface_elements"][...] - 1] = True   # the joints belong to the phases too
    first = next(i for i, s in enumerate(st) if np.any(s["active"][...][slab]))
    placed = [int(np.sum(s["active"][...][slab])) for s in st0]
    phases = sum(1 for a, b in zip([0] + placed, placed) if b > a)
    err = max(abs(st[i].attrs["applied_load"][1] + placed_weight(weights, st[i])) /
              placed_weight(weights, st[i]) for i in (first - 1, first))
    at_once = bool(np.all(st[first]["active"][...][slab]))
    check("phases-off", at_once and len(st) == len(st0) - (phases - 1) and err < 1e-9,
          f"the slab's {int(slab.sum())} elements all placed at stage {first + 1} "
          f"({'yes' if at_once else 'no'}), none before; {len(st)} stages (the deck's "
          f"{len(st0)} less {phases - 1} earlier phases); the load before and after it against"
          f" the weights placed (shoelace): rel. error {err:.1e} (tol 1e-9)")


def bonded(work, cfrd, joint, bonded_deck):
    h5 = run(work, cfrd, "x1-joint-bonded", with_effects(joint, INTERFACE="BONDED"))
    ref = run(work, cfrd, "x1-bonded", bonded_deck)
    st, st0 = stages(h5), stages(ref)
    xy, xy0 = h5["mesh/coordinates"][...], ref["mesh/coordinates"][...]
    # the bonded deck's node at each coordinate of the bonded joint deck's used nodes
    used = np.unique(h5["mesh/connectivity"][...][:len(h5["mesh/kind"])] - 1)
    key0 = {tuple(np.round(p, 6)): i for i, p in enumerate(xy0)}
    pairs = np.array([(i, key0.get(tuple(np.round(xy[i], 6)), -1)) for i in used])
    err = np.inf
    if len(st) == len(st0) and np.all(pairs[:, 1] >= 0) and len(pairs) == len(xy0):
        err = max(float(np.max(np.abs(results.field(a, "displacement_total")[pairs[:, 0]]
                                      - results.field(b, "displacement_total")[pairs[:, 1]])))
                  / float(np.max(np.abs(results.field(b, "displacement_total"))) or 1.0)
                  for a, b in zip(st, st0))
    stored = "interface" in st[-1]
    check("bonded", err < 1e-9 and not stored, f"x1 joint deck with INTERFACE BONDED against "
          f"the bonded x1 deck (shared nodes): {len(pairs)} nodes matched of {len(xy0)}, "
          f"displacements at all {len(st)} stages: max rel. difference {err:.1e} (tol 1e-9); "
          f"interface results stored: {'yes' if stored else 'no'} (expected no)")


def contact(work, cfrd, contact_deck, bonded_deck):
    st = stages(run(work, cfrd, "x1-contact-frictionless", with_effects(contact_deck,
                                                                      FRICTION="OFF")))
    tau = max(float(np.max(np.abs(s["contact/tau"][...]))) for s in st)
    sig = max(float(np.max(np.abs(s["contact/sigma_n"][...]))) for s in st)
    check("friction-off", tau <= 1e-12 * sig, f"largest shear traction of {len(st)} stages "
          f"{tau:.1e} kPa against a largest normal traction of {sig:.3g} kPa (mu = 0: zero, "
          f"tol 1e-12 of it)")
    h5 = run(work, cfrd, "x1-contact-small-slip", with_effects(contact_deck, SLIP="SMALL"))
    st = stages(h5)
    # the elements of the CONTACT SURFACE cards (ELEM 21-25, NGEN 31-35, INC 36-40)
    faces = np.zeros(len(h5["mesh/kind"]), bool)
    for line in dict(groups(contact_deck)).get("CONTACT", []):
        if line[:10].strip().upper() == "SURFACE":
            faces[[int(line[20:25]) + g * int(line[35:40].strip() or 1) - 1
                   for g in range(int(line[30:35].strip() or 0) + 1)]] = True
    placing = [bool(np.any(faces & (s["active"][...] != 0) & (
        p["active"][...] == 0 if p is not None else True))) for p, s in zip([None] + st[:-1], st)]
    wrong = [i + 1 for i, s in enumerate(st) if int(s["solver"].attrs["searches"])
             != int(placing[i])]
    large = sum(int(s["solver"].attrs["searches"]) for s in stages(run(
        work, cfrd, "x1-contact-large-slip", contact_deck)))
    small = sum(int(s["solver"].attrs["searches"]) for s in st)
    none = sum(int(s["solver"].attrs["searches"]) + (s["solver"].attrs["t_contact"] > 0)
               for s in stages(run(work, cfrd, "x1-bonded-searches", bonded_deck)))
    check("slip-small", not wrong and none == 0 and small < large, f"searches: one at each of "
          f"the {sum(placing)} stages that place faces of the CONTACT surfaces, none at the "
          f"others; stages off that: {wrong or 'none'}; {small} in all against {large} with "
          f"large slip (one per increment); the bonded deck: {none} searches or stages with "
          f"contact time (expected 0)")


def main(argv=None):
    args = parser(__doc__, cfrd="build/debug-bin/cfrd", workdir="build/check-effects"
                  ).parse_args(argv)
    cfrd = os.path.abspath(args.cfrd)
    os.makedirs(args.workdir, exist_ok=True)
    joint, bonded_deck, contact_deck = (open(os.path.join("inputs", f"tianshengqiao-x1{m}.dat"))
                                        .read() for m in ("-joint", "", "-contact"))
    for case, *decks in ((single_element,), (water_off, joint), (phases_off, joint),
                         (bonded, joint, bonded_deck), (contact, contact_deck, bonded_deck)):
        # a check that cannot run is a failure, with its reason
        check.guard("run", case, args.workdir, cfrd, *decks)
    return check.status


if __name__ == "__main__":
    sys.exit(main())
