#!/usr/bin/env python3
"""CalculiX as the independent peer of frictional contact (issue 7, section 2; the case and
what CalculiX is given: docs/theory.md section 14, "Verification").

  python3 tools/ccx_contact.py --cfrd bin/cfrd [--workdir DIR]
  python3 tools/ccx_contact.py --cfrd bin/cfrd --penalty-study     (the K, lambda table)

A slab (40 x 2 quads) on a cushion block (30 x 6, non-matching), mu = 0.5, on a 1 : 1.4
slope, its toe held, the base settling, water on the slab. Asserted: the normal and
tangential resultants of the contact force on the slab within 1 % of CalculiX's; the same
open zones (gap > 1e-4 m, measured the same way for both), each as long within one slab
element; and that the case has two open zones, a closed part, and slave nodes that stick and
that slip.
"""
import math
import os
import sys

import numpy as np

from cfrdtools import ccx, results, runner
from cfrdtools.checks import Checks, parser
from cfrdtools.decks import fmt_alpha as a, fmt_int as f

L, T, H = 20.0, 0.5, 4.0         # slab and cushion length, slab thickness, cushion depth (m)
NXS, NYS = 40, 2                 # slab quads: 0.5 x 0.25 m
NXC, NYC = 30, 6                 # cushion quads: 0.667 x 0.667 m (4 : 3 against the slab)
SLOPE = 1.4                      # 1 : 1.4
SLAB = (3.0e7, 0.2, 24.0)        # E (kPa), nu, unit weight (kN/m3)
CUSHION = (5.0e4, 0.3, 21.0)
MU = 0.5
X0, SMAX = 12.0, 0.05            # the base settles beyond x = X0, linearly to SMAX at x = L
XW = 12.0                        # water on the slab up to x = XW
GAMMAW = 9.81
NINC = 10
PENALTY = 1.0e8                  # CalculiX pressure-overclosure slope K (kPa/m)
STICK = 1.0e6                    # CalculiX stick slope lambda (kPa/m)
FORCE_RTOL = 0.01
OPEN_GAP = 1.0e-4                # m: 5 times the node-to-face distance of the closed part
ELEMENT = L / NXS                # the opened lengths' tolerance: one slab element
SIN = 1.0 / math.hypot(1.0, SLOPE)
COS = SLOPE / math.hypot(1.0, SLOPE)


def grid(x0, y0, w, h, nx, ny, first):
    """Nodes row by row and CCW quads of a block whose first node is number `first`."""
    xy = [(x0 + w * i / nx, y0 + h * j / ny) for j in range(ny + 1) for i in range(nx + 1)]
    conn = [(n, n + 1, n + nx + 2, n + nx + 1) for j in range(ny) for i in range(nx)
            for n in [first + j * (nx + 1) + i]]
    return xy, conn


def mesh():
    """Nodes (cushion row by row, then the slab), CCW quads, and the sets the decks need."""
    xy, conn = grid(0.0, -H, L, H, NXC, NYC, 1)
    nc, ecs = len(xy), len(conn)
    sxy, sconn = grid(0.0, 0.0, L, T, NXS, NYS, nc + 1)
    return dict(
        xy=np.array(xy + sxy), conn=conn + sconn, mat=[2] * ecs + [1] * len(sconn), ecs=ecs,
        cushion_base=list(range(1, NXC + 2)),
        cushion_toe=[j * (NXC + 1) + 1 for j in range(1, NYC + 1)],
        slab_toe=[nc + j * (NXS + 1) + 1 for j in range(NYS + 1)],
        slab_bottom_elems=[ecs + i + 1 for i in range(NXS)],                 # face 1
        slab_top_elems=[ecs + (NYS - 1) * NXS + i + 1 for i in range(NXS)],  # face 3
        cushion_top_elems=[(NYC - 1) * NXC + i + 1 for i in range(NXC)],     # face 3
        slab_bottom_nodes=[nc + i + 1 for i in range(NXS + 1)],
        cushion_top_nodes=[NYC * (NXC + 1) + i + 1 for i in range(NXC + 1)])


def settlement(x):
    """Prescribed (ux, uy) of a base node: vertical settlement s(x) seen in the slope's frame."""
    s = SMAX * max(0.0, (x - X0) / (L - X0))
    return -s * SIN, -s * COS


def water_faces(m):
    """(element, pressure) on the slab's outer faces below the water: GAMMAW (XW - x) sin t
    at each face's middle, uniform over the face (the same in both decks)."""
    return [(e, GAMMAW * (XW - ELEMENT * (i + 0.5)) * SIN)
            for i, e in enumerate(m["slab_top_elems"]) if ELEMENT * (i + 0.5) < XW]


