#!/usr/bin/env python3
"""Checks of the rockfill creep and wetting laws in cfrd (issue 19; docs/theory.md sections
15 and 16), each against a reference computed here without cfrd code:

  closed-form    one axisymmetric element in a triaxial state, then years of WAIT: the axial
                 and radial creep strains follow eps_f (1 - exp(-alpha t)) (0.5 %);
  order          a plane-strain element held laterally under a fixed vertical stress: the
                 settlement after a year for 1, 2, 4, ... time steps against scipy's
                 integration of the same ODE, and the observed order of the error;
  column         five layers placed a month apart, then two years: the settlement of layer
                 1's top and of the column's top at every stage against scipy per layer (1 %);
  contact        a slab cast on a creeping block settles with it, the contact pressure the
                 load;
  effects-off    EFFECTS CREEP OFF: the results of the deck without CREEP cards, bit for bit;
  wetting        the triaxial element wetted (WET stage): axial strain CW (s3/pa)^NW / 3 +
                 DW S/(1-S), volumetric CW (s3/pa)^NW (0.5 %);
  wet-level      a held column of two layers wetted below the level between them: the upper
                 layer's stresses and strains do not change (1e-9 of the collapse).

  python3 tools/check_creep.py --cfrd bin/cfrd --workdir build/creep   (PASS/FAIL lines)
"""

import datetime
import math
import os
import sys

import numpy as np
from scipy.integrate import solve_ivp

from cfrdtools.checks import Checks, parser
from cfrdtools.decks import free
from cfrdtools.results import field, open_results, stages
from cfrdtools.runner import h5_of, run_text, write_deck
from cfrdtools.runner import run as run_cfrd

PA, NU_MAX, LEVEL_CAP = 101.325, 0.49, 0.99
FLOOR = 0.1 * PA
# IIIB of the paper's Table 3: K, n, Rf, Kb, m, phi0, dphi
EB = dict(k=564.0, n=0.35, rf=0.85, kb=204.0, m=0.18, phi0=51.0, dphi=13.0)
# Test parameters (not a dam's) of the creep law, alpha 1/day, and of the wetting model
CREEP = dict(alpha=0.01, b=0.003, mc=0.5, d=0.005, l=0.8)
WETTING = dict(cw=0.003, nw=0.6, dw=0.004)
check = Checks("creep")


# The law, written again from docs/theory.md (sections 8, 15 and 16)

def level(sx, sy, sxy):
    """E-B stress level and sigma3 (compression positive; FE stresses are tension positive)."""
    centre, radius = -0.5 * (sx + sy), math.hypot(0.5 * (sx - sy), sxy)
    s1, s3 = centre + radius, centre - radius
    phi = math.radians(min(max(EB["phi0"] - EB["dphi"] * math.log10(max(s3, FLOOR) / PA),
                               1.0), 89.0))
    qf = 2.0 * max(s3, FLOOR) * math.sin(phi) / (1.0 - math.sin(phi))
    return min(max((s1 - s3) / qf, 0.0), LEVEL_CAP), s3


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
    d[range(3), range(3)] = c * (1.0 - nu)
    d[3, 3] = c * (1.0 - 2.0 * nu) / 2.0
    return d


def final_strains(sigma3, lev):
    s = min(max(lev, 0.0), 0.99)
    return CREEP["b"] * (max(sigma3, 0.0) / PA) ** CREEP["mc"], \
        CREEP["d"] * (s / (1.0 - s)) ** CREEP["l"] if s > 0.0 else 0.0


def wetting_strains(sigma3, lev):
    """Shen's wetting model: volumetric and shear collapse."""
    s = min(max(lev, 0.0), 0.99)
    return WETTING["cw"] * (max(sigma3, FLOOR) / PA) ** WETTING["nw"], WETTING["dw"] * s / (1 - s)


