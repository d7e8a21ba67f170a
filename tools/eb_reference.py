#!/usr/bin/env python3
"""Independent integration of the Duncan-Chang E-B law (numpy/scipy, no cfrd code), the check
of cfrd's finite-element plane-strain compression test against it (issue 4), and the table of
a triaxial test run by cfrd against Kondner's hyperbola.

The law (docs/theory.md section 8, paper eqs. 18-21, c = 0):
    phi = phi0 - dphi log10(s3/pa),  qf = 2 s3 sin(phi) / (1 - sin(phi)),  S = q/qf (<= 0.99)
    Et = K pa (s3/pa)^n (1 - Rf S)^2,  Bt = Kb pa (s3/pa)^m bounded to [Et/3, Et/0.06],
    nu_t = (3 Bt - Et) / (6 Bt).
Loading paths at constant s3 (compression positive), integrated with scipy's solve_ivp (RK45,
rtol 1e-11): triaxial (d s_z = dq): d eps1/dq = 1/Et, d eps_v/dq = (1 - 2 nu_t)/Et;
plane-strain (d s_y = dq, d eps_z = 0): d eps1/dq = (1 - nu_t^2)/Et,
d eps_v/dq = (1 + nu_t)(1 - 2 nu_t)/Et.

  python3 tools/eb_reference.py --material IIIB --sigma3 500 --mode plane-strain [--csv F]
  python3 tools/eb_reference.py --check-cfrd bin/cfrd --workdir DIR   (PASS/FAIL lines)
  python3 tools/eb_reference.py --selftest
  python3 tools/eb_reference.py --triaxial inputs/triaxial-iiib.h5 [--material IIIB
                                --sigma3 500]

--triaxial: the deviator, axial and volumetric strain of a drained triaxial test (one
axisymmetric element, node 3 the top of its side at x = R, y = H, e.g. inputs/triaxial-iiib.dat)
from the RESET stage on: eps1 = -u_y(3)/H, eps_v = eps1 - 2 u_x(3)/R, q from the stage's
applied load (the axial load per radian on the top is (p3 + q) R^2 / 2), beside Kondner's
hyperbola.
"""

import argparse
import math
import os
import sys

import numpy as np
from scipy.integrate import solve_ivp

from cfrdtools import results, runner
from cfrdtools.checks import Checks

PA = 101.325
# Paper Table 3 (../shared/reference/tianshengqiao-i.md): phi0, dphi, K, n, Rf, Kb, m.
TABLE3 = {
    "IIA": (50.6, 7.0, 1000.0, 0.35, 0.71, 450.0, 0.24),
    "IIIA": (52.5, 8.0, 900.0, 0.36, 0.76, 400.0, 0.19),
    "IIIB": (51.0, 13.0, 564.0, 0.35, 0.85, 204.0, 0.18),
    "IIID": (51.0, 13.5, 432.0, 0.30, 0.80, 300.0, -0.18),
    "IIIC": (45.0, 10.0, 250.0, 0.25, 0.73, 125.0, 0.00),
}
NU_MAX = 0.49
LEVEL_CAP = 0.99


def failure_deviator(mat, s3):
    phi0, dphi = TABLE3[mat][:2]
    phi = math.radians(phi0 - dphi * math.log10(s3 / PA))
    return 2.0 * s3 * math.sin(phi) / (1.0 - math.sin(phi))


def moduli(mat, s3, q):
    """Et, nu_t at constant s3 and deviator q (loading branch)."""
    _, _, k, n, rf, kb, m = TABLE3[mat]
    level = min(max(q / failure_deviator(mat, s3), 0.0), LEVEL_CAP)
    et = k * PA * (s3 / PA) ** n * (1.0 - rf * level) ** 2
    bt = min(max(kb * PA * (s3 / PA) ** m, et / 3.0), et / (3.0 * (1.0 - 2.0 * NU_MAX)))
    return et, (3.0 * bt - et) / (6.0 * bt)


