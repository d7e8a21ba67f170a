#!/usr/bin/env python3
"""CalculiX (ccx) as the independent peer of cfrd: five cases, each solved by both programs
on the same mesh (ccx prints 7 digits: displacements agree to 1e-6 of the largest).

  python3 tools/ccx_peer.py --cfrd CFRD [--elements N] [--free] --workdir DIR
      The issue's embankment, a cfrd deck and a CalculiX .inp of one mesh (tools/embankment.py):
      nodal displacements max |u_cfrd - u_ccx| / max |u_ccx| <= 1e-6; cfrd's applied_load +
      reaction_sum cancel and the /reaction sum is the dam's weight (sum of gamma * area,
      computed here), each to 1e-9.
  python3 tools/ccx_peer.py --column [--cfrd CFRD] --workdir DIR
      CalculiX on a confined column under its own weight against the closed form
      u_y(z) = -gamma (H z - z^2/2) / M, M = E(1-nu)/((1+nu)(1-2nu)), exact at the nodes of
      bilinear elements; with --cfrd the same column through cfrd (peer/cfrd-column).
  python3 tools/ccx_peer.py --thin --cfrd CFRD --workdir DIR
      The thin-layer interface (issue 6, section 4): two elastic blocks (8 x 2 quads each, 8 m
      wide, 2 m high, E 50 MPa, nu 0.25, 20 kN/m3) with a 0.1 m thin layer between them (E 1
      MPa, nu 0.3, weightless: the paper's soft layer), under their own weight and a 100 kPa
      surface load on the right half of the top, bottom fixed. cfrd reads the layer from
      INTERFACE cards (TYPE THIN, built from node pairs); CalculiX gets the same quads as CPE4.
  python3 tools/ccx_peer.py --staged --cfrd CFRD [--elements 1000 --layers 10] --workdir DIR
      Layer-by-layer construction (issue 4). For a linear elastic body built in layers, the
      staged solution is a superposition: placing layer k adds the static solution of the mesh
      of layers 1..k under the weight of layer k alone, every node starting from zero when it
      first appears. So N ordinary CalculiX runs, run k on the sub-mesh of layers 1..k with
      gravity on layer k only, summed node by node, give the staged displacements with no
      staging feature of CalculiX at all. (CalculiX 2.20 adds elements strain-free only in
      NLGEOM steps, and its removed elements' free nodes made that route fail.) The two-zone
      embankment is built in N layers and run by cfrd with NEWTOP = 1 (a node's displacement
      counts from its creation: the plain sum) and NEWTOP = 0 (from the completion of its
      layer: the sum over the layers above it only); each against the CalculiX sums.
  python3 tools/ccx_peer.py --contact --cfrd CFRD [--penalty-study] --workdir DIR
      Frictional contact (issue 7, section 2; the case and what CalculiX is given:
      docs/theory.md section 14, "Verification"). A slab (40 x 2 quads) on a cushion block (30
      x 6, non-matching), mu = 0.5, on a 1 : 1.4 slope, its toe held, the base settling, water
      on the slab. Asserted: the normal and tangential resultants of the contact force on the
      slab within 1 % of CalculiX's; the same open zones (gap > 1e-4 m, measured the same way
      for both), each as long within one slab element; and that the case has two open zones, a
      closed part, and slave nodes that stick and that slip. --penalty-study: the resultants
      against CalculiX's K and lambda (the table of docs/theory.md section 14).
"""

import math
import os
import sys

import numpy as np

import embankment as emb
from cfrdtools import ccx, results, runner
from cfrdtools.ccx import RunError, displacement_array, run_ccx, timed_run
from cfrdtools.checks import Checks, parser
from cfrdtools.decks import fmt_alpha as a, fmt_int as f, fmt_real as r
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


# --- the thin layer

NX, NY, W, HB, D = 8, 2, 8.0, 2.0, 0.1   # quads, width, block height, layer (m)
BLOCK = (5.0e4, 0.25, 20.0)
LAYER = (1.0e3, 0.3, 0.0)
P = 100.0                        # kPa on the right half of the top


