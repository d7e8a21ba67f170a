#!/usr/bin/env python3
"""The deviator / axial strain / volumetric strain table of a drained triaxial test run by
cfrd (inputs/triaxial-iiib.dat), with Kondner's hyperbola beside it.

    python3 tools/triaxial.py inputs/triaxial-iiib.h5 [--material IIIB --sigma3 500]

The sample is one axisymmetric element: node 3 is the top of its side (x = radius R,
y = height H). Strains are compression positive and counted from the RESET stage:
eps1 = -u_y(3)/H, eps_v = eps1 - 2 u_x(3)/R. The deviator q of a stage is the sum of the
axial pressure steps applied since the RESET; it is read back from the stage's applied load
(the axial load per radian on the top is (p3 + q) R^2 / 2).
"""
import argparse
import sys

import h5py
import numpy as np

import eb_reference as ref
from cfrdtools import results


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("result", help="the .h5 file of the triaxial deck")
    ap.add_argument("--material", default="IIIB", choices=sorted(ref.TABLE3))
    ap.add_argument("--sigma3", type=float, default=500.0, help="cell pressure, kPa")
    a = ap.parse_args(argv)
    with h5py.File(a.result) as f:
        x = f["mesh/coordinates"][...]
        radius, height = x[2]
        rows = []
        started = False
        for g in results.stages(f):
            label = results.text(g.attrs["name"])
            if label.startswith("RESET"):
                started = True
                continue
            if not started:
                continue
            u = g["displacement"][...]
            axial = -float(np.asarray(g.attrs["applied_load"]).ravel()[1])
            q = axial / (radius ** 2 / 2) - a.sigma3
            eps1 = -u[2, 1] / height
            epsv = eps1 - 2 * u[2, 0] / radius
            rows.append((q, eps1, epsv))
    _, _, k, n, rf, _, _ = ref.TABLE3[a.material]
    ei = k * ref.PA * (a.sigma3 / ref.PA) ** n
    qf = ref.failure_deviator(a.material, a.sigma3)
    print(f"drained triaxial test, {a.material}, sigma3 = {a.sigma3:g} kPa, "
          f"qf = {qf:.1f} kPa, Ei = {ei:.0f} kPa")
    print("   q (kPa)   q/qf    eps1 (%)   eps_v (%)   Kondner eps1 (%)   difference")
    for q, e1, ev in rows:
        kondner = q / (ei * (1 - rf * q / qf))
        print(f"{q:10.1f} {q / qf:6.3f} {100 * e1:11.4f} {100 * ev:11.4f} "
              f"{100 * kondner:18.4f} {e1 / kondner - 1:12.2e}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
