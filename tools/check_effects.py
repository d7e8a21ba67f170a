#!/usr/bin/env python3
"""Checks of the EFFECTS card (issue 9, section 3; docs/cards.md, CONTROL): each effect
switched off does what docs/cards.md says, against a reference that cfrd does not compute:

  effects/linear-rockfill   one E-B element as linear elastic (E = K pa, nu from B = Kb pa):
                            plane-strain strain closed form (1e-9), one factorisation in all
  effects/unload-off        loading to 0.9 qf and unloading to 0.3 qf without Kur: the strain
                            of the loading curve at 0.3 qf (scipy's integration of the E-B
                            law, tools/eb_reference.py, 5e-3); no history kept
  effects/water-off         the x1 joint deck: WATER stages solve nothing and move nothing;
                            the load is the weight, sum of gamma * area (shoelace, 1e-9)
  effects/phases-off        the slab placed at its last phase only: stages, active elements,
                            and the load before and after it (shoelace, 1e-9)
  effects/bonded            the x1 joint deck with INTERFACE BONDED against the bonded x1 deck
                            (shared nodes, written by tools/tianshengqiao.py): displacements
                            at every stage (1e-9); no interface results stored
  effects/friction-off      the x1 contact deck frictionless: zero shear tractions (Coulomb
                            with mu = 0)
  effects/slip-small        the x1 contact deck: one search per FILL stage, none otherwise;
                            and no contact search at all in a deck without CONTACT

  python3 tools/check_effects.py --cfrd build/debug-bin/cfrd --workdir DIR   (PASS/FAIL lines)
"""

import argparse
import os
import sys

import numpy as np

from cfrdtools import results, runner
import eb_reference  # the independent E-B integration

FIELDS = ("ROCKFILL", "UNLOAD", "WATER", "INTERFACE", "FRICTION", "SLIP", "PHASES")


def effects_card(**switch):
    """The EFFECTS card, A10 fields after the keyword (blank = the default)."""
    return "EFFECTS   " + "".join(f"{switch.get(k, ''):<10s}" for k in FIELDS)


def with_effects(deck_text, card):
    """The deck with `card` put after the CONTROL header (the group takes it anywhere)."""
    lines = deck_text.split("\n")
    k = next(i for i, line in enumerate(lines) if line.rstrip() == "CONTROL")
    return "\n".join(lines[:k + 1] + [card] + lines[k + 1:])


class Checker:
    def __init__(self, cfrd, workdir):
        self.cfrd = cfrd
        self.workdir = workdir
        self.failed = 0
        os.makedirs(workdir, exist_ok=True)

    def run(self, name, text):
        path = os.path.join(self.workdir, name + ".dat")
        return results.open_results(runner.run_text(self.cfrd, path, text))

    def report(self, name, ok, text):
        self.failed += not ok
        print(f"{'PASS' if ok else 'FAIL'} effects/{name}: {text}")


stages = results.stages


def unit_weights(deck_text):
    """Unit weight of each material from the MATERIALS group of a fixed-format deck: EB
    cards give GAMMA in columns 1-10 of the first data card, ELASTIC in columns 21-30,
    GOODMAN joints weigh nothing."""
    columns = {"EB": (0, 10), "ELASTIC": (20, 30)}
    weights, group, pending = {}, None, None
    for line in deck_text.split("\n"):
        if not line.strip() or line.startswith("*"):
            continue
        head = line[:10].strip().upper()
        if line[:1] != " " and head.isalpha():
            group = head
        elif group == "MATERIALS" and pending is None and line[5:15].strip().upper() in (
                "EB", "ELASTIC", "GOODMAN"):
            pending = (int(line[:5]), line[5:15].strip().upper())
        elif group == "MATERIALS" and pending is not None:
            number, law = pending
            a, b = columns.get(law, (0, 0))
            weights[number] = float(line[a:b] or 0.0) if b else 0.0
            pending = None
    return weights


