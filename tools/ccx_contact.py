#!/usr/bin/env python3
"""CalculiX as the independent peer of frictional contact (issue 7, section 2).

  python3 tools/ccx_contact.py --cfrd bin/cfrd [--workdir DIR]
  python3 tools/ccx_contact.py --cfrd bin/cfrd --penalty-study     (the K, lambda table)

The case, in the frame of a 1 : 1.4 slope (x up the slope along the slab, y its outward
normal; gravity (-sin t, -cos t)): a concrete face slab 20 m x 0.5 m (E 3e7 kPa, nu 0.2,
24 kN/m3; 40 x 2 quads of 0.5 x 0.25 m) on a cushion block 20 m x 4 m (E 5e4 kPa, nu 0.3,
21 kN/m3; 30 x 6 quads of 0.667 m): meshes that do not match (4 : 3 along the interface,
nodes shared only at the ends). The slab's toe (its end face, 3 nodes) is held in x and y:
the plinth. The cushion's base is fixed up to x = 12 m and beyond settles vertically,
linearly to 0.05 m at x = 20 m; its face at the toe is on rollers. Water stands on the slab
up to x = 12 m (a uniform pressure per face, the hydrostatic value at the face's middle:
66 kPa at the toe). Weight, water and settlement grow together in 10 equal increments.
Coulomb friction mu = 0.5. The slab bridges over the cushion next to the plinth and above the
water: two open zones (0-2.8 m, 1.2 mm wide at the plinth; 14.2-20 m, 13 mm wide at the top)
around a closed part that slips down the slope, sticks near x = 12 m and slips up the slope
above it. The largest penetration CalculiX lets through is 6 micrometres (at a peak of
580 kPa at one integration point).

cfrd: CONTACT SURFACE / PAIR cards (slave = the slab's bottom faces, master = the cushion's
top; mortar, exact multipliers). CalculiX 2.20: the same mesh in CPE4, *CONTACT PAIR TYPE=
SURFACE TO SURFACE (face-to-face penalty), *SURFACE BEHAVIOR PRESSURE-OVERCLOSURE=LINEAR
with slope K = 1e8 kPa/m and *FRICTION 0.5 with stick slope lambda = 1e6 kPa/m (K / 100, the
manual's advice). The slab is in plain Q4 quads in cfrd (ELEMENTS TYPE blank), because
CalculiX's CPE4 is the plain fully integrated quad: both programs then have the same slab,
and the comparison measures the contact alone (cfrd's Q4S slab, which does not lock, carries
4 % more of the load on the cushion here: a difference of the element, not of the contact).

Asserted:
  - the resultant of the contact force on the slab, normal (y) and tangential (x), kN/m:
    within 1 % of CalculiX's (cfrd: the slab's loads minus its toe reactions, i.e. the force
    its contact multipliers apply, to the run's residual of 1e-11; CalculiX: *CONTACT PRINT
    CF, checked against its own toe reactions);
  - the opened lengths, where the gap exceeds 1e-4 m (the gap measured the same way for both
    programs, from their displacements: the normal distance of each deformed slab-bottom node
    from the deformed cushion top): the same open zones, each as long as CalculiX's within one
    slab element (0.5 m). 1e-4 m is 5 times the largest node-to-face distance in the closed
    part (2e-5 m, from the meshes not matching) and a tenth of the smaller opening.
  - that the case tests what it should: two open zones and a closed part, with nodes that
    stick and nodes that slip in cfrd's result.
"""
import argparse
import math
import os
import sys

import h5py
import numpy as np

import embankment as emb
from cfrdtools import results, runner
from cfrdtools.ccx import run_ccx

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
OPEN_GAP = 1.0e-4                # m
ELEMENT = L / NXS                # the opened lengths' tolerance: one slab element

SIN = 1.0 / math.hypot(1.0, SLOPE)
COS = SLOPE / math.hypot(1.0, SLOPE)