def thin_mesh():
    xy = [(W * i / NX, y0 + HB * j / NY) for y0 in (0.0, HB + D) for j in range(NY + 1)
          for i in range(NX + 1)]
    nb = (NX + 1) * (NY + 1)
    conn = [(a_, a_ + 1, a_ + NX + 2, a_ + NX + 1) for block in (0, 1) for j in range(NY)
            for i in range(NX) for a_ in [block * nb + j * (NX + 1) + i + 1]]
    pairs = [(NY * (NX + 1) + i + 1, nb + i + 1) for i in range(NX + 1)]
    layer = [(b0, b1, t1, t0) for (b0, t0), (b1, t1) in zip(pairs, pairs[1:])]
    loaded = [e for e in range(2 * NX * NY - NX, 2 * NX * NY) if e % NX >= NX // 2]  # 0-based
    return np.array(xy), conn, pairs, layer, loaded


def thin_cfrd(path, xy, conn, pairs, loaded):
    out = ["TITLE     thin-layer peer: two blocks and a soft layer", "NODES"]
    out += [f(k) + " " * 10 + r(x) + r(y) for k, (x, y) in enumerate(xy, 1)]
    out += ["ELEMENTS"] + [f(e) + "".join(f(n) for n in c) + f(1) for e, c in enumerate(conn, 1)]
    out += ["MATERIALS", f(1) + a("ELASTIC") + "block", r(BLOCK[0]) + r(BLOCK[1]) + r(BLOCK[2]),
            f(2) + a("ELASTIC") + "thin layer", r(LAYER[0]) + r(LAYER[1]) + r(LAYER[2]),
            "INTERFACE", f(1) + f(pairs[0][0]) + f(pairs[0][1]) + f(NX) + f(1) + f(1) + f(2)
            + a("THIN"), "BOUNDARY", f(1) + f(NX + 1) + f(1) + f(1) + f(1), "LOADS", "GRAVITY"]
    runner.write_deck(path, out + [a("PRESSURE") + f(e + 1) + f(3) + r(P) for e in loaded]
                      + ["END"])


def thin_ccx(path, xy, conn, layer, loaded):
    out = ccx.node_cards(xy) + ccx.element_cards("EBLOCK", conn, range(1, len(conn) + 1))
    out += ccx.element_cards("ELAYER", layer, range(len(conn) + 1, len(conn) + len(layer) + 1))
    out += ["*NSET, NSET=NALL, GENERATE", f"1, {len(xy)}, 1",
            "*NSET, NSET=NBASE, GENERATE", f"1, {NX + 1}, 1"]
    out += ccx.material_cards("MBLOCK", *BLOCK, elset="EBLOCK")
    out += ccx.material_cards("MLAYER", *LAYER, elset="ELAYER", density="1e-30")
    out += ["*BOUNDARY", "NBASE, 1, 2", "*STEP", "*STATIC", "*DLOAD",
            "EBLOCK, GRAV, 9.81, 0., -1., 0."] + [f"{e + 1}, P3, {P!r}" for e in loaded]
    runner.write_deck(path, out + ["*NODE PRINT, NSET=NALL", "U", "*END STEP"])


def check_thin(check, cfrd, workdir):
    xy, conn, pairs, layer, loaded = thin_mesh()
    deck = os.path.join(workdir, "thin.dat")
    thin_cfrd(deck, xy, conn, pairs, loaded)
    thin_ccx(os.path.join(workdir, "thin_ccx.inp"), xy, conn, layer, loaded)
    run = runner.run(cfrd, deck, check=False)
    if run.returncode != 0:
        return check("ccx-thin-layer", False, f"cfrd exit {run.returncode}: {run.stderr[:300]}")
    run_ccx(workdir, "thin_ccx")
    u_ccx = displacement_array(os.path.join(workdir, "thin_ccx.dat"), len(xy))
    with open_results(runner.h5_of(deck)) as h5:
        u = results.read(h5, "displacement")
    diff = relative_difference(u if u.shape == u_ccx.shape else u.T, u_ccx)
    check("ccx-thin-layer", diff <= DU_TOL, f"{len(layer)} thin-layer quads from INTERFACE "
          f"pairs vs CalculiX CPE4: max |u_cfrd - u_ccx| / max |u_ccx| = {diff:.2e} (tol 1e-6;"
          f" max |u| {np.abs(u_ccx).max():.4e} m)")


# --- layer-by-layer construction


def ccx_submesh_deck(mesh, layer_of_elem, k, path):
    """The mesh of layers 1..k, base fixed, gravity on layer k only (CPE4, thickness 1)."""
    keep = np.nonzero(layer_of_elem <= k)[0]
    nodes = np.unique(mesh.conn[keep].ravel())
    out = ["** layers 1.." + str(k) + " of " + mesh.title] + ccx.node_cards(
        mesh.coords[nodes - 1], nodes)
    sets = []
    for m in sorted(mesh.materials):
        for top in "BT":
            sel = [e for e in keep if mesh.mat[e] == m and (layer_of_elem[e] == k) == (top == "T")]
            if sel:
                sets.append(f"E{m}{top}")
                out += ccx.element_cards(sets[-1], mesh.conn[sel], np.array(sel) + 1)
    out += ["*ELSET, ELSET=EALL"] + sets + ["*ELSET, ELSET=ETOP"] + [s for s in sets
                                                                   if s.endswith("T")]
    out += ccx.set_cards("NSET", "NBASE", [n for n in mesh.base_nodes() if n in set(nodes)])
    out += ccx.set_cards("NSET", "NALL", nodes)
    for m in sorted(mesh.materials):
        out += ccx.material_cards(f"MAT{m}", *mesh.materials[m][:3])
        for s in (s for s in sets if s[1:-1] == str(m)):
            out += [f"*SOLID SECTION, ELSET={s}, MATERIAL=MAT{m}", "1.0"]
    out += ["*BOUNDARY", "NBASE, 1, 2", "*STEP", "*STATIC", "*DLOAD",
            f"ETOP, GRAV, {ccx.GRAVITY_G!r}, 0., -1., 0.", "*NODE PRINT, NSET=NALL", "U",
            "*END STEP"]
    runner.write_deck(path, out)
    return nodes


def check_staged(check, cfrd, workdir, elements, layers):
    mesh = emb.embankment_mesh(elements, free=True)
    mesh.layers = layers
    layer_of_elem = np.array([mesh.layer_of_row(e // mesh.ncol) for e in range(mesh.nelem)])
    layer_of_node = np.full(mesh.nnode, 10 ** 9)
    for e in range(mesh.nelem):
        layer_of_node[mesh.conn[e] - 1] = np.minimum(layer_of_node[mesh.conn[e] - 1],
                                                     layer_of_elem[e])
    total = np.zeros((mesh.nnode, 2))          # NEWTOP = 1: every run counts
    above = np.zeros((mesh.nnode, 2))          # NEWTOP = 0: runs of later layers only
    for k in range(1, layers + 1):
        name = f"layers-{k:03d}"
        nodes = ccx_submesh_deck(mesh, layer_of_elem, k, os.path.join(workdir, name + ".inp"))
        try:
            run_ccx(workdir, name)
        except RunError as exc:
            return check("staged", False, f"CalculiX failed on layers 1..{k}: {exc}")
        disp = ccx.read_displacements(os.path.join(workdir, name + ".dat"))
        for n in nodes:
            total[n - 1] += disp[n][:2]
            if layer_of_node[n - 1] < k:
                above[n - 1] += disp[n][:2]
    for newtop, ref in ((1, total), (0, above)):
        lines = emb.deck_lines(mesh)
        lines[lines.index("CONTROL") + 1] += f", {newtop}"    # free format: NEWTOP after UNITS
        h5 = runner.run_text(cfrd, os.path.join(workdir, f"staged-newtop{newtop}.dat"), lines)
        with open_results(h5) as h:
            err = relative_difference(results.read(h, "displacement"), ref)
        check(f"staged-newtop{newtop}", err <= DU_TOL, f"{layers} layers, {mesh.nelem} elements:"
              f" max |du|/max|u| = {err:.2e} (tol 1e-6; CalculiX superposition of {layers} runs)")


# --- frictional contact

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


def contact_mesh():
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


def contact_cfrd(path, m, slab_type=""):
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


def contact_ccx(path, m, penalty, stick):
    cr = ccx.real
    out = ["** contact peer of cfrd (tools/ccx_peer.py --contact)"] + ccx.node_cards(m["xy"],
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
    m = contact_mesh()
    deck = os.path.join(workdir, "contact.dat")
    contact_cfrd(deck, m, slab_type)
    contact_ccx(os.path.join(workdir, "contact_ccx.inp"), m, penalty, stick)
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
    for res in (a_, b_):
        res["gap"] = gaps(m["xy"], res["u"], m)
        res["zones"] = open_zones(x, res["gap"])
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
    ap = parser(__doc__, cfrd="", workdir="build/peer")
    ap.add_argument("--elements", type=int, default=1000)
    ap.add_argument("--free", action="store_true", help="write the cfrd deck in free format")
    ap.add_argument("--layers", type=int, default=10, help="--staged: construction layers")
    for case in ("column", "thin", "staged", "contact"):
        ap.add_argument("--" + case, action="store_true", help=f"the {case} case")
    ap.add_argument("--penalty", type=float, default=PENALTY,
                    help="--contact: CalculiX pressure-overclosure slope K, kPa/m")
    ap.add_argument("--stick", type=float, default=STICK,
                    help="--contact: CalculiX stick slope lambda, kPa/m")
    ap.add_argument("--slab-type", default="", choices=["", "Q4", "Q4S"],
                    help="--contact: cfrd's slab element (default blank: plain Q4, like CPE4)")
    ap.add_argument("--penalty-study", action="store_true", help="--contact: the K, lambda table")
    args = ap.parse_args(argv)
    if not args.cfrd and not args.column:
        ap.error("--cfrd is required (except with --column)")
    os.makedirs(args.workdir, exist_ok=True)
    check = Checks("ccx" if args.staged else "peer")
    if args.column:
        check_column(check, args.workdir, args.cfrd)
    elif args.thin:
        check_thin(check, args.cfrd, args.workdir)
    elif args.staged:
        check_staged(check, args.cfrd, args.workdir, args.elements, args.layers)
    elif args.contact and args.penalty_study:
        return penalty_study(args)
    elif args.contact:
        return check.guard("ccx-contact", check_case, args) or check.status
    else:
        check_embankment(check, args.cfrd, args.elements, args.workdir, args.free or None)
    return check.status


if __name__ == "__main__":
    sys.exit(main())
