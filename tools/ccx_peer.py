#!/usr/bin/env python3
"""Peer check of cfrd against CalculiX (ccx) on the issue's embankment.

  python3 tools/ccx_peer.py --cfrd CFRD --elements N --workdir DIR
      Writes the same mesh as a cfrd deck and a CalculiX .inp (tools/embankment.py), runs
      both, and compares nodal displacements: max over nodes and components of
      |u_cfrd - u_ccx| / max |u_ccx| <= 1e-6 (ccx's .dat holds 7 significant digits).
      Also checks cfrd's force balance: the stage attributes applied_load + reaction_sum
      cancel to 1e-9 of the load, and the sum of the /reaction dataset equals the weight of
      the dam computed here (sum of gamma * area), to 1e-9.
  python3 tools/ccx_peer.py --column [--cfrd CFRD] --workdir DIR
      Checks CalculiX itself against the closed form of a confined column under its own
      weight, u_y(z) = -gamma (H z - z^2/2) / M, M = E(1-nu)/((1+nu)(1-2nu)); bilinear
      elements reproduce it exactly at the nodes (1D problem, consistent load). With --cfrd
      the same column is also run through cfrd (line peer/cfrd-column).

One PASS/FAIL line per check; exit status 0 when all pass, 1 otherwise.
"""

import argparse
import os
import sys

import numpy as np

import embankment as emb
from cfrdtools.ccx import RunError, run_ccx, timed_run  # noqa: F401  (bench.py: peer.*)

DU_TOL = 1.0e-6          # ccx .dat: 7 significant digits, rounding <= 5e-7 of max |u|
BALANCE_TOL = 1.0e-9


def run_cfrd(cfrd, deck, workdir):
    """CFRD deck --quiet (results beside the deck); returns (wall s, peak kB, h5 path)."""
    h5 = os.path.splitext(deck)[0] + ".h5"
    if os.path.exists(h5):
        os.unlink(h5)
    log = os.path.splitext(deck)[0] + ".cfrd.log"
    wall, rss = timed_run([os.path.abspath(cfrd), os.path.abspath(deck), "--quiet"],
                          cwd=workdir, log=log)
    if not os.path.exists(h5):
        raise RunError(f"cfrd exited 0 but wrote no {h5}")
    return wall, rss, h5


def read_cfrd(h5path):
    """Everything the peer check needs from cfrd's HDF5 file (layout fixed by the lead)."""
    import h5py
    with h5py.File(h5path, "r") as f:
        st = f["/stages/stage_0001"]
        out = dict(coords=f["/mesh/coordinates"][()], conn=f["/mesh/connectivity"][()],
                   u=st["displacement"][()], reaction=st["reaction"][()],
                   applied_load=None, reaction_sum=None, solver={})
        for key in ("applied_load", "reaction_sum"):
            if key in st.attrs:
                out[key] = np.atleast_1d(np.asarray(st.attrs[key], dtype=float))
        if "solver" in st:
            out["solver"] = {k: float(np.asarray(v).ravel()[0])
                             for k, v in st["solver"].attrs.items()}
        if "/run" in f:
            out["wall_time"] = float(np.asarray(f["/run"].attrs.get("wall_time", np.nan)))
    return out


def mesh_for(elements, free=None):
    """The embankment in fixed format, or free format when fixed cannot hold it (I5 limits
    node and element numbers to 99999) or when free is asked for."""
    if free:
        return emb.embankment_mesh(elements, free=True), "free"
    try:
        mesh = emb.embankment_mesh(elements, free=False)
        emb.deck_lines(mesh)
        return mesh, "fixed"
    except emb.FieldOverflow:
        return emb.embankment_mesh(elements, free=True), "free"


def relative_difference(u, v):
    """max |u - v| / max |v| over nodes and components."""
    return float(np.max(np.abs(u - v)) / np.max(np.abs(v)))


def check_embankment(cfrd, elements, workdir, free=None):
    """The peer comparison; returns (ok, line, figures)."""
    os.makedirs(workdir, exist_ok=True)
    mesh, form = mesh_for(elements, free)
    name = f"embankment-{elements}"
    # Separate job names: ccx writes its results to <job>.dat, which would overwrite the
    # cfrd deck of the same name.
    job = name + "-ccx"
    deck = os.path.join(workdir, name + ".dat")
    emb.write_cfrd_deck(mesh, deck)
    emb.write_ccx_deck(mesh, os.path.join(workdir, job + ".inp"))
    label = f"peer/embankment-{elements}"
    figs = dict(mesh=mesh, form=form)
    try:
        t_ccx, rss_ccx = run_ccx(workdir, job)
        u_ccx = emb.ccx_displacement_array(os.path.join(workdir, job + ".dat"), mesh.nnode)
    except (RunError, ValueError) as exc:
        return False, f"FAIL {label}: CalculiX: {exc}", figs
    figs.update(t_ccx=t_ccx, rss_ccx=rss_ccx, u_ccx=u_ccx)
    return _finish_embankment(cfrd, mesh, deck, workdir, label, figs)