def slab_loads(m):
    """Resultant (fx, fy) of the loads on the slab: its weight and the water."""
    w = SLAB[2] * L * T
    return np.array([-w * SIN, -w * COS - sum(p * ELEMENT for _, p in water_faces(m))])


def write_cfrd(path, m, slab_type=""):
    out = ["TITLE     contact peer of CalculiX: slab on a settling cushion", "NODES"]
    out += [f"&{k}, , , {x!r}, {y!r}" for k, (x, y) in enumerate(m["xy"].tolist(), 1)]
    out += ["ELEMENTS"] + [f(e) + "".join(f(n) for n in c) + f(mt) + f(0) + f(1)
                           + a("SLAB" if mt == 1 else "CUSHION") + a(slab_type if mt == 1 else "")
                           for e, (c, mt) in enumerate(zip(m["conn"], m["mat"]), 1)]
    out += ["MATERIALS", "&1, ELASTIC, face slab", "&" + ", ".join(map(repr, SLAB)),
            "&2, ELASTIC, cushion", "&" + ", ".join(map(repr, CUSHION)), "BOUNDARY"]
    out += [f"&{n}, {n}, 1, 1, 1, {ux!r}, {uy!r}" for n in m["cushion_base"]
            for ux, uy in [settlement(float(m["xy"][n - 1][0]))]]
    out += [f"&{n}, {n}, 1, 1, 0" for n in m["cushion_toe"]]
    out += [f"&{n}, {n}, 1, 1, 1" for n in m["slab_toe"]]
    out += ["LOADS", f"&GRAVITY, ALL, {-SIN!r}, {-COS!r}"]
    out += [f"&PRESSURE, {e}, 3, {p!r}, {p!r}" for e, p in water_faces(m)]
    es, ec = m["slab_bottom_elems"], m["cushion_top_elems"]
    runner.write_deck(path, out + [
        "CONTACT", a("SURFACE") + a("SLABBOT") + f(es[0]) + f(1) + f(len(es) - 1) + f(1),
        a("SURFACE") + a("CUSHTOP") + f(ec[0]) + f(3) + f(len(ec) - 1) + f(1),
        f"&PAIR, SLABBOT, CUSHTOP, {MU!r}, 0.0, MORTAR",
        "STAGES", a("LOAD") + " " * 10 + f(NINC) + " " * 10 + "weight, water, settlement",
        "END"])


def write_ccx(path, m, penalty, stick):
    cr = ccx.real
    out = ["** contact peer of cfrd (tools/ccx_contact.py)"] + ccx.node_cards(m["xy"],
                                                                            nset="NALL")
    for name, keep in (("ECUSH", lambda e: e <= m["ecs"]), ("ESLAB", lambda e: e > m["ecs"])):
        numbers = [e for e in range(1, len(m["conn"]) + 1) if keep(e)]
        out += ccx.element_cards(name, [m["conn"][e - 1] for e in numbers], numbers)
    for name, key in (("NTOE", "slab_toe"), ("NCTOE", "cushion_toe"), ("NBASE", "cushion_base")):
        out += ccx.set_cards("NSET", name, m[key])
    out += ccx.material_cards("MSLAB", *SLAB, elset="ESLAB")
    out += ccx.material_cards("MCUSH", *CUSHION, elset="ECUSH")
    out += ["*SURFACE, NAME=SSLAB, TYPE=ELEMENT"] + [f"{e}, S1" for e in m["slab_bottom_elems"]]
    out += ["*SURFACE, NAME=SCUSH, TYPE=ELEMENT"] + [f"{e}, S3" for e in m["cushion_top_elems"]]
    out += ["*SURFACE INTERACTION, NAME=SI", "*SURFACE BEHAVIOR, PRESSURE-OVERCLOSURE=LINEAR",
            cr(penalty), "*FRICTION", f"{cr(MU)}, {cr(stick)}",
            "*CONTACT PAIR, INTERACTION=SI, TYPE=SURFACE TO SURFACE", "SSLAB, SCUSH",
            "*BOUNDARY", "NTOE, 1, 2", "NCTOE, 1, 1",
            "*STEP, INC=1000", "*STATIC, DIRECT", f"{1.0 / NINC!r}, 1.0",
            "*DLOAD", f"ECUSH, GRAV, {ccx.GRAVITY_G!r}, {cr(-SIN)}, {cr(-COS)}, 0.",
            f"ESLAB, GRAV, {ccx.GRAVITY_G!r}, {cr(-SIN)}, {cr(-COS)}, 0."]
    out += [f"{e}, P3, {cr(p)}" for e, p in water_faces(m)]
    out.append("*BOUNDARY")       # in the step: ramped with the loads
    for n in m["cushion_base"]:
        ux, uy = settlement(float(m["xy"][n - 1][0]))
        out += [f"{n}, 1, 1, {cr(ux)}", f"{n}, 2, 2, {cr(uy)}"]
    runner.write_deck(path, out + [
        "*NODE PRINT, NSET=NALL", "U", "*NODE PRINT, NSET=NTOE, TOTALS=YES", "RF",
        "*CONTACT PRINT, SLAVE=SSLAB, MASTER=SCUSH", "CF", "*END STEP"])