def creep_rate(stress, ev, es):
    """d(creep strain)/dt (FE order and sign), d ev/dt, d es/dt at a stress."""
    evf, esf = final_strains(*reversed(level(stress[0], stress[1], stress[3])))
    dev, des = CREEP["alpha"] * max(evf - ev, 0.0), CREEP["alpha"] * max(esf - es, 0.0)
    rate = np.zeros(4)
    rate[:3] = -dev / 3.0
    s = np.append(stress[:3] - stress[:3].mean(), stress[3])
    q = math.sqrt(1.5 * (s[0] ** 2 + s[1] ** 2 + s[2] ** 2 + 2.0 * s[3] ** 2))
    if q > 0.0 and des > 0.0:
        rate[:3] += 1.5 * des * s[:3] / q
        rate[3] = 3.0 * des * s[3] / q
    return rate, dev, des


def integrate(y, t0, t1, sv_rate, with_creep=True):
    """One point held laterally (eps_x = eps_z = 0, no shear) under a vertical stress
    changing at sv_rate, from t0 to t1: y = (sx, sz, sy, eps_y, ev, es)."""
    def rhs(t, y):
        stress = np.array([y[0], y[2], y[1], 0.0])
        d = tangent(stress[0], stress[1], stress[3])
        c, dev, des = creep_rate(stress, y[4], y[5]) if with_creep else (np.zeros(4), 0.0, 0.0)
        dc = d @ c
        ey = (sv_rate + dc[1]) / d[1, 1]          # sigma_y' = D_yy eps_y' - (D c)_y = sv_rate
        return [d[0, 1] * ey - dc[0], d[2, 1] * ey - dc[2], sv_rate, ey, dev, des]
    if t1 <= t0:
        return y
    return solve_ivp(rhs, (t0, t1), y, rtol=1e-10, atol=1e-13, method="LSODA").y[:, -1]


# Decks and runs

def eb_cards(gamma, creep=True, wetting=False):
    return [free(gamma, *(EB[k] for k in ("k", "n", "rf", "kb", "m"))), free(EB["phi0"],
                                                                          EB["dphi"])] + \
        ([free("CREEP", *CREEP.values())] if creep else []) + \
        ([free("WETTING", *WETTING.values())] if wetting else [])


def run(cfrd, workdir, name, lines):
    """Write and run a deck (cfrdtools); its results file, open."""
    return open_results(run_text(cfrd, os.path.join(workdir, name), "\n".join(lines) + "\n"))


def triaxial_deck(title, cards, stages_):
    """One axisymmetric element: cell pressure 400 kPa, a deviator of 600 kPa, then stages."""
    return [f"TITLE     one axisymmetric element: {title}", "CONTROL", "&4, 1, 1, 2",
            "NODES", "&1, 2, 1, 0.0, 0.0, 1.0, 0.0", "&3, 4, 1, 1.0, 1.0, 0.0, 1.0",
            "ELEMENTS", "&1, 1, 2, 3, 4, 1", "MATERIALS", "&1, EB, test rockfill"] + cards + [
        "BOUNDARY", "&1, , , 1, 1", "&2, , , 0, 1", "&4, , , 1, 0",
        "LOADS", "&PRESSURE, 1, 2, 400.0", "&PRESSURE, 1, 3, 400.0",
        "LOADS     SHEAR", "&PRESSURE, 1, 3, 600.0", "STAGES"] + stages_ + ["END"]


def check_closed_form(cfrd, workdir, tol=5e-3):
    deck = triaxial_deck("triaxial creep", eb_cards(0.0), [
        "&LOAD, , 50, 2000-01-01, cell pressure", "&LOAD, SHEAR, 50, 2000-01-01, deviator",
        "&WAIT, , 5, 2000-01-11", "&WAIT, , 5, 2000-04-10", "&WAIT, , 10, 2001-01-01",
        "&WAIT, , 10, 2004-01-01"])
    with run(cfrd, workdir, "triaxial.dat", deck) as f:
        st = stages(f)
        t0, u0 = st[1].attrs["day"], field(st[1], "displacement_total")
        lev, s3 = level(-400.0, -1000.0, 0.0)
        evf, esf = final_strains(s3, lev)
        worst = radial_err = 0.0
        for g in st[2:]:
            decay = 1.0 - math.exp(-CREEP["alpha"] * (g.attrs["day"] - t0))
            u = field(g, "displacement_total") - u0
            axial, radial = -u[2, 1], -u[1, 0]        # node 3 (1, 1), node 2 (1, 0)
            worst = max(worst, *(abs(got - want) / abs(want) for got, want in (
                (axial, (evf / 3 + esf) * decay), (axial + 2.0 * radial, evf * decay))))
            radial_err = max(radial_err, abs(radial - (evf / 3 - esf / 2) * decay)
                             / ((evf / 3 + esf) * decay))
    check("closed-form", worst <= tol, f"triaxial element (sigma3 400, q 600 kPa, S {lev:.3f}):"
          f" axial and volumetric creep strain at 10 d .. 4 years, max rel. error {worst:.1e} "
          f"against eps_f (1 - exp(-alpha t)) (tol {tol:g}); radial strain within "
          f"{radial_err:.1e} of the axial")