def _finish_embankment(cfrd, mesh, deck, workdir, label, figs):
    try:
        t_cfrd, rss_cfrd, h5 = run_cfrd(cfrd, deck, workdir)
        res = read_cfrd(h5)
    except (RunError, OSError, KeyError) as exc:
        return False, f"FAIL {label}: cfrd: {exc}", figs
    figs.update(t_cfrd=t_cfrd, rss_cfrd=rss_cfrd, res=res)
    problems = []
    u, u_ccx = res["u"], figs["u_ccx"]
    if u.shape != (mesh.nnode, 2):
        return False, (f"FAIL {label}: /stages/stage_0001/displacement has shape {u.shape}, "
                       f"expected ({mesh.nnode}, 2)"), figs
    # cfrd must have read the mesh the deck describes (coordinates to rounding noise).
    dx = float(np.max(np.abs(res["coords"] - mesh.coords)))
    if res["coords"].shape != mesh.coords.shape or dx > 1e-12 * emb.HEIGHT:
        problems.append(f"/mesh/coordinates differ from the deck's mesh by {dx:.2e} m")
    if not np.array_equal(res["conn"], mesh.conn):
        problems.append("/mesh/connectivity differs from the deck's elements")
    du = relative_difference(u, u_ccx)
    figs["du"] = du
    if not du <= DU_TOL:
        problems.append(f"displacements differ from CalculiX by {du:.2e} of max |u|")
    # Balance: reactions against what gravity puts on the dam.
    weight = mesh.total_weight()
    rsum = res["reaction"].sum(axis=0)
    wbal = float(max(abs(rsum[0]), abs(rsum[1] - weight)) / weight)
    if not wbal <= BALANCE_TOL:
        problems.append(f"sum of /reaction = ({rsum[0]:.9g}, {rsum[1]:.9g}) kN/m, weight "
                        f"{weight:.9g} kN/m (rel {wbal:.1e})")
    if res["applied_load"] is None or res["reaction_sum"] is None:
        problems.append("no applied_load/reaction_sum attributes on /stages/stage_0001")
        bal_text = "n/a"
    else:
        ap, rs = res["applied_load"], res["reaction_sum"]
        bal = float(np.max(np.abs(ap + rs)) / np.max(np.abs(ap)))
        bal_text = f"{bal:.1e}"
        if not bal <= BALANCE_TOL:
            problems.append(f"applied_load {ap} + reaction_sum {rs} do not cancel ({bal:.1e})")
        wap = float(max(abs(ap[0]), abs(ap[-1] + weight)) / weight)
        if not wap <= BALANCE_TOL:
            problems.append(f"applied_load {ap} is not (0, -weight {weight:.9g}) ({wap:.1e})")
    status = "FAIL" if problems else "PASS"
    line = (f"{status} {label}: max |du|/max|u| = {du:.2e} (tol {DU_TOL:g}), "
            f"balance {bal_text}, sum R vs weight {wbal:.1e} (tol {BALANCE_TOL:g}) "
            f"[cfrd {figs['t_cfrd']:.2f} s, ccx {figs['t_ccx']:.2f} s]")
    if problems:
        line += " -- " + "; ".join(problems)
    return not problems, line, figs


# --------------------------------------------------------------------------------------
# Confined column: CalculiX (and optionally cfrd) against the closed form
# --------------------------------------------------------------------------------------

def column_exact(mesh):
    e, nu, gam, _ = mesh.materials[1]
    m_oed = e * (1 - nu) / ((1 + nu) * (1 - 2 * nu))
    h = mesh.y[-1]
    z = mesh.coords[:, 1]
    u = np.zeros_like(mesh.coords)
    u[:, 1] = -gam * (h * z - 0.5 * z * z) / m_oed
    return u


def check_column(workdir, cfrd=None, n=10):
    os.makedirs(workdir, exist_ok=True)
    lines, ok = [], True
    # Height 10 m, width 1 m, every node fixed in x: a 1D oedometric column.
    mesh = emb.column_mesh(n, width=1.0, height=10.0)
    exact = column_exact(mesh)
    name = "column-ccx"
    emb.write_ccx_deck(mesh, os.path.join(workdir, name + ".inp"))
    try:
        t, _ = run_ccx(workdir, name)
        u = emb.ccx_displacement_array(os.path.join(workdir, name + ".dat"), mesh.nnode)
        err = relative_difference(u, exact)
        good = err <= DU_TOL
        lines.append(f"{'PASS' if good else 'FAIL'} peer/ccx-column: {n} CPE4, max |u - u_exact|"
                     f"/max|u_exact| = {err:.2e} (tol {DU_TOL:g}; closed form -gamma(Hz-z^2/2)/M,"
                     f" top u_y = {u[-1, 1]:.7e} m vs {exact[-1, 1]:.7e}) [ccx {t:.2f} s]")
        ok &= good
    except (RunError, ValueError) as exc:
        lines.append(f"FAIL peer/ccx-column: {exc}")
        ok = False
    if cfrd:
        deck = os.path.join(workdir, "column.dat")
        emb.write_cfrd_deck(mesh, deck)
        try:
            t, _, h5 = run_cfrd(cfrd, deck, workdir)
            u = read_cfrd(h5)["u"]
            err = relative_difference(u, exact)
            good = err <= 1e-10      # cfrd has full double precision: only solver round-off
            lines.append(f"{'PASS' if good else 'FAIL'} peer/cfrd-column: max |u - u_exact|"
                         f"/max|u_exact| = {err:.2e} (tol 1e-10, closed form) [cfrd {t:.2f} s]")
            ok &= good
        except (RunError, OSError, KeyError) as exc:
            lines.append(f"FAIL peer/cfrd-column: {exc}")
            ok = False
    return ok, lines


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--cfrd", help="path of the cfrd program")
    ap.add_argument("--elements", type=int, default=1000)
    ap.add_argument("--workdir", default="build/peer")
    ap.add_argument("--free", action="store_true", help="write the cfrd deck in free format")
    ap.add_argument("--column", action="store_true", help="check CalculiX on the column")
    args = ap.parse_args(argv)
    if args.column:
        ok, lines = check_column(args.workdir, args.cfrd)
        print("\n".join(lines))
        return 0 if ok else 1
    if not args.cfrd:
        ap.error("--cfrd is required (except with --column)")
    ok, line, _ = check_embankment(args.cfrd, args.elements, args.workdir,
                                   free=args.free or None)
    print(line)
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
