#!/usr/bin/env python3
"""Checks of the rockfill creep law in cfrd (issue 19; docs/theory.md section 15), each against
a reference computed here without cfrd code:

  closed-form  one axisymmetric element in a triaxial state (cell pressure, then a deviator),
               then years of WAIT: the stresses are fixed by the loads, so the axial and
               radial creep strains follow eps_f (1 - exp(-alpha t)) with
               axial = eps_vf/3 + eps_sf, radial = eps_vf/3 - eps_sf/2 (0.5 %);
  order        one plane-strain element under a fixed vertical stress with its sides held
               (oedometer): creep changes the horizontal stresses, so the final strains move
               with time; the settlement after one year for 1, 2, 4, ... time steps against
               scipy's integration of the same ODE, and the observed order of the error;
  column       a column of five layers placed a month apart, then two years: the settlement
               of the top of the first layer and of the column's top at every stage against
               scipy's integration of the law on each layer (1 %);
  wetting      the same triaxial element wetted (WETTING card, WET stage in 4 increments):
               axial strain CW (s3/pa)^NW / 3 + DW S/(1-S), volumetric CW (s3/pa)^NW (0.5 %);
  wet-level    a held column of two layers wetted below the level between them: the upper
               layer's stresses and strains do not change (1e-9 of the collapse).

  python3 tools/check_creep.py --cfrd bin/cfrd --workdir build/creep   (PASS/FAIL lines)
"""

import argparse
import math
import os
import sys

import numpy as np
from scipy.integrate import solve_ivp

from cfrdtools.results import open_results, stages
from cfrdtools.runner import run_text

PA = 101.325
NU_MAX = 0.49
LEVEL_CAP = 0.99
# IIIB of the paper's Table 3: K, n, Rf, Kb, m, phi0, dphi
EB = dict(k=564.0, n=0.35, rf=0.85, kb=204.0, m=0.18, phi0=51.0, dphi=13.0)
# Test parameters of the creep law (not a dam's): alpha 1/day, b, mc, d, l
CREEP = dict(alpha=0.01, b=0.003, mc=0.5, d=0.005, l=0.8)
# Test parameters of the wetting model (not a dam's): CW, NW, DW
WETTING = dict(cw=0.003, nw=0.6, dw=0.004)
FLOOR = 0.1 * PA


# --------------------------------------------------------------------------------------
# The law, written again from docs/theory.md (sections 8 and 15)
# --------------------------------------------------------------------------------------

def principal_in_plane(sx, sy, sxy):
    """In-plane principal stresses, compression positive (FE stresses tension positive)."""
    centre = -0.5 * (sx + sy)
    radius = math.hypot(0.5 * (sx - sy), sxy)
    return centre + radius, centre - radius


def failure_deviator(s3):
    s3 = max(s3, FLOOR)
    phi = math.radians(min(max(EB["phi0"] - EB["dphi"] * math.log10(s3 / PA), 1.0), 89.0))
    return 2.0 * s3 * math.sin(phi) / (1.0 - math.sin(phi))


def level(sx, sy, sxy):
    s1, s3 = principal_in_plane(sx, sy, sxy)
    return min(max((s1 - s3) / failure_deviator(s3), 0.0), LEVEL_CAP), s3


def tangent(sx, sy, sxy):
    """E-B loading tangent (no unloading: EFFECTS UNLOAD OFF), 4x4, FE order xx yy zz xy."""
    lev, s3 = level(sx, sy, sxy)
    s3 = max(s3, FLOOR)
    et = EB["k"] * PA * (s3 / PA) ** EB["n"] * (1.0 - EB["rf"] * lev) ** 2
    bt = EB["kb"] * PA * (s3 / PA) ** EB["m"]
    bt = min(max(bt, et / 3.0), et / (3.0 * (1.0 - 2.0 * NU_MAX)))
    nu = (3.0 * bt - et) / (6.0 * bt)
    c = et / ((1.0 + nu) * (1.0 - 2.0 * nu))
    d = np.zeros((4, 4))
    d[:3, :3] = c * nu
    for i in range(3):
        d[i, i] = c * (1.0 - nu)
    d[3, 3] = c * (1.0 - 2.0 * nu) / 2.0
    return d