def gaps(xy, u, m):
    """Normal distance (open +) of each deformed slab-bottom node from the deformed cushion
    top (the polyline of its nodes): one measure for both programs' displacements."""
    top, bot = np.array(m["cushion_top_nodes"]) - 1, np.array(m["slab_bottom_nodes"]) - 1
    q, p = xy[top] + u[top], xy[bot] + u[bot]
    out = np.empty(len(p))
    for k, pt in enumerate(p):
        i = int(np.clip(np.searchsorted(q[:, 0], pt[0]) - 1, 0, len(q) - 2))
        t = (q[i + 1] - q[i]) / np.linalg.norm(q[i + 1] - q[i])
        out[k] = np.dot(pt - q[i], [-t[1], t[0]])
    return out


def open_zones(x, g, limit=OPEN_GAP):
    """The intervals of x where the piecewise-linear gap exceeds limit: [(start, end), ...]."""
    zones, start = [], None
    for k in range(len(x)):
        if g[k] > limit and start is None:
            start = x[0] if k == 0 else x[k - 1] + (x[k] - x[k - 1]) * \
                (limit - g[k - 1]) / (g[k] - g[k - 1])
        if g[k] <= limit and start is not None:
            zones.append((start, x[k - 1] + (x[k] - x[k - 1]) * (g[k - 1] - limit)
                          / (g[k - 1] - g[k])))
            start = None
    return zones + ([(start, x[-1])] if start is not None else [])


def toe_loads(m):
    """The external nodal loads on the toe nodes (CalculiX's RF includes them): a quarter of
    each adjacent slab rectangle's weight, half of an adjacent wet face's water force."""
    toe = set(m["slab_toe"])
    quarter = SLAB[2] * ELEMENT * (T / NYS) / 4.0
    f_ = sum(quarter * len(toe & set(m["conn"][e])) for e in range(m["ecs"], len(m["conn"])))
    fy = sum(p * ELEMENT / 2.0 * len(toe & set(m["conn"][e - 1][2:])) for e, p in water_faces(m))
    return np.array([-f_ * SIN, -f_ * COS - fy])


def run_case(cfrd, workdir, penalty=PENALTY, stick=STICK, slab_type=""):
    os.makedirs(workdir, exist_ok=True)
    m = mesh()
    deck = os.path.join(workdir, "contact.dat")
    write_cfrd(deck, m, slab_type)
    write_ccx(os.path.join(workdir, "contact_ccx.inp"), m, penalty, stick)
    run = runner.run(os.path.abspath(cfrd), os.path.abspath(deck), check=False)
    if run.returncode != 0:
        raise RuntimeError(f"cfrd exit {run.returncode}: {run.stderr.strip()[:300]}")
    ccx.run_ccx(workdir, "contact_ccx")
    with results.open_results(deck[:-4] + ".h5") as h5:
        st = results.last_stage(h5)
        toe = st["reaction"][...][np.array(m["slab_toe"]) - 1].sum(axis=0)
        a_ = dict(u=st["displacement"][...], force=-(slab_loads(m) + toe),
                  status=st["contact/status"][...], resid=float(st.attrs["max_residual"]))
    dat = os.path.join(workdir, "contact_ccx.dat")
    lines = open(dat).read().splitlines()
    sums = {}
    for k, line in enumerate(lines):
        for key, head in (("cf", "total surface force (fx,fy,fz)"),
                          ("rf", "total force (fx,fy,fz) for set NTOE")):
            if line.strip().startswith(head) or (key == "cf" and head in line):
                sums[key] = np.array([ccx.ffloat(v) for v in lines[k + 2].split()[:2]])
    if len(sums) < 2:
        raise ValueError(f"{dat}: no contact force (CF) or toe reaction block")
    # the slab's equilibrium with CalculiX's own toe reactions, against its CF
    b_ = dict(u=ccx.displacement_array(dat, len(m["xy"])), force=sums["cf"],
              balance=-(slab_loads(m) + sums["rf"] - toe_loads(m)))
    x = m["xy"][np.array(m["slab_bottom_nodes"]) - 1][:, 0]
    for r in (a_, b_):
        r["gap"] = gaps(m["xy"], r["u"], m)
        r["zones"] = open_zones(x, r["gap"])
    return a_, b_


