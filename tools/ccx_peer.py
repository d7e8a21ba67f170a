#!/usr/bin/env python3
"""Peer check of cfrd against CalculiX (ccx) on the issue's embankment.

  python3 tools/ccx_peer.py --cfrd CFRD --elements N --workdir DIR
      The same mesh as a cfrd deck and a CalculiX .inp (tools/embankment.py), both run: nodal
      displacements max |u_cfrd - u_ccx| / max |u_ccx| <= 1e-6 (ccx prints 7 digits); cfrd's
      applied_load + reaction_sum cancel and the /reaction sum is the dam's weight (sum of
      gamma * area, computed here), each to 1e-9.
  python3 tools/ccx_peer.py --column [--cfrd CFRD] --workdir DIR
      CalculiX on a confined column under its own weight against the closed form
      u_y(z) = -gamma (H z - z^2/2) / M, M = E(1-nu)/((1+nu)(1-2nu)), exact at the nodes of
      bilinear elements; with --cfrd the same column through cfrd (peer/cfrd-column).
"""

import os
import sys

import numpy as np

import embankment as emb
from cfrdtools.ccx import RunError, displacement_array, run_ccx, timed_run
from cfrdtools.checks import Checks, parser
from cfrdtools.results import open_results, stage

DU_TOL = 1.0e-6          # ccx .dat: 7 significant digits, rounding <= 5e-7 of max |u|
BALANCE_TOL = 1.0e-9


def run_cfrd(cfrd, deck, workdir):
    """CFRD deck --quiet (results beside the deck); returns (wall s, peak kB, h5 path)."""
    h5 = os.path.splitext(deck)[0] + ".h5"
    if os.path.exists(h5):
        os.unlink(h5)
    wall, rss = timed_run([os.path.abspath(cfrd), os.path.abspath(deck), "--quiet"],
                          cwd=workdir, log=os.path.splitext(deck)[0] + ".cfrd.log")
    if not os.path.exists(h5):
        raise RunError(f"cfrd exited 0 but wrote no {h5}")
    return wall, rss, h5


def read_cfrd(h5path):
    """Stage 1 of a cfrd results file: mesh, displacements, reactions, load sums, solver."""
    with open_results(h5path) as f:
        st = stage(f, 1)
        out = dict(coords=f["mesh/coordinates"][()], conn=f["mesh/connectivity"][()],
                   u=st["displacement"][()], reaction=st["reaction"][()],
                   applied_load=None, reaction_sum=None,
                   solver={k: float(np.ravel(v)[0]) for k, v in st["solver"].attrs.items()}
                   if "solver" in st else {})
        for key in ("applied_load", "reaction_sum"):
            if key in st.attrs:
                out[key] = np.atleast_1d(np.asarray(st.attrs[key], dtype=float))
    return out


def mesh_for(elements, free=None):
    """The embankment in fixed format, or free format when asked or when fixed cannot hold
    it (I5 limits node and element numbers to 99999)."""
    if not free:
        try:
            mesh = emb.embankment_mesh(elements, free=False)
            emb.deck_lines(mesh)
            return mesh, "fixed"
        except emb.FieldOverflow:
            pass
    return emb.embankment_mesh(elements, free=True), "free"


def relative_difference(u, v):
    """max |u - v| / max |v| over nodes and components."""
    return float(np.max(np.abs(u - v)) / np.max(np.abs(v)))