def final_strains(sigma3, lev):
    ev = CREEP["b"] * (max(sigma3, 0.0) / PA) ** CREEP["mc"]
    s = min(max(lev, 0.0), 0.99)
    es = CREEP["d"] * (s / (1.0 - s)) ** CREEP["l"] if s > 0.0 else 0.0
    return ev, es


def creep_rate(stress, ev, es):
    """d(creep strain)/dt (FE order and sign), d ev/dt, d es/dt at a stress."""
    lev, s3 = level(stress[0], stress[1], stress[3])
    evf, esf = final_strains(s3, lev)
    dev = CREEP["alpha"] * max(evf - ev, 0.0)
    des = CREEP["alpha"] * max(esf - es, 0.0)
    rate = np.zeros(4)
    rate[:3] = -dev / 3.0
    mean = stress[:3].mean()
    s = np.array([stress[0] - mean, stress[1] - mean, stress[2] - mean, stress[3]])
    q = math.sqrt(1.5 * (s[0] ** 2 + s[1] ** 2 + s[2] ** 2 + 2.0 * s[3] ** 2))
    if q > 0.0 and des > 0.0:
        rate[:3] += 1.5 * des * s[:3] / q
        rate[3] = 3.0 * des * s[3] / q
    return rate, dev, des


def oedometer_rhs(sv_rate, with_creep):
    """ODE of one point held laterally (eps_x = eps_z = 0, no shear) under a vertical stress
    changing at sv_rate: y = (sx, sz, sy, eps_y, ev, es)."""
    def rhs(t, y):
        stress = np.array([y[0], y[2], y[1], 0.0])
        d = tangent(stress[0], stress[1], stress[3])
        if with_creep:
            c, dev, des = creep_rate(stress, y[4], y[5])
        else:
            c, dev, des = np.zeros(4), 0.0, 0.0
        dc = d @ c
        # sigma_y' = D_yy eps_y' - (D c)_y = sv_rate
        ey = (sv_rate + dc[1]) / d[1, 1]
        sx = d[0, 1] * ey - dc[0]
        sz = d[2, 1] * ey - dc[2]
        return [sx, sz, sv_rate, ey, dev, des]
    return rhs


def integrate(y, t0, t1, sv_rate, with_creep=True):
    if t1 <= t0:
        return y
    sol = solve_ivp(oedometer_rhs(sv_rate, with_creep), (t0, t1), y, rtol=1e-10,
                    atol=1e-13, method="LSODA")
    return sol.y[:, -1]


# --------------------------------------------------------------------------------------
# Decks and runs
# --------------------------------------------------------------------------------------

def creep_card():
    return "&CREEP, " + ", ".join(repr(CREEP[k]) for k in ("alpha", "b", "mc", "d", "l"))


def eb_cards(gamma):
    return [f"&{gamma!r}, {EB['k']!r}, {EB['n']!r}, {EB['rf']!r}, {EB['kb']!r}, {EB['m']!r}",
            f"&{EB['phi0']!r}, {EB['dphi']!r}", creep_card()]


def run(cfrd, path, text):
    """Write and run a deck (cfrdtools); its results file, open."""
    return open_results(run_text(cfrd, path, text))