def check_case(args):
    a_, b_ = run_case(args.cfrd, args.workdir, args.penalty, args.stick, args.slab_type)
    check = Checks("peer/ccx-contact")
    nstick, nslip = int((a_["status"] == 1).sum()), int((a_["status"] == 2).sum())
    closed = L - sum(e - s for s, e in a_["zones"])
    check("case", len(a_["zones"]) == 2 and closed > 5.0 and nstick > 0 and nslip > 0,
          f"cfrd open zones {', '.join(f'{s:.2f}-{e:.2f}' for s, e in a_['zones'])} m (gap >"
          f" {OPEN_GAP:g} m; widest {a_['gap'].max() * 1e3:.1f} mm), closed {closed:.2f} m,"
          f" {nstick} slave nodes stick, {nslip} slip (expected: two open zones, >5 m closed,"
          " both stick and slip)")
    for i, name in ((1, "normal"), (0, "tangential")):
        rel = abs(a_["force"][i] - b_["force"][i]) / abs(b_["force"][i])
        check(f"{name}-force", rel <= FORCE_RTOL, f"contact force on the slab "
              f"{a_['force'][i]:.3f} kN/m, CalculiX {b_['force'][i]:.3f} (CF; its toe reactions"
              f" give {b_['balance'][i]:.3f}): difference {rel:.2%} (tol {FORCE_RTOL:.0%}; K "
              f"{args.penalty:g} kPa/m, lambda {args.stick:g} kPa/m; cfrd residual"
              f" {a_['resid']:.1e})")
    if len(a_["zones"]) != len(b_["zones"]):
        check("opened-length", False, f"cfrd has {len(a_['zones'])} open zones, CalculiX"
              f" {len(b_['zones'])}: {a_['zones']} / {b_['zones']}")
    for (s1, e1), (s2, e2) in zip(a_["zones"], b_["zones"]) \
            if len(a_["zones"]) == len(b_["zones"]) else ():
        d = abs((e1 - s1) - (e2 - s2))
        check(f"opened-length {s1:.1f}-{e1:.1f} m", d <= ELEMENT, f"cfrd {e1 - s1:.3f} m, "
              f"CalculiX {e2 - s2:.3f} m ({s2:.3f}-{e2:.3f}): difference {d:.3f} m (tol one"
              f" slab element, {ELEMENT} m; gap > {OPEN_GAP:g} m)")
    return check.status


def penalty_study(args):
    """The resultants and opened lengths against CalculiX's K and lambda (docs/theory.md 14)."""
    print("K (kPa/m)  lambda     N cfrd    N ccx   dN      T cfrd    T ccx   dT     open cfrd"
          "  open ccx")
    for k, lam in ((1e7, 1e5), (1e7, 1e6), (1e8, 1e6), (1e8, 1e7), (1e9, 1e6), (1e9, 1e7)):
        a_, b_ = run_case(args.cfrd, args.workdir, k, lam, args.slab_type)
        la, lb = (sum(e - s for s, e in r["zones"]) for r in (a_, b_))
        d = (a_["force"] - b_["force"]) / np.abs(b_["force"])
        print(f"{k:9.0e} {lam:7.0e} {a_['force'][1]:9.3f} {b_['force'][1]:8.3f} {d[1]:+.2%}"
              f" {a_['force'][0]:9.3f} {b_['force'][0]:8.3f} {d[0]:+.2%} {la:8.3f} {lb:8.3f}")
    return 0


def main(argv=None):
    ap = parser(__doc__, cfrd=True, workdir="build/ccx-contact")
    ap.add_argument("--penalty", type=float, default=PENALTY,
                    help="CalculiX pressure-overclosure slope K, kPa/m")
    ap.add_argument("--stick", type=float, default=STICK,
                    help="CalculiX stick slope lambda, kPa/m")
    ap.add_argument("--slab-type", default="", choices=["", "Q4", "Q4S"],
                    help="cfrd's slab element (default blank: plain Q4, like CPE4)")
    ap.add_argument("--penalty-study", action="store_true")
    args = ap.parse_args(argv)
    if args.penalty_study:
        return penalty_study(args)
    check = Checks("peer")
    return check.guard("ccx-contact", check_case, args) or check.status


if __name__ == "__main__":
    sys.exit(main())