def check_order(cfrd, workdir):
    y = integrate(np.zeros(6), 0.0, 1.0, -1000.0, with_creep=False)   # the load, no time
    ref = -(integrate(y, 0.0, 365.0, 0.0)[3] - y[3])
    counts, errors = (1, 2, 4, 8, 16, 32), []
    for n in counts:
        deck = ["TITLE     one plane-strain element held laterally: creep under a fixed load",
                "* Newton to 1e-12, so that what is left is the error of the time steps",
                "CONTROL", "&4, 1, 1, 1, , , , 0, 3, 1e-12, 50", "&EFFECTS, , OFF",
                "NODES", "&1, 2, 1, 0.0, 0.0, 1.0, 0.0", "&3, 4, 1, 1.0, 1.0, 0.0, 1.0",
                "ELEMENTS", "&1, 1, 2, 3, 4, 1", "MATERIALS", "&1, EB, test rockfill"] + \
            eb_cards(0.0) + ["BOUNDARY", "&1, 4, 1, 1, 0", "&1, 2, 1, 1, 1", "LOADS",
                             "&PRESSURE, 1, 3, 1000.0", "STAGES",
                             "&LOAD, , 4000, 2000-01-01, vertical stress",
                             f"&WAIT, , {n}, 2000-12-31", "END"]
        with run(cfrd, workdir, f"oedometer-{n}.dat", deck) as f:
            st = stages(f)
            settled = [field(g, "displacement_total")[2, 1] for g in st[:2]]
            errors.append((-(settled[1] - settled[0]) - ref) / ref)
    orders = [math.log2(abs(errors[i] / errors[i + 1])) for i in range(len(errors) - 1)]
    check("time-step-order", 0.8 <= orders[-1] <= 1.3 and abs(errors[-1]) < 2e-3,
          f"oedometer creep settlement over one year ({ref * 1000:.4f} mm, scipy LSODA), errors "
          + ", ".join(f"{e:+.1e}" for e in errors) + f" for {counts} steps: order "
          + ", ".join(f"{p:.2f}" for p in orders) + " (first order expected; tol 0.8-1.3,"
          " error at 32 steps < 2e-3)")


COLUMN_LAYERS, LAYER_H = 5, 2.0
GAMMA = 200.0          # kN/m3: test loads of a 100 m column in a 10 m one
FILL_DAYS = [0, 30, 60, 91, 121]          # from 2000-01-01
WAITS = [(181, 12), (365, 12), (730, 24)]


def column_deck(ninc_fill):
    day = lambda k: (datetime.date(2000, 1, 1) + datetime.timedelta(days=k)).isoformat()  # noqa
    n, top = 2 * (COLUMN_LAYERS + 1), repr(LAYER_H * COLUMN_LAYERS)
    return ["TITLE     layered column with creep", "CONTROL", f"&{n}, {COLUMN_LAYERS}, 1, 1",
            "&EFFECTS, , OFF", "NODES", f"&1, {n - 1}, 2, 0.0, 0.0, 0.0, {top}",
            f"&2, {n}, 2, 1.0, 0.0, 1.0, {top}", "ELEMENTS"] + [
        f"&{e}, {2 * e - 1}, {2 * e}, {2 * e + 2}, {2 * e + 1}, 1, , , L{e}"
        for e in range(1, COLUMN_LAYERS + 1)] + ["MATERIALS", "&1, EB, test rockfill"] + \
        eb_cards(GAMMA) + ["BOUNDARY", f"&1, {n}, 1, 1, 0", "&1, 2, 1, 1, 1", "STAGES"] + [
        f"&FILL, L{e}, {ninc_fill}, {day(d)}, layer {e}" for e, d in enumerate(FILL_DAYS, 1)] + [
        f"&WAIT, , {k * 4}, {day(d)}" for d, k in WAITS] + ["END"]