def check_closed_form(cfrd, workdir, tol=5e-3):
    cell, dev = 400.0, 600.0
    deck = "\n".join([
        "TITLE     one axisymmetric element: triaxial creep",
        "CONTROL", "&4, 1, 1, 2",
        "NODES", "&1, 2, 1, 0.0, 0.0, 1.0, 0.0", "&3, 4, 1, 1.0, 1.0, 0.0, 1.0",
        "ELEMENTS", "&1, 1, 2, 3, 4, 1",
        "MATERIALS", "&1, EB, test rockfill"] + eb_cards(0.0) + [
        "BOUNDARY", "&1, , , 1, 1", "&2, , , 0, 1", "&4, , , 1, 0",
        "LOADS", f"&PRESSURE, 1, 2, {cell!r}", f"&PRESSURE, 1, 3, {cell!r}",
        "LOADS     SHEAR", f"&PRESSURE, 1, 3, {dev!r}",
        "STAGES",
        "&LOAD, , 50, 2000-01-01, cell pressure",
        "&LOAD, SHEAR, 50, 2000-01-01, deviator",
        "&WAIT, , 5, 2000-01-11", "&WAIT, , 5, 2000-04-10", "&WAIT, , 10, 2001-01-01",
        "&WAIT, , 10, 2004-01-01", "END"]) + "\n"
    with run(cfrd, os.path.join(workdir, "triaxial.dat"), deck) as f:
        st = stages(f)
        t0 = st[1].attrs["day"]
        u0 = st[1]["displacement_total"][...]
        lev, s3 = level(-cell, -(cell + dev), 0.0)
        evf, esf = final_strains(s3, lev)
        worst = radial_err = 0.0
        for g in st[2:]:
            decay = 1.0 - math.exp(-CREEP["alpha"] * (g.attrs["day"] - t0))
            u = g["displacement_total"][...] - u0
            axial, radial = -u[2, 1], -u[1, 0]        # node 3 (1, 1), node 2 (1, 0)
            for got, want in ((axial, (evf / 3 + esf) * decay),
                              (axial + 2.0 * radial, evf * decay)):
                worst = max(worst, abs(got - want) / abs(want))
            radial_err = max(radial_err, abs(radial - (evf / 3 - esf / 2) * decay)
                             / ((evf / 3 + esf) * decay))
    ok = worst <= tol
    print(f"{'PASS' if ok else 'FAIL'} creep/closed-form: triaxial element (sigma3 {cell:g},"
          f" q {dev:g} kPa, S {lev:.3f}): axial and volumetric creep strain at 10 d .. 4 years,"
          f" max rel. error {worst:.1e} against eps_f (1 - exp(-alpha t)) (tol {tol:g});"
          f" radial strain within {radial_err:.1e} of the axial")
    return ok


def oedometer_deck(ninc):
    return "\n".join([
        "TITLE     one plane-strain element held laterally: creep under a fixed load",
        "* Newton to 1e-12, so that what is left is the error of the time steps",
        "CONTROL", "&4, 1, 1, 1, , , , 0, 3, 1e-12, 50",
        "&EFFECTS, , OFF",
        "NODES", "&1, 2, 1, 0.0, 0.0, 1.0, 0.0", "&3, 4, 1, 1.0, 1.0, 0.0, 1.0",
        "ELEMENTS", "&1, 1, 2, 3, 4, 1",
        "MATERIALS", "&1, EB, test rockfill"] + eb_cards(0.0) + [
        "BOUNDARY", "&1, 4, 1, 1, 0", "&1, 2, 1, 1, 1",
        "LOADS", "&PRESSURE, 1, 3, 1000.0",
        "STAGES",
        "&LOAD, , 4000, 2000-01-01, vertical stress",
        f"&WAIT, , {ninc}, 2000-12-31", "END"]) + "\n"


def oedometer_reference():
    y = np.zeros(6)
    # the load, with no time: a pseudo-time of 1 day and no creep
    y = integrate(y, 0.0, 1.0, -1000.0, with_creep=False)
    y1 = integrate(y, 0.0, 365.0, 0.0)
    return -(y1[3] - y[3])


def check_order(cfrd, workdir):
    ref = oedometer_reference()
    errors = []
    counts = (1, 2, 4, 8, 16, 32)
    for n in counts:
        with run(cfrd, os.path.join(workdir, f"oedometer-{n}.dat"), oedometer_deck(n)) as f:
            st = stages(f)
            settle = -(st[1]["displacement_total"][2, 1] - st[0]["displacement_total"][2, 1])
        errors.append((settle - ref) / ref)
    orders = [math.log2(abs(errors[i] / errors[i + 1])) for i in range(len(errors) - 1)]
    ok = 0.8 <= orders[-1] <= 1.3 and abs(errors[-1]) < 2e-3
    print(f"{'PASS' if ok else 'FAIL'} creep/time-step-order: oedometer creep settlement over"
          f" one year ({ref * 1000:.4f} mm, scipy LSODA), errors "
          + ", ".join(f"{e:+.1e}" for e in errors) + f" for {counts} steps: order "
          + ", ".join(f"{p:.2f}" for p in orders) + " (first order expected; tol 0.8-1.3,"
          " error at 32 steps < 2e-3)")
    return ok