def element_weights(h5, deck_text):
    """gamma * area of every element (kN/m): the shoelace area of its corners."""
    gamma = unit_weights(deck_text)
    xy = h5["mesh/coordinates"][...]
    conn = h5["mesh/connectivity"][...] - 1
    mat = h5["mesh/material"][...]
    x, y = xy[conn, 0], xy[conn, 1]
    area = 0.5 * np.abs(np.sum(x * np.roll(y, -1, axis=1) - np.roll(x, -1, axis=1) * y, axis=1))
    return area * np.array([gamma.get(int(m), 0.0) for m in mat])


def surface_elements(deck_text):
    """Elements of the CONTACT SURFACE cards (ELEM 21-25, NGEN 31-35, INC 36-40)."""
    elements = []
    for line in deck_text.split("\n"):
        if line[:10].strip().upper() != "SURFACE":
            continue
        first = int(line[20:25])
        ngen = int(line[30:35].strip() or 0)
        inc = int(line[35:40].strip() or 1)
        elements += [first + g * inc for g in range(ngen + 1)]
    return np.array(sorted(set(elements)))


def single_element(checker):
    """ROCKFILL LINEAR and UNLOAD OFF on one plane-strain element of IIIB at 500 kPa."""
    mat, s3 = "IIIB", 500.0
    k, kb = eb_reference.TABLE3[mat][2], eb_reference.TABLE3[mat][5]
    qf = eb_reference.failure_deviator(mat, s3)
    base = eb_reference.cfrd_deck(mat, s3, 0.1 * qf, 9, 40)

    def with_card(deck, card):       # the one-element deck has no CONTROL group
        return deck.replace("NODES", "CONTROL\n" + card + "\nNODES", 1)
    # Linear: E = K pa, B = Kb pa bounded to [E/3, E/0.06], nu = (3B - E)/(6B); the deviator
    # steps at constant sigma_x in plane strain: d eps_y = (1 - nu^2) dq / E.
    pa = eb_reference.PA
    e = k * pa
    b = min(max(kb * pa, e / 3.0), e / (3.0 * (1.0 - 2.0 * eb_reference.NU_MAX)))
    nu = (3.0 * b - e) / (6.0 * b)
    h5 = checker.run("linear", with_card(base, effects_card(ROCKFILL="LINEAR")))
    st = stages(h5)
    eps = np.array([-s["displacement"][2, 1] for s in st[2:]])
    exact = (1.0 - nu * nu) * 0.1 * qf * np.arange(1, 10) / e
    err = float(np.max(np.abs(eps / exact - 1.0)))
    factorisations = sum(int(s.attrs["factorisations"]) for s in st)
    checker.report("linear-rockfill", err < 1e-9 and factorisations == 1,
                   f"eps_y of 9 deviator steps against (1 - nu^2) q / E, E = {e:.0f} kPa, "
                   f"nu = {nu:.4f}: max rel. error {err:.1e} (tol 1e-9); {factorisations} "
                   f"factorisation(s) in the run (expected 1: a linear model)")
    # Unload without Kur: 9 steps up to 0.9 qf, 6 down to 0.3 qf.
    deck = base.replace("STAGES\n", f"LOADS     UNSHEAR\n&PRESSURE, 1, 3, {-0.1 * qf!r}\n"
                        "STAGES\n", 1)
    deck = deck.replace("END\n", "".join(f"&LOAD, UNSHEAR, 40, , unloading step {i + 1}\n"
                                          for i in range(6)) + "END\n", 1)
    results = {}
    for switch in ("OFF", "ON"):
        h5 = checker.run(f"unload-{switch.lower()}", with_card(deck, effects_card(UNLOAD=switch)))
        st = stages(h5)
        results[switch] = (-st[-1]["displacement"][2, 1],
                           float(np.max(np.abs(st[-1]["history_gauss"][..., 0]))))
    r1, _ = eb_reference.integrate(mat, s3, np.array([0.0, 0.3 * qf]), "plane-strain")
    ref = r1[1]
    err_off = abs(results["OFF"][0] / ref - 1.0)
    err_on = abs(results["ON"][0] / ref - 1.0)
    ok = err_off < 5e-3 and results["OFF"][1] == 0.0 and err_on > 0.1
    checker.report("unload-off", ok,
                   f"eps_y after unloading to 0.3 qf: {results['OFF'][0]:.6e} against the "
                   f"loading curve's {ref:.6e} (scipy ODE): rel. error {err_off:.1e} (tol "
                   f"5e-3); past maximum of the stress state kept: {results['OFF'][1]:g} "
                   f"(expected 0); with UNLOAD ON the strain is {err_on:.0%} off it (Kur, "
                   f"expected > 10 %)")