def column_reference():
    """Each layer's element as one point held laterally, its vertical stress the weight above
    its middle (the element's constant stress under consistent loads); loads ramp over each
    FILL stage's time span, the first stage's at once. Returns the settlement of the top of
    layer 1 (since its placement) and of the column's top (since the last layer's) at the end
    of every stage."""
    n = COLUMN_LAYERS
    state, eps_at, out = [np.zeros(6) for _ in range(n)], {}, []
    times = FILL_DAYS + [d for d, _ in WAITS]
    for k, t in enumerate(times):
        t_prev = times[k - 1] if k > 0 else t
        for e in range(min(k + 1, n)):
            # vertical stress added to element e during stage k (FILL k+1), kPa
            add = GAMMA * LAYER_H * (0.5 if e == k else 1.0) if k < n else 0.0
            state[e] = integrate(state[e], 0.0, 1.0, -add, with_creep=False) \
                if k == 0 or t == t_prev else integrate(state[e], t_prev, t, -add / (t - t_prev))
        eps_at[k] = [state[e][3] for e in range(n)]
        out.append((-LAYER_H * (eps_at[k][0] - eps_at[0][0]), -LAYER_H * sum(
            eps_at[k][e] - eps_at[n - 1][e] for e in range(n)) if k >= n - 1 else 0.0))
    return out


def check_column(cfrd, workdir, tol=1e-2):
    ref, last = column_reference(), COLUMN_LAYERS - 1
    with run(cfrd, workdir, "column.dat", column_deck(32)) as f:
        st = stages(f)
        total = [field(g, "displacement_total") for g in st]
        got = [(-total[k][2, 1],                                   # node 3: top of layer 1
                -(total[k][-2, 1] - total[last][-2, 1])
                if k >= last else 0.0) for k, g in enumerate(st)]
    worst = max(max(abs(a - c) / max(abs(c), 1e-12), abs(b - d) / abs(d) if d else 0.0)
                for (a, b), (c, d) in zip(got, ref))
    check("layered-column", worst <= tol, f"5 layers a month apart, then 2 years: settlement "
          f"of layer 1's top ({got[-1][0] * 1000:.2f} mm) and of the top since completion "
          f"({got[-1][1] * 1000:.2f} mm) at all {len(got)} stages, max rel. error {worst:.1e} "
          f"against scipy's integration per layer (tol {tol:g})")