COLUMN_LAYERS = 5
LAYER_H = 2.0
GAMMA = 200.0          # kN/m3: test loads of a 100 m column in a 10 m one
FILL_DAYS = [0, 30, 60, 91, 121]          # from 2000-01-01
WAITS = [(181, 12), (365, 12), (730, 24)]


def column_deck(ninc_fill):
    import datetime
    day = lambda k: (datetime.date(2000, 1, 1) + datetime.timedelta(days=k)).isoformat()
    rows = COLUMN_LAYERS + 1
    lines = ["TITLE     layered column with creep",
             "CONTROL", f"&{2 * rows}, {COLUMN_LAYERS}, 1, 1",
             "&EFFECTS, , OFF",
             "NODES", f"&1, {2 * rows - 1}, 2, 0.0, 0.0, 0.0, {LAYER_H * COLUMN_LAYERS!r}",
             f"&2, {2 * rows}, 2, 1.0, 0.0, 1.0, {LAYER_H * COLUMN_LAYERS!r}",
             "ELEMENTS"]
    for e in range(1, COLUMN_LAYERS + 1):
        a = 2 * e - 1
        lines.append(f"&{e}, {a}, {a + 1}, {a + 3}, {a + 2}, 1, , , L{e}")
    lines += ["MATERIALS", "&1, EB, test rockfill"] + eb_cards(GAMMA)
    lines += ["BOUNDARY", f"&1, {2 * rows}, 1, 1, 0", "&1, 2, 1, 1, 1",
              "STAGES"]
    for e, d in enumerate(FILL_DAYS, 1):
        lines.append(f"&FILL, L{e}, {ninc_fill}, {day(d)}, layer {e}")
    for d, n in WAITS:
        lines.append(f"&WAIT, , {n * 4}, {day(d)}")
    lines.append("END")
    return "\n".join(lines) + "\n"


def column_reference():
    """Each layer's element as one point held laterally, its vertical stress the weight above
    its middle (the element's constant stress under consistent loads); loads ramp over each
    FILL stage's time span, the first stage's at once. Returns the settlement of the top
    of layer 1 (since its placement) and of the column's top (since the last layer's) at
    the end of every stage."""
    n = COLUMN_LAYERS
    state = [np.zeros(6) for _ in range(n)]
    eps_at = {}
    times = FILL_DAYS + [d for d, _ in WAITS]
    out = []
    for k, t in enumerate(times):
        t_prev = times[k - 1] if k > 0 else t
        for e in range(n):
            if e > k:
                continue
            # vertical stress added to element e during stage k (FILL k+1), kPa
            if k < n:
                add = GAMMA * LAYER_H * (0.5 if e == k else 1.0)
            else:
                add = 0.0
            if k == 0 or t == t_prev:
                state[e] = integrate(state[e], 0.0, 1.0, -add, with_creep=False)
            else:
                state[e] = integrate(state[e], t_prev, t, -add / (t - t_prev))
        eps_at[k] = [state[e][3] for e in range(n)]
        s1 = -LAYER_H * (eps_at[k][0] - eps_at[0][0])
        top = (-LAYER_H * sum(eps_at[k][e] - eps_at[n - 1][e] for e in range(n))
               if k >= n - 1 else 0.0)
        out.append((s1, top))
    return out