def water_off(checker, joint_text):
    text = with_effects(joint_text, effects_card(WATER="OFF"))
    h5 = checker.run("x1-joint-water-off", text)
    st = stages(h5)
    weights = element_weights(h5, text)
    bad, moved = [], 0.0
    for i, s in enumerate(st):
        if s.attrs["kind"] == b"WATER":
            solves = int(s.attrs["factorisations"]) + int(s.attrs["increments"])
            moved = max(moved, float(np.max(np.abs(s["displacement"][...]
                                                   - st[i - 1]["displacement"][...]))))
            if solves:
                bad.append(i + 1)
    load = st[-1].attrs["applied_load"]
    total = float(np.sum(weights * (st[-1]["active"][...] != 0)))
    err = max(abs(load[1] + total), abs(load[0])) / total
    nwater = sum(s.attrs["kind"] == b"WATER" for s in st)
    ok = not bad and moved == 0.0 and err < 1e-9
    checker.report("water-off", ok,
                   f"{nwater} WATER stages: {len(bad)} with increments or factorisations "
                   f"(expected 0), largest displacement change {moved:g} m (expected 0); the "
                   f"final load ({load[0]:.6g}, {load[1]:.6g}) kN/m against the weight "
                   f"{total:.6f} kN/m (sum of gamma * shoelace area): rel. error {err:.1e} "
                   f"(tol 1e-9)")


def phases_off(checker, joint_text):
    h5_base = checker.run("x1-joint-water-off-ref", with_effects(joint_text,
                                                                 effects_card(WATER="OFF")))
    text = with_effects(joint_text, effects_card(WATER="OFF", PHASES="OFF"))
    h5 = checker.run("x1-joint-phases-off", text)
    st, st0 = stages(h5), stages(h5_base)
    weights = element_weights(h5, text)
    slab = np.zeros(len(weights), bool)
    slab[results.last_stage(h5)["slab/element"][...] - 1] = True
    # the joints' elements belong to the slab phases too
    slab[h5["mesh/interface_elements"][...] - 1] = True
    first = next(i for i, s in enumerate(st) if np.any(s["active"][...][slab]))
    placed = [int(np.sum(s["active"][...][slab])) for s in st0]
    phases = sum(1 for a, b in zip([0] + placed, placed) if b > a)
    before = st[first - 1]
    w_before = float(np.sum(weights * (before["active"][...] != 0)))
    w_after = float(np.sum(weights * (st[first]["active"][...] != 0)))
    err = max(abs(before.attrs["applied_load"][1] + w_before) / w_before,
              abs(st[first].attrs["applied_load"][1] + w_after) / w_after)
    all_at_once = bool(np.all(st[first]["active"][...][slab]))
    expected_stages = len(st0) - (phases - 1)
    ok = all_at_once and len(st) == expected_stages and err < 1e-9
    checker.report("phases-off", ok,
                   f"the slab's {int(slab.sum())} elements all placed at stage {first + 1} "
                   f"({'yes' if all_at_once else 'no'}), none before; {len(st)} stages "
                   f"(the deck's {len(st0)} less {phases - 1} earlier phases); the load before "
                   f"and after it against the weights placed (shoelace): rel. error {err:.1e} "
                   f"(tol 1e-9)")