def integrate(mat, s3, qs, mode):
    """eps1(q), eps_v(q) at the deviators qs (increasing, from 0)."""
    def rhs(q, y):
        et, nu = moduli(mat, s3, q)
        if mode == "triaxial":
            return [1.0 / et, (1.0 - 2.0 * nu) / et]
        return [(1.0 - nu * nu) / et, (1.0 + nu) * (1.0 - 2.0 * nu) / et]
    sol = solve_ivp(rhs, (0.0, qs[-1]), [0.0, 0.0], t_eval=qs, rtol=1e-11, atol=1e-16,
                    max_step=qs[-1] / 200)
    return sol.y[0], sol.y[1]


def table(mat, s3, mode, fraction=0.9, points=9):
    qs = np.linspace(0.0, fraction * failure_deviator(mat, s3), points + 1)[1:]
    e1, ev = integrate(mat, s3, np.concatenate([[0.0], qs]), mode)
    return qs, e1[1:], ev[1:]


def cfrd_deck(mat, s3, dq, steps, increments):
    """One 1 m x 1 m plane-strain element: cell pressure, then deviator steps on the top."""
    phi0, dphi, k, n, rf, kb, m = TABLE3[mat]
    return "\n".join([
        f"TITLE     plane-strain compression, {mat} at {s3:g} kPa",
        "* One 1 m x 1 m element: node 1 pinned, node 2 on a roller (y), node 4 (x).",
        "* Cell pressure on the right and top faces, then deviator steps on the top.",
        "NODES", "&1, 2, 1, 0.0, 0.0, 1.0, 0.0", "&3, 4, 1, 1.0, 1.0, 0.0, 1.0",
        "ELEMENTS", "&1, 1, 2, 3, 4, 1", "MATERIALS", f"&1, EB, {mat}",
        f"&0.0, {k!r}, {n!r}, {rf!r}, {kb!r}, {m!r}", f"&{phi0!r}, {dphi!r}",
        "BOUNDARY", "&1, , , 1, 1", "&2, , , 0, 1", "&4, , , 1, 0",
        "LOADS", f"&PRESSURE, 1, 2, {s3!r}", f"&PRESSURE, 1, 3, {s3!r}",
        "LOADS     SHEAR", f"&PRESSURE, 1, 3, {dq!r}",
        "STAGES", "&LOAD, , 400, , cell pressure", "&RESET",
    ] + [f"&LOAD, SHEAR, {increments}, , deviator step {s + 1}" for s in range(steps)]
        + ["END"]) + "\n"


def check_cfrd(cfrd, workdir, tol=5e-3, steps=9):
    """Two Table 3 materials at two confining pressures: eps1 and eps_v at every step within
    0.5 % of the ODE (issue 4). One PASS/FAIL line per case."""
    os.makedirs(workdir, exist_ok=True)
    check = Checks("eb")
    for mat in ("IIIB", "IIID"):
        for s3 in (200.0, 1000.0):
            dq = 0.9 * failure_deviator(mat, s3) / steps
            with results.open_results(runner.run_text(cfrd, os.path.join(
                    workdir, f"ps-{mat}-{s3:g}.dat"), cfrd_deck(mat, s3, dq, steps, 40))) as f:
                u = np.array([results.read(f, "displacement", s + 3)[2] for s in range(steps)])
            e1, ev = -u[:, 1], -u[:, 1] - u[:, 0]   # node 3, top right: eps = u / 1 m
            r1, rv = integrate(mat, s3, np.concatenate([[0.0], dq * np.arange(1, steps + 1)]),
                               "plane-strain")
            err1 = np.max(np.abs(e1 - r1[1:]) / np.abs(r1[1:]))
            errv = np.max(np.abs(ev - rv[1:]) / np.max(np.abs(rv[1:])))
            check(f"plane-strain-{mat}-{s3:g}", err1 <= tol and errv <= tol, f"max rel. error "
                  f"eps1 {err1:.2e}, eps_v {errv:.2e} (tol {tol:g}; scipy ODE reference)")
    return check.status