def check_contact(cfrd, workdir, tol=5e-3):
    """A stiff slab cast in contact on a creeping block (held laterally, linear E-B: EFFECTS
    ROCKFILL LINEAR, volumetric creep only with MC = 0.001) and pressed by 500 kPa: the
    contact stays closed and the slab settles with the block, by H (1 + nu)/(3 (1 - nu))
    eps_v(t) (the creep compaction of a held block whose vertical stress the load fixes),
    and the contact pressure stays the load (statics). Nothing on standard output but the
    run's own lines: no LAPACK (XERBLA) message, as the empty row update of each LOAD
    increment printed before (docs/robustness.md, "The empty row update")."""
    mc, e, b = 0.001, EB["k"] * PA, max(EB["kb"] * PA, EB["k"] * PA / 3.0)
    nu = (3.0 * b - e) / (6.0 * b)
    p_contact = 500.0 + 24.0 * 0.2
    ev_final = CREEP["b"] * (nu / (1.0 - nu) * p_contact / PA) ** mc
    deck = ["TITLE     a slab cast on a creeping block", "CONTROL", "&12, 4, 2, 1",
            "&EFFECTS, LINEAR", "NODES", "&1, 3, 1, 0.0, 0.0, 2.0, 0.0",
            "&4, 6, 1, 0.0, 1.0, 2.0, 1.0", "&7, 9, 1, 0.0, 1.0, 2.0, 1.0",
            "&10, 12, 1, 0.0, 1.2, 2.0, 1.2", "ELEMENTS", "&1, 1, 2, 5, 4, 1, 1, 1",
            "&3, 7, 8, 11, 10, 2, 1, 1, SLAB", "MATERIALS", "&1, EB, creeping block",
            free(0.0, EB["k"], EB["n"], EB["rf"], EB["kb"], EB["m"]), free(EB["phi0"], EB["dphi"]),
            free("CREEP", CREEP["alpha"], CREEP["b"], mc, 0.0, 1.0), "&2, ELASTIC, slab",
            "&3.0e7, 0.2, 24.0", "CONTACT", "&SURFACE, SLAB, 3, 1, 1, 1",
            "&SURFACE, BLOCK, 1, 3, 1, 1", "&PAIR, SLAB, BLOCK, 0.5, , , , 1", "BOUNDARY",
            "&1, 3, 1, 1, 1", "&4, 12, 1, 1, 0", "LOADS", "&PRESSURE, 3, 3, 500.0",
            "&PRESSURE, 4, 3, 500.0", "STAGES", "&FILL, SLAB, 1, 2000-01-01, slab cast",
            "&LOAD, , 10, 2000-01-01, pressure on the slab", "&WAIT, , 10, 2000-04-10",
            "&WAIT, , 10, 2001-01-01", "&WAIT, , 10, 2004-01-01", "END"]
    path = write_deck(os.path.join(workdir, "slab-on-block.dat"), deck)
    lapack = [ln for ln in run_cfrd(cfrd, path).stdout.splitlines() if "On entry to" in ln]
    with open_results(h5_of(path)) as f:
        st = stages(f)
        t0, u0 = st[1].attrs["day"], field(st[1], "displacement_total")
        worst = worst_p = 0.0
        for g in st[2:]:
            want = (1.0 + nu) / (3.0 * (1.0 - nu)) * ev_final * (
                1.0 - math.exp(-CREEP["alpha"] * (g.attrs["day"] - t0)))
            u = field(g, "displacement_total") - u0
            worst = max(worst, *(abs(-u[node, 1] - want) / want for node in (9, 10, 11)))
            if "sigma_n" in g["contact"]:                  # the slab's top nodes above
                worst_p = max(worst_p, abs(np.mean(g["contact"]["sigma_n"][...]) + p_contact)
                              / p_contact)
    check("contact-closed", worst <= tol and worst_p <= 1e-2 and not lapack, f"slab cast on a "
          f"creeping block: its settlement from 10 days to 4 years within {worst:.1e} of "
          f"H (1+nu)/(3(1-nu)) eps_v(t) (tol {tol:g}), mean contact pressure within "
          f"{worst_p:.1e} of the load {p_contact:g} kPa (tol 1e-2), LAPACK messages on "
          f"standard output: {len(lapack)}")


def check_wetting(cfrd, workdir, tol=5e-3):
    """The triaxial element of check_closed_form wetted instead of creeping."""
    deck = triaxial_deck("triaxial wetting", eb_cards(0.0, creep=False, wetting=True), [
        "&LOAD, , 50, , cell pressure", "&LOAD, SHEAR, 50, , deviator", "&WET, , 4, , flooded"])
    with run(cfrd, workdir, "triaxial-wet.dat", deck) as f:
        st = stages(f)
        u = field(st[2], "displacement_total") - field(st[1], "displacement_total")
        stored = st[2]["wetting_gauss"][...]                  # (element, point, component)
    axial, radial = -u[2, 1], -u[1, 0]
    lev, s3 = level(-400.0, -1000.0, 0.0)
    evw, esw = wetting_strains(s3, lev)
    worst = max(abs(axial - (evw / 3 + esw)) / (evw / 3 + esw), abs(axial + 2.0 * radial - evw)
                / evw, float(np.max(np.abs(stored[0, :, 0] - evw))) / evw,
                float(np.max(np.abs(stored[0, :, 1] - esw))) / esw)
    check("wetting", worst <= tol, f"triaxial element (sigma3 400, q 600 kPa, S {lev:.3f}) "
          f"wetted in 4 increments: axial and volumetric strain and the stored wetting strains,"
          f" max rel. error {worst:.1e} against CW (s3/pa)^NW = {evw:.3e}, DW S/(1-S) = "
          f"{esw:.3e} (tol {tol:g})")