def bonded(checker, joint_text, bonded_text):
    h5 = checker.run("x1-joint-bonded", with_effects(joint_text,
                                                      effects_card(INTERFACE="BONDED")))
    ref = checker.run("x1-bonded", bonded_text)
    st, st0 = stages(h5), stages(ref)
    xy, xy0 = h5["mesh/coordinates"][...], ref["mesh/coordinates"][...]
    # the bonded deck's node at each coordinate of the bonded joint deck's used nodes
    used = np.unique(h5["mesh/connectivity"][...][:len(h5["mesh/kind"])] - 1)
    key0 = {tuple(np.round(p, 6)): i for i, p in enumerate(xy0)}
    pairs = np.array([(i, key0.get(tuple(np.round(xy[i], 6)), -1)) for i in used])
    err = np.inf
    if len(st) == len(st0) and np.all(pairs[:, 1] >= 0) and len(pairs) == len(xy0):
        err = max(float(np.max(np.abs(a["displacement_total"][...][pairs[:, 0]]
                                      - b["displacement_total"][...][pairs[:, 1]])))
                  / float(np.max(np.abs(b["displacement_total"][...])) or 1.0)
                  for a, b in zip(st, st0))
    stored = "interface" in st[-1]
    checker.report("bonded", err < 1e-9 and not stored,
                   f"x1 joint deck with INTERFACE BONDED against the bonded x1 deck (shared "
                   f"nodes): {len(pairs)} nodes matched of {len(xy0)}, displacements at all "
                   f"{len(st)} stages: max rel. difference {err:.1e} (tol 1e-9); interface "
                   f"results stored: {'yes' if stored else 'no'} (expected no)")


def contact(checker, contact_text, bonded_text):
    h5 = checker.run("x1-contact-frictionless", with_effects(contact_text,
                                                             effects_card(FRICTION="OFF")))
    st = stages(h5)
    tau = max(float(np.max(np.abs(s["contact/tau"][...]))) for s in st)
    sig = max(float(np.max(np.abs(s["contact/sigma_n"][...]))) for s in st)
    checker.report("friction-off", tau <= 1e-12 * sig,
                   f"largest shear traction of {len(st)} stages {tau:.1e} kPa against a "
                   f"largest normal traction of {sig:.3g} kPa (mu = 0: zero, tol 1e-12 of it)")
    h5 = checker.run("x1-contact-small-slip", with_effects(contact_text,
                                                           effects_card(SLIP="SMALL")))
    st = stages(h5)
    faces = np.zeros(len(h5["mesh/kind"]), bool)
    faces[surface_elements(contact_text) - 1] = True
    placing = [bool(np.any(faces & (s["active"][...] != 0) & (p["active"][...] == 0)))
               for p, s in zip([None] + st[:-1], st) if p is not None]
    placing = [bool(np.any(faces & (st[0]["active"][...] != 0)))] + placing
    wrong = [i + 1 for i, s in enumerate(st) if int(s["solver"].attrs["searches"])
             != int(placing[i])]
    large = sum(int(s["solver"].attrs["searches"]) for s in stages(checker.run(
        "x1-contact-large-slip", contact_text)))
    small = sum(int(s["solver"].attrs["searches"]) for s in st)
    ref = checker.run("x1-bonded-searches", bonded_text)
    none = sum(int(s["solver"].attrs["searches"]) + (s["solver"].attrs["t_contact"] > 0)
               for s in stages(ref))
    checker.report("slip-small", not wrong and none == 0 and small < large,
                   f"searches: one at each of the {sum(placing)} stages that place faces of "
                   f"the CONTACT surfaces, none at the others; stages off that: "
                   f"{wrong or 'none'}; "
                   f"{small} in all against {large} with large slip (one per increment); the "
                   f"bonded deck: {none} searches or stages with contact time (expected 0)")


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--cfrd", default="build/debug-bin/cfrd")
    ap.add_argument("--workdir", default="build/check-effects")
    args = ap.parse_args(argv)
    checker = Checker(os.path.abspath(args.cfrd), args.workdir)

    def read(name):
        with open(os.path.join("inputs", name)) as f:
            return f.read()

    joint, bonded_deck, contact_deck = (read("tianshengqiao-x1-joint.dat"),
                                        read("tianshengqiao-x1.dat"),
                                        read("tianshengqiao-x1-contact.dat"))
    for check in (lambda: single_element(checker), lambda: water_off(checker, joint),
                  lambda: phases_off(checker, joint),
                  lambda: bonded(checker, joint, bonded_deck),
                  lambda: contact(checker, contact_deck, bonded_deck)):
        try:
            check()
        except Exception as exc:  # a check that cannot run is a failure, with its reason
            checker.report("run", False, f"{type(exc).__name__}: {exc}")
    return 1 if checker.failed else 0


if __name__ == "__main__":
    sys.exit(main())