def check_column(cfrd, workdir, tol=1e-2):
    ref = column_reference()
    with run(cfrd, os.path.join(workdir, "column.dat"), column_deck(32)) as f:
        st = stages(f)
        got = []
        last = COLUMN_LAYERS - 1
        for k, g in enumerate(st):
            u = g["displacement_total"][...]
            s1 = -u[2, 1]                                  # node 3: top of layer 1
            top = -(u[-2, 1] - st[last]["displacement_total"][-2, 1]) if k >= last else 0.0
            got.append((s1, top))
    worst = 0.0
    for (a, b), (c, d) in zip(got, ref):
        worst = max(worst, abs(a - c) / max(abs(c), 1e-12))
        if abs(d) > 0:
            worst = max(worst, abs(b - d) / abs(d))
    ok = worst <= tol
    print(f"{'PASS' if ok else 'FAIL'} creep/layered-column: 5 layers a month apart, then 2"
          f" years: settlement of layer 1's top ({got[-1][0] * 1000:.2f} mm) and of the top"
          f" since completion ({got[-1][1] * 1000:.2f} mm) at all {len(got)} stages, max rel."
          f" error {worst:.1e} against scipy's integration per layer (tol {tol:g})")
    return ok


def check_contact(cfrd, workdir, tol=5e-3):
    """A stiff slab cast in contact on a creeping block (held laterally, linear E-B: EFFECTS
    ROCKFILL LINEAR, volumetric creep only with MC = 0.001) and pressed by 500 kPa: the
    contact stays closed and the slab settles with the block, by H (1 + nu)/(3 (1 - nu))
    eps_v(t) (the creep compaction of a held block whose vertical stress the load fixes),
    and the contact pressure stays the load (statics)."""
    q, mc = 500.0, 0.001
    k, kb = EB["k"], EB["kb"]
    e, b = k * PA, max(kb * PA, k * PA / 3.0)
    nu = (3.0 * b - e) / (6.0 * b)
    p_contact = q + 24.0 * 0.2
    sigma3 = nu / (1.0 - nu) * p_contact
    ev_final = CREEP["b"] * (sigma3 / PA) ** mc
    deck = "\n".join([
        "TITLE     a slab cast on a creeping block",
        "CONTROL", "&12, 4, 2, 1",
        "&EFFECTS, LINEAR",
        "NODES", "&1, 3, 1, 0.0, 0.0, 2.0, 0.0", "&4, 6, 1, 0.0, 1.0, 2.0, 1.0",
        "&7, 9, 1, 0.0, 1.0, 2.0, 1.0", "&10, 12, 1, 0.0, 1.2, 2.0, 1.2",
        "ELEMENTS", "&1, 1, 2, 5, 4, 1, 1, 1", "&3, 7, 8, 11, 10, 2, 1, 1, SLAB",
        "MATERIALS", "&1, EB, creeping block",
        f"&0.0, {k!r}, {EB['n']!r}, {EB['rf']!r}, {kb!r}, {EB['m']!r}",
        f"&{EB['phi0']!r}, {EB['dphi']!r}",
        f"&CREEP, {CREEP['alpha']!r}, {CREEP['b']!r}, {mc!r}, 0.0, 1.0",
        "&2, ELASTIC, slab", "&3.0e7, 0.2, 24.0",
        "CONTACT", "&SURFACE, SLAB, 3, 1, 1, 1", "&SURFACE, BLOCK, 1, 3, 1, 1",
        "&PAIR, SLAB, BLOCK, 0.5, , , , 1",
        "BOUNDARY", "&1, 3, 1, 1, 1", "&4, 12, 1, 1, 0",
        "LOADS", "&PRESSURE, 3, 3, 500.0", "&PRESSURE, 4, 3, 500.0",
        "STAGES", "&FILL, SLAB, 1, 2000-01-01, slab cast",
        "&LOAD, , 10, 2000-01-01, pressure on the slab",
        "&WAIT, , 10, 2000-04-10", "&WAIT, , 10, 2001-01-01", "&WAIT, , 10, 2004-01-01",
        "END"]) + "\n"
    with run(cfrd, os.path.join(workdir, "slab-on-block.dat"), deck) as f:
        st = stages(f)
        t0, u0 = st[1].attrs["day"], st[1]["displacement_total"][...]
        worst = worst_p = 0.0
        for g in st[2:]:
            want = (1.0 + nu) / (3.0 * (1.0 - nu)) * ev_final * (
                1.0 - math.exp(-CREEP["alpha"] * (g.attrs["day"] - t0)))
            u = g["displacement_total"][...] - u0
            for node in (9, 10, 11):                       # the slab's top nodes
                worst = max(worst, abs(-u[node, 1] - want) / want)
            c = g["contact"]
            sn = c["sigma_n"][...] if "sigma_n" in c else None
            if sn is not None:
                worst_p = max(worst_p, abs(np.mean(sn) + p_contact) / p_contact)
    ok = worst <= tol and worst_p <= 1e-2
    print(f"{'PASS' if ok else 'FAIL'} creep/contact-closed: slab cast on a creeping block:"
          f" its settlement from 10 days to 4 years within {worst:.1e} of"
          f" H (1+nu)/(3(1-nu)) eps_v(t) (tol {tol:g}), mean contact pressure within"
          f" {worst_p:.1e} of the load {p_contact:g} kPa (tol 1e-2)")
    return ok