def check_wet_level(cfrd, workdir, tol=1e-9):
    """Two layers of a laterally held column; WET below the level between them."""
    deck = ["TITLE     held column of two layers, the lower one wetted", "CONTROL",
            "&6, 2, 1, 1, , , , , 3, 1e-11", "NODES", "&1, 5, 2, 0.0, 0.0, 0.0, 10.0",
            "&2, 6, 2, 1.0, 0.0, 1.0, 10.0", "ELEMENTS", "&1, 1, 2, 4, 3, 1, , , LOWER",
            "&2, 3, 4, 6, 5, 1, , , UPPER", "MATERIALS", "&1, EB, test rockfill"] + \
        eb_cards(20.0, creep=False, wetting=True) + [
            "BOUNDARY", "&1, 6, 1, 1, 0", "&1, 2, 1, 1, 1", "STAGES", "&FILL, LOWER, 10",
            "&FILL, UPPER, 10", "&WET, 5.0, 4, , lower layer flooded", "END"]
    with run(cfrd, workdir, "column-wet.dat", deck) as f:
        st = stages(f)
        s_before, s_after = st[1]["stress_gauss"][...], st[2]["stress_gauss"][...]
        w = st[2]["wetting_gauss"][...]
        u = field(st[2], "displacement_total") - field(st[1], "displacement_total")
    collapse = -u[2, 1]                                  # node 3, top of the lower layer
    upper_stress = float(np.max(np.abs(s_after[1] - s_before[1])))   # (element, point, comp)
    stretch = abs((u[4, 1] - u[2, 1]) / collapse)        # node 5 against node 3
    check("wet-level", collapse > 0.0 and upper_stress <= tol * float(np.max(np.abs(
        s_before[1]))) and stretch <= tol and float(np.max(np.abs(w[1]))) == 0.0 and
        float(np.min(w[0, :, 0])) > 0.0, f"held column, WET below 5 m: the lower layer "
        f"collapses {collapse * 1e3:.2f} mm; the upper layer's stresses change by "
        f"{upper_stress:.1e} kPa, its height by {stretch:.1e} of the collapse, its wetting "
        f"strains {float(np.max(np.abs(w[1]))):g} (tol {tol:g})")


def check_off(cfrd, workdir):
    """EFFECTS CREEP OFF (and a deck without CREEP cards): the results of a deck without creep,
    bit for bit, and no creep state stored."""
    deck = column_deck(4)
    off = [ln.replace("&EFFECTS, , OFF", "&EFFECTS, , OFF, , , , , , OFF") for ln in deck]
    with run(cfrd, workdir, "column-off.dat", off) as a, \
            run(cfrd, workdir, "column-bare.dat", [ln for ln in deck
                                                   if not ln.startswith("&CREEP")]) as b:
        sa, sb = stages(a), stages(b)
        same = len(sa) == len(sb) and all(np.array_equal(field(x, name), field(y, name))
                                          for x, y in zip(sa, sb)
                                          for name in ("displacement_total", "stress_gauss"))
        stored = any("creep_gauss" in g for g in sa)
        effects = a.attrs["effects"].decode()
    check("effects-off", same and not stored and effects.endswith("CREEP OFF"), f"the column "
          f"with EFFECTS CREEP OFF against the same deck without CREEP cards: "
          f"{'bit-identical' if same else 'DIFFERENT'} displacements and stresses at {len(sa)}"
          f" stages, creep state stored: {stored}, effects attribute '{effects[-9:]}'")


def main(argv=None):
    a = parser(__doc__, cfrd=True, workdir="build/creep").parse_args(argv)
    os.makedirs(a.workdir, exist_ok=True)
    for case in (check_closed_form, check_order, check_column, check_contact, check_off,
                 check_wetting, check_wet_level):
        check.guard(case.__name__, case, a.cfrd, a.workdir)  # a failed run: a failed check
    return check.status


if __name__ == "__main__":
    sys.exit(main())