def check_embankment(check, cfrd, elements, workdir, free=None):
    os.makedirs(workdir, exist_ok=True)
    mesh, form = mesh_for(elements, free)
    # ccx writes its results to JOB.dat: a job name of its own keeps the cfrd deck.
    name, label = f"embankment-{elements}", f"embankment-{elements}"
    deck, job = os.path.join(workdir, name + ".dat"), name + "-ccx"
    emb.write_cfrd_deck(mesh, deck)
    emb.write_ccx_deck(mesh, os.path.join(workdir, job + ".inp"))
    try:
        t_ccx, _ = run_ccx(workdir, job)
        u_ccx = displacement_array(os.path.join(workdir, job + ".dat"), mesh.nnode)
    except (RunError, ValueError) as exc:
        return check(label, False, f"CalculiX: {exc}")
    try:
        t_cfrd, _, h5 = run_cfrd(cfrd, deck, workdir)
        res = read_cfrd(h5)
    except (RunError, OSError, KeyError) as exc:
        return check(label, False, f"cfrd: {exc}")
    u = res["u"]
    if u.shape != (mesh.nnode, 2):
        return check(label, False, f"/stages/stage_0001/displacement has shape {u.shape}, "
                     f"expected ({mesh.nnode}, 2)")
    problems = []
    # cfrd must have read the mesh the deck describes (coordinates to rounding noise).
    dx = float(np.max(np.abs(res["coords"] - mesh.coords)))
    if res["coords"].shape != mesh.coords.shape or dx > 1e-12 * emb.HEIGHT:
        problems.append(f"/mesh/coordinates differ from the deck's mesh by {dx:.2e} m")
    if not np.array_equal(res["conn"], mesh.conn):
        problems.append("/mesh/connectivity differs from the deck's elements")
    du = relative_difference(u, u_ccx)
    if not du <= DU_TOL:
        problems.append(f"displacements differ from CalculiX by {du:.2e} of max |u|")
    weight = mesh.total_weight()           # reactions against what gravity puts on the dam
    rsum = res["reaction"].sum(axis=0)
    wbal = float(max(abs(rsum[0]), abs(rsum[1] - weight)) / weight)
    if not wbal <= BALANCE_TOL:
        problems.append(f"sum of /reaction = ({rsum[0]:.9g}, {rsum[1]:.9g}) kN/m, weight "
                        f"{weight:.9g} kN/m (rel {wbal:.1e})")
    bal_text = "n/a"
    if res["applied_load"] is None or res["reaction_sum"] is None:
        problems.append("no applied_load/reaction_sum attributes on /stages/stage_0001")
    else:
        ap, rs = res["applied_load"], res["reaction_sum"]
        bal = float(np.max(np.abs(ap + rs)) / np.max(np.abs(ap)))
        bal_text = f"{bal:.1e}"
        if not bal <= BALANCE_TOL:
            problems.append(f"applied_load {ap} + reaction_sum {rs} do not cancel ({bal:.1e})")
        wap = float(max(abs(ap[0]), abs(ap[-1] + weight)) / weight)
        if not wap <= BALANCE_TOL:
            problems.append(f"applied_load {ap} is not (0, -weight {weight:.9g}) ({wap:.1e})")
    return check(label, not problems, f"max |du|/max|u| = {du:.2e} (tol {DU_TOL:g}), balance "
                 f"{bal_text}, sum R vs weight {wbal:.1e} (tol {BALANCE_TOL:g}) [cfrd "
                 f"{t_cfrd:.2f} s, ccx {t_ccx:.2f} s]" + (" -- " + "; ".join(problems)
                                                          if problems else ""))


def check_column(check, workdir, cfrd=None, n=10):
    """A 10 m x 1 m column, every node fixed in x: oedometric, a 1D closed form."""
    os.makedirs(workdir, exist_ok=True)
    mesh = emb.column_mesh(n, width=1.0, height=10.0)
    e, nu, gam, _ = mesh.materials[1]
    z = mesh.coords[:, 1]
    exact = np.zeros_like(mesh.coords)
    exact[:, 1] = -gam * (mesh.y[-1] * z - 0.5 * z * z) / (e * (1 - nu) / ((1 + nu) * (1 - 2 * nu)))
    emb.write_ccx_deck(mesh, os.path.join(workdir, "column-ccx.inp"))
    try:
        t, _ = run_ccx(workdir, "column-ccx")
        u = displacement_array(os.path.join(workdir, "column-ccx.dat"), mesh.nnode)
        err = relative_difference(u, exact)
        check("ccx-column", err <= DU_TOL, f"{n} CPE4, max |u - u_exact|/max|u_exact| = "
              f"{err:.2e} (tol {DU_TOL:g}; closed form -gamma(Hz-z^2/2)/M, top u_y = "
              f"{u[-1, 1]:.7e} m vs {exact[-1, 1]:.7e}) [ccx {t:.2f} s]")
    except (RunError, ValueError) as exc:
        check("ccx-column", False, str(exc))
    if cfrd:
        deck = os.path.join(workdir, "column.dat")
        emb.write_cfrd_deck(mesh, deck)
        try:
            t, _, h5 = run_cfrd(cfrd, deck, workdir)
            err = relative_difference(read_cfrd(h5)["u"], exact)
            # cfrd has full double precision: only the solver's round-off
            check("cfrd-column", err <= 1e-10, f"max |u - u_exact|/max|u_exact| = {err:.2e} "
                  f"(tol 1e-10, closed form) [cfrd {t:.2f} s]")
        except (RunError, OSError, KeyError) as exc:
            check("cfrd-column", False, str(exc))


def main(argv=None):
    ap = parser(__doc__, workdir="build/peer")
    ap.add_argument("--cfrd", help="path of the cfrd program")
    ap.add_argument("--elements", type=int, default=1000)
    ap.add_argument("--free", action="store_true", help="write the cfrd deck in free format")
    ap.add_argument("--column", action="store_true", help="check CalculiX on the column")
    args = ap.parse_args(argv)
    check = Checks("peer")
    if args.column:
        check_column(check, args.workdir, args.cfrd)
    elif not args.cfrd:
        ap.error("--cfrd is required (except with --column)")
    else:
        check_embankment(check, args.cfrd, args.elements, args.workdir, args.free or None)
    return check.status


if __name__ == "__main__":
    sys.exit(main())