def wetting_strains(sigma3, lev):
    """Shen's wetting model (docs/theory.md section 16): volumetric and shear collapse."""
    ev = WETTING["cw"] * (max(sigma3, FLOOR) / PA) ** WETTING["nw"]
    s = min(max(lev, 0.0), 0.99)
    return ev, WETTING["dw"] * s / (1.0 - s)


def wetting_card():
    return "&WETTING, " + ", ".join(repr(WETTING[k]) for k in ("cw", "nw", "dw"))


def check_wetting(cfrd, workdir, tol=5e-3):
    """The triaxial element of check_closed_form wetted instead of creeping."""
    cell, dev = 400.0, 600.0
    cards = eb_cards(0.0)[:2] + [wetting_card()]
    deck = "\n".join([
        "TITLE     one axisymmetric element: triaxial wetting",
        "CONTROL", "&4, 1, 1, 2",
        "NODES", "&1, 2, 1, 0.0, 0.0, 1.0, 0.0", "&3, 4, 1, 1.0, 1.0, 0.0, 1.0",
        "ELEMENTS", "&1, 1, 2, 3, 4, 1",
        "MATERIALS", "&1, EB, test rockfill"] + cards + [
        "BOUNDARY", "&1, , , 1, 1", "&2, , , 0, 1", "&4, , , 1, 0",
        "LOADS", f"&PRESSURE, 1, 2, {cell!r}", f"&PRESSURE, 1, 3, {cell!r}",
        "LOADS     SHEAR", f"&PRESSURE, 1, 3, {dev!r}",
        "STAGES",
        "&LOAD, , 50, , cell pressure",
        "&LOAD, SHEAR, 50, , deviator",
        "&WET, , 4, , flooded", "END"]) + "\n"
    with run(cfrd, os.path.join(workdir, "triaxial-wet.dat"), deck) as f:
        st = stages(f)
        u = st[2]["displacement_total"][...] - st[1]["displacement_total"][...]
        stored = st[2]["wetting_gauss"][...]
    axial, radial = -u[2, 1], -u[1, 0]
    lev, s3 = level(-cell, -(cell + dev), 0.0)
    evw, esw = wetting_strains(s3, lev)
    errors = [abs(axial - (evw / 3 + esw)) / (evw / 3 + esw),
              abs(axial + 2.0 * radial - evw) / evw,
              float(np.max(np.abs(stored[0, :, 0] - evw))) / evw,     # (element, point,
              float(np.max(np.abs(stored[0, :, 1] - esw))) / esw]     # component)
    worst = max(errors)
    ok = worst <= tol
    print(f"{'PASS' if ok else 'FAIL'} creep/wetting: triaxial element (sigma3 {cell:g},"
          f" q {dev:g} kPa, S {lev:.3f}) wetted in 4 increments: axial and volumetric strain"
          f" and the stored wetting strains, max rel. error {worst:.1e} against"
          f" CW (s3/pa)^NW = {evw:.3e}, DW S/(1-S) = {esw:.3e} (tol {tol:g})")
    return ok