def mesh():
    """Nodes (cushion row by row, then the slab), CCW quads, and the sets the decks need."""
    xy, conn, mat = [], [], []
    for j in range(NYC + 1):
        for i in range(NXC + 1):
            xy.append((L * i / NXC, -H + H * j / NYC))
    nc = len(xy)
    for j in range(NYS + 1):
        for i in range(NXS + 1):
            xy.append((L * i / NXS, T * j / NYS))
    for j in range(NYC):
        for i in range(NXC):
            a = j * (NXC + 1) + i + 1
            conn.append((a, a + 1, a + NXC + 2, a + NXC + 1))
            mat.append(2)
    ecs = len(conn)
    for j in range(NYS):
        for i in range(NXS):
            a = nc + j * (NXS + 1) + i + 1
            conn.append((a, a + 1, a + NXS + 2, a + NXS + 1))
            mat.append(1)
    return dict(
        xy=np.array(xy), conn=conn, mat=mat, ecs=ecs,
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
    out = []
    for i, e in enumerate(m["slab_top_elems"]):
        xm = ELEMENT * (i + 0.5)
        if xm < XW:
            out.append((e, GAMMAW * (XW - xm) * SIN))
    return out


def slab_loads(m):
    """Resultant (fx, fy) of the loads on the slab: its weight and the water."""
    w = SLAB[2] * L * T
    return np.array([-w * SIN, -w * COS - sum(p * ELEMENT for _, p in water_faces(m))])


def write_cfrd(path, m, slab_type=""):
    f, a = emb.fmt_int, emb.fmt_alpha
    out = ["TITLE     contact peer of CalculiX: slab on a settling cushion",
           "NODES"]
    out += [f"&{k}, , , {x!r}, {y!r}" for k, (x, y) in enumerate(m["xy"].tolist(), 1)]
    out.append("ELEMENTS")
    for e, (c, mt) in enumerate(zip(m["conn"], m["mat"]), 1):
        out.append(f(e) + "".join(f(n) for n in c) + f(mt) + f(0) + f(1)
                   + a("SLAB" if mt == 1 else "CUSHION") + a(slab_type if mt == 1 else ""))
    out += ["MATERIALS", "&1, ELASTIC, face slab", "&" + ", ".join(map(repr, SLAB)),
            "&2, ELASTIC, cushion", "&" + ", ".join(map(repr, CUSHION)), "BOUNDARY"]
    for n in m["cushion_base"]:
        ux, uy = settlement(float(m["xy"][n - 1][0]))
        out.append(f"&{n}, {n}, 1, 1, 1, {ux!r}, {uy!r}")
    out += [f"&{n}, {n}, 1, 1, 0" for n in m["cushion_toe"]]
    out += [f"&{n}, {n}, 1, 1, 1" for n in m["slab_toe"]]
    out += ["LOADS", f"&GRAVITY, ALL, {-SIN!r}, {-COS!r}"]
    out += [f"&PRESSURE, {e}, 3, {p!r}, {p!r}" for e, p in water_faces(m)]
    es, ec = m["slab_bottom_elems"], m["cushion_top_elems"]
    out += ["CONTACT",
            a("SURFACE") + a("SLABBOT") + f(es[0]) + f(1) + f(len(es) - 1) + f(1),
            a("SURFACE") + a("CUSHTOP") + f(ec[0]) + f(3) + f(len(ec) - 1) + f(1),
            f"&PAIR, SLABBOT, CUSHTOP, {MU!r}, 0.0, MORTAR",
            "STAGES", a("LOAD") + " " * 10 + f(NINC) + " " * 10 + "weight, water, settlement",
            "END"]
    with open(path, "w") as fh:
        fh.write("\n".join(out) + "\n")


def write_ccx(path, m, penalty, stick):
    cr = emb.ccx_real
    out = ["** contact peer of cfrd (tools/ccx_contact.py)", "*NODE, NSET=NALL"]
    out += [f"{k}, {cr(x)}, {cr(y)}, 0.0" for k, (x, y) in enumerate(m["xy"].tolist(), 1)]
    for name, keep in (("ECUSH", lambda e: e <= m["ecs"]), ("ESLAB", lambda e: e > m["ecs"])):
        out.append(f"*ELEMENT, TYPE=CPE4, ELSET={name}")
        out += [f"{e}, {a}, {b}, {c}, {d}" for e, (a, b, c, d) in enumerate(m["conn"], 1)
                if keep(e)]

    def nset(name, nodes):
        out.append(f"*NSET, NSET={name}")
        out.extend(", ".join(map(str, nodes[i:i + 10])) for i in range(0, len(nodes), 10))

    nset("NTOE", m["slab_toe"])
    nset("NCTOE", m["cushion_toe"])
    nset("NBASE", m["cushion_base"])
    for name, (e, nu, g), elset in (("MSLAB", SLAB, "ESLAB"), ("MCUSH", CUSHION, "ECUSH")):
        out += [f"*MATERIAL, NAME={name}", "*ELASTIC", f"{cr(e)}, {cr(nu)}", "*DENSITY",
                cr(g / emb.GRAVITY_G), f"*SOLID SECTION, ELSET={elset}, MATERIAL={name}",
                "1.0"]
    out.append("*SURFACE, NAME=SSLAB, TYPE=ELEMENT")
    out += [f"{e}, S1" for e in m["slab_bottom_elems"]]
    out.append("*SURFACE, NAME=SCUSH, TYPE=ELEMENT")
    out += [f"{e}, S3" for e in m["cushion_top_elems"]]
    out += ["*SURFACE INTERACTION, NAME=SI", "*SURFACE BEHAVIOR, PRESSURE-OVERCLOSURE=LINEAR",
            cr(penalty), "*FRICTION", f"{cr(MU)}, {cr(stick)}",
            "*CONTACT PAIR, INTERACTION=SI, TYPE=SURFACE TO SURFACE", "SSLAB, SCUSH",
            "*BOUNDARY", "NTOE, 1, 2", "NCTOE, 1, 1",
            "*STEP, INC=1000", "*STATIC, DIRECT", f"{1.0 / NINC!r}, 1.0",
            "*DLOAD", f"ECUSH, GRAV, {emb.GRAVITY_G!r}, {cr(-SIN)}, {cr(-COS)}, 0.",
            f"ESLAB, GRAV, {emb.GRAVITY_G!r}, {cr(-SIN)}, {cr(-COS)}, 0."]
    out += [f"{e}, P3, {cr(p)}" for e, p in water_faces(m)]
    out.append("*BOUNDARY")       # in the step: ramped with the loads
    for n in m["cushion_base"]:
        ux, uy = settlement(float(m["xy"][n - 1][0]))
        out += [f"{n}, 1, 1, {cr(ux)}", f"{n}, 2, 2, {cr(uy)}"]
    out += ["*NODE PRINT, NSET=NALL", "U", "*NODE PRINT, NSET=NTOE, TOTALS=YES", "RF",
            "*CONTACT PRINT, SLAVE=SSLAB, MASTER=SCUSH", "CF", "*END STEP"]
    with open(path, "w") as fh:
        fh.write("\n".join(out) + "\n")


def gaps(xy, u, m):
    """Normal distance (open +) of each deformed slab-bottom node from the deformed cushion top
    (the polyline of its nodes): one measure for both programs' displacements."""
    top = np.array(m["cushion_top_nodes"]) - 1
    bot = np.array(m["slab_bottom_nodes"]) - 1
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
    if start is not None:
        zones.append((start, x[-1]))
    return zones


def read_cfrd(h5path, m):
    with h5py.File(h5path, "r") as f:
        st = results.last_stage(f)
        u, r = st["displacement"][...], st["reaction"][...]
        status = st["contact/status"][...]
        resid = float(st.attrs["max_residual"])
    toe = r[np.array(m["slab_toe"]) - 1].sum(axis=0)
    return dict(u=u, force=-(slab_loads(m) + toe), status=status, resid=resid)


def toe_loads(m):
    """The external nodal loads on the toe nodes (CalculiX's RF includes them): a quarter of
    each adjacent slab rectangle's weight, half of an adjacent wet face's water force."""
    toe = set(m["slab_toe"])
    f = np.zeros(2)
    quarter = SLAB[2] * ELEMENT * (T / NYS) / 4.0
    for e in range(m["ecs"], len(m["conn"])):
        f += quarter * len(toe & set(m["conn"][e])) * np.array([-SIN, -COS])
    for e, p in water_faces(m):
        a, b, c, d = m["conn"][e - 1]
        f[1] -= p * ELEMENT / 2.0 * len(toe & {c, d})
    return f


def read_ccx(dat, m):
    u = emb.ccx_displacement_array(dat, len(m["xy"]))
    lines = open(dat).read().splitlines()
    cf = rf = None
    for k, line in enumerate(lines):
        if "total surface force (fx,fy,fz)" in line:
            cf = np.array([emb._ffloat(v) for v in lines[k + 2].split()[:2]])
        if line.strip().startswith("total force (fx,fy,fz) for set NTOE"):
            rf = np.array([emb._ffloat(v) for v in lines[k + 2].split()[:2]])
    if cf is None or rf is None:
        raise ValueError(f"{dat}: no contact force (CF) or toe reaction block")
    # the slab's equilibrium with CalculiX's own toe reactions, against its CF
    balance = -(slab_loads(m) + rf - toe_loads(m))
    return dict(u=u, force=cf, balance=balance)


def run_case(cfrd, workdir, penalty=PENALTY, stick=STICK, slab_type=""):
    os.makedirs(workdir, exist_ok=True)
    m = mesh()
    deck = os.path.join(workdir, "contact.dat")
    write_cfrd(deck, m, slab_type)
    write_ccx(os.path.join(workdir, "contact_ccx.inp"), m, penalty, stick)
    run = runner.run(os.path.abspath(cfrd), os.path.abspath(deck), check=False)
    if run.returncode != 0:
        raise RuntimeError(f"cfrd exit {run.returncode}: {run.stderr.strip()[:300]}")
    run_ccx(workdir, "contact_ccx")
    a = read_cfrd(deck[:-4] + ".h5", m)
    b = read_ccx(os.path.join(workdir, "contact_ccx.dat"), m)
    x = m["xy"][np.array(m["slab_bottom_nodes"]) - 1][:, 0]
    for r in (a, b):
        r["gap"] = gaps(m["xy"], r["u"], m)
        r["zones"] = open_zones(x, r["gap"])
    return a, b


def check(args):
    a, b = run_case(args.cfrd, args.workdir, args.penalty, args.stick, args.slab_type)
    ok = True

    def verdict(good, text):
        nonlocal ok
        ok &= bool(good)
        print(("PASS" if good else "FAIL") + " peer/ccx-contact/" + text)

    nstick, nslip = int((a["status"] == 1).sum()), int((a["status"] == 2).sum())
    closed = L - sum(e - s for s, e in a["zones"])
    verdict(len(a["zones"]) == 2 and closed > 5.0 and nstick > 0 and nslip > 0,
            f"case: cfrd open zones {', '.join(f'{s:.2f}-{e:.2f}' for s, e in a['zones'])} m"
            f" (gap > {OPEN_GAP:g} m; widest {a['gap'].max() * 1e3:.1f} mm), closed"
            f" {closed:.2f} m, {nstick} slave nodes stick, {nslip} slip (expected: two open"
            f" zones, >5 m closed, both stick and slip)")
    for i, name in ((1, "normal"), (0, "tangential")):
        rel = abs(a["force"][i] - b["force"][i]) / abs(b["force"][i])
        verdict(rel <= FORCE_RTOL,
                f"{name}-force: contact force on the slab {a['force'][i]:.3f} kN/m, CalculiX"
                f" {b['force'][i]:.3f} (CF; its toe reactions give {b['balance'][i]:.3f}):"
                f" difference {rel:.2%} (tol {FORCE_RTOL:.0%}; K {args.penalty:g} kPa/m,"
                f" lambda {args.stick:g} kPa/m; cfrd residual {a['resid']:.1e})")
    if len(a["zones"]) != len(b["zones"]):
        verdict(False, f"opened-length: cfrd has {len(a['zones'])} open zones, CalculiX"
                f" {len(b['zones'])}: {a['zones']} / {b['zones']}")
    else:
        for (s1, e1), (s2, e2) in zip(a["zones"], b["zones"]):
            d = abs((e1 - s1) - (e2 - s2))
            verdict(d <= ELEMENT,
                    f"opened-length {s1:.1f}-{e1:.1f} m: cfrd {e1 - s1:.3f} m, CalculiX"
                    f" {e2 - s2:.3f} m ({s2:.3f}-{e2:.3f}): difference {d:.3f} m (tol one"
                    f" slab element, {ELEMENT} m; gap > {OPEN_GAP:g} m)")
    return 0 if ok else 1


def penalty_study(args):
    """The resultants and opened lengths against CalculiX's K and lambda (docs/theory.md 14)."""
    print("K (kPa/m)  lambda     N cfrd    N ccx   dN      T cfrd    T ccx   dT     open cfrd"
          "  open ccx")
    for k, lam in ((1e7, 1e5), (1e7, 1e6), (1e8, 1e6), (1e8, 1e7), (1e9, 1e6), (1e9, 1e7)):
        a, b = run_case(args.cfrd, args.workdir, k, lam, args.slab_type)
        la = sum(e - s for s, e in a["zones"])
        lb = sum(e - s for s, e in b["zones"])
        d = (a["force"] - b["force"]) / np.abs(b["force"])
        print(f"{k:9.0e} {lam:7.0e} {a['force'][1]:9.3f} {b['force'][1]:8.3f} {d[1]:+.2%}"
              f" {a['force'][0]:9.3f} {b['force'][0]:8.3f} {d[0]:+.2%} {la:8.3f} {lb:8.3f}")
    return 0


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--cfrd", required=True)
    parser.add_argument("--workdir", default="build/ccx-contact")
    parser.add_argument("--penalty", type=float, default=PENALTY,
                        help="CalculiX pressure-overclosure slope K, kPa/m")
    parser.add_argument("--stick", type=float, default=STICK,
                        help="CalculiX stick slope lambda, kPa/m")
    parser.add_argument("--slab-type", default="", choices=["", "Q4", "Q4S"],
                        help="cfrd's slab element (default blank: plain Q4, like CPE4)")
    parser.add_argument("--penalty-study", action="store_true")
    args = parser.parse_args(argv)
    if args.penalty_study:
        return penalty_study(args)
    try:
        return check(args)
    except Exception as exc:  # noqa: BLE001 - one verdict line whatever failed
        print(f"FAIL peer/ccx-contact: {type(exc).__name__}: {exc}")
        return 1


if __name__ == "__main__":
    sys.exit(main())