def kondner(mat, s3, qs):
    """Kondner's hyperbola eps1 = q / (Ei (1 - Rf q/qf)) and Ei."""
    _, _, k, n, rf, _, _ = TABLE3[mat]
    ei = k * PA * (s3 / PA) ** n
    return np.asarray(qs) / (ei * (1.0 - rf * np.asarray(qs) / failure_deviator(mat, s3))), ei


def selftest():
    """The triaxial mode reproduces Kondner's hyperbola: eps1 is the hyperbola whatever
    nu_t."""
    worst = 0.0
    for mat in TABLE3:
        for s3 in (100.0, 500.0, 1500.0):
            qs, e1, _ = table(mat, s3, "triaxial")
            worst = max(worst, float(np.max(np.abs(e1 / kondner(mat, s3, qs)[0] - 1.0))))
    return 0 if Checks("eb")("reference-selftest", worst < 1e-8, f"triaxial ODE vs Kondner "
                             f"hyperbola, max rel. error {worst:.1e} (tol 1e-8)") else 1


def triaxial(path, mat, s3):
    """The table of a drained triaxial test run by cfrd, from its RESET on."""
    rows = []
    with results.open_results(path) as f:
        radius, height = f["mesh/coordinates"][2]
        started = False
        for g in results.stages(f):
            reset = results.text(g.attrs["name"]).startswith("RESET")
            started |= reset
            if reset or not started:
                continue
            u = g["displacement"][...]
            q = -results.scalar(np.asarray(g.attrs["applied_load"]).ravel()[1]) / (
                radius ** 2 / 2) - s3
            rows.append((q, -u[2, 1] / height, -u[2, 1] / height - 2 * u[2, 0] / radius))
    _, ei = kondner(mat, s3, [0.0])
    qf = failure_deviator(mat, s3)
    print(f"drained triaxial test, {mat}, sigma3 = {s3:g} kPa, qf = {qf:.1f} kPa, "
          f"Ei = {ei:.0f} kPa")
    print("   q (kPa)   q/qf    eps1 (%)   eps_v (%)   Kondner eps1 (%)   difference")
    for q, e1, ev in rows:
        k = kondner(mat, s3, q)[0]
        print(f"{q:10.1f} {q / qf:6.3f} {100 * e1:11.4f} {100 * ev:11.4f} "
              f"{100 * k:18.4f} {e1 / k - 1:12.2e}")
    return 0


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--material", default="IIIB", choices=sorted(TABLE3))
    ap.add_argument("--sigma3", type=float, default=500.0, help="cell pressure, kPa")
    ap.add_argument("--mode", default="triaxial", choices=["triaxial", "plane-strain"])
    ap.add_argument("--qmax-fraction", type=float, default=0.9)
    ap.add_argument("--points", type=int, default=9)
    ap.add_argument("--csv")
    ap.add_argument("--check-cfrd", metavar="CFRD")
    ap.add_argument("--workdir", default="build/eb-reference")
    ap.add_argument("--selftest", action="store_true")
    ap.add_argument("--triaxial", metavar="RESULTS.h5",
                    help="the table of a triaxial test run by cfrd (inputs/triaxial-iiib.dat)")
    a = ap.parse_args(argv)
    if a.selftest:
        return selftest()
    if a.check_cfrd:
        return check_cfrd(a.check_cfrd, a.workdir)
    if a.triaxial:
        return triaxial(a.triaxial, a.material, a.sigma3)
    qs, e1, ev = table(a.material, a.sigma3, a.mode, a.qmax_fraction, a.points)
    print(f"{a.mode} test, {a.material}, sigma3 = {a.sigma3:g} kPa")
    print("      q (kPa)        eps1       eps_v")
    for q, x, y in zip(qs, e1, ev):
        print(f"{q:13.3f} {x:11.6f} {y:11.6f}")
    if a.csv:
        np.savetxt(a.csv, np.column_stack([qs, e1, ev]), delimiter=",",
                   header="q_kPa,eps1,eps_v", comments="")
    return 0


if __name__ == "__main__":
    sys.exit(main())