def check_wet_level(cfrd, workdir, tol=1e-9):
    """Two layers of a laterally held column; WET below the level between them."""
    cards = eb_cards(20.0)[:2] + [wetting_card()]
    deck = "\n".join([
        "TITLE     held column of two layers, the lower one wetted",
        "CONTROL", "&6, 2, 1, 1, , , , , 3, 1e-11",
        "NODES", "&1, 5, 2, 0.0, 0.0, 0.0, 10.0", "&2, 6, 2, 1.0, 0.0, 1.0, 10.0",
        "ELEMENTS", "&1, 1, 2, 4, 3, 1, , , LOWER", "&2, 3, 4, 6, 5, 1, , , UPPER",
        "MATERIALS", "&1, EB, test rockfill"] + cards + [
        "BOUNDARY", "&1, 6, 1, 1, 0", "&1, 2, 1, 1, 1",
        "STAGES", "&FILL, LOWER, 10", "&FILL, UPPER, 10",
        "&WET, 5.0, 4, , lower layer flooded", "END"]) + "\n"
    with run(cfrd, os.path.join(workdir, "column-wet.dat"), deck) as f:
        st = stages(f)
        s_before, s_after = st[1]["stress_gauss"][...], st[2]["stress_gauss"][...]
        w = st[2]["wetting_gauss"][...]
        u = st[2]["displacement_total"][...] - st[1]["displacement_total"][...]
    collapse = -u[2, 1]                                  # node 3, top of the lower layer
    upper_stress = float(np.max(np.abs(s_after[1] - s_before[1])))   # (element, point, comp)
    stretch = abs((u[4, 1] - u[2, 1]) / collapse)        # node 5 against node 3
    ok = (collapse > 0.0 and upper_stress <= tol * float(np.max(np.abs(s_before[1])))
          and stretch <= tol and float(np.max(np.abs(w[1]))) == 0.0
          and float(np.min(w[0, :, 0])) > 0.0)
    print(f"{'PASS' if ok else 'FAIL'} creep/wet-level: held column, WET below 5 m: the lower"
          f" layer collapses {collapse * 1e3:.2f} mm; the upper layer's stresses change by"
          f" {upper_stress:.1e} kPa, its height by {stretch:.1e} of the collapse, its wetting"
          f" strains {float(np.max(np.abs(w[1]))):g} (tol {tol:g})")
    return ok


def check_off(cfrd, workdir):
    """EFFECTS CREEP OFF (and a deck without CREEP cards): the results of a deck without creep,
    bit for bit, and no creep state stored."""
    deck = column_deck(4)
    off = deck.replace("&EFFECTS, , OFF", "&EFFECTS, , OFF, , , , , , OFF")
    bare = "\n".join(l for l in deck.split("\n") if not l.startswith("&CREEP"))
    with run(cfrd, os.path.join(workdir, "column-off.dat"), off) as a, \
            run(cfrd, os.path.join(workdir, "column-bare.dat"), bare) as b:
        sa, sb = stages(a), stages(b)
        same = len(sa) == len(sb) and all(
            np.array_equal(x[name][...], y[name][...]) for x, y in zip(sa, sb)
            for name in ("displacement_total", "stress_gauss"))
        stored = any("creep_gauss" in g for g in sa)
        effects = a.attrs["effects"].decode()
    ok = same and not stored and effects.endswith("CREEP OFF")
    print(f"{'PASS' if ok else 'FAIL'} creep/effects-off: the column with EFFECTS CREEP OFF"
          f" against the same deck without CREEP cards: {'bit-identical' if same else 'DIFFERENT'}"
          f" displacements and stresses at {len(sa)} stages, creep state stored: {stored},"
          f" effects attribute '{effects[-9:]}'")
    return ok


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--cfrd", required=True)
    ap.add_argument("--workdir", default="build/creep")
    a = ap.parse_args(argv)
    os.makedirs(a.workdir, exist_ok=True)
    ok = True
    for check in (check_closed_form, check_order, check_column, check_contact, check_off,
                  check_wetting, check_wet_level):
        try:
            ok &= check(a.cfrd, a.workdir)
        except Exception as exc:       # a run that fails is a failed check, with its reason
            print(f"FAIL creep/{check.__name__}: {exc}")
            ok = False
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
