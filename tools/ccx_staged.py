#!/usr/bin/env python3
"""CalculiX as the independent peer of layer-by-layer construction (issue 4).

For a linear elastic body built in layers, the staged solution is a superposition: placing
layer k adds the static solution of the mesh of layers 1..k under the weight of layer k alone,
every node starting from zero when it first appears. So N ordinary CalculiX runs, run k on the
sub-mesh of layers 1..k with gravity on layer k only, summed node by node, give the staged
displacements with no staging feature of CalculiX at all. (CalculiX 2.20 adds elements
strain-free only in NLGEOM steps, and its removed elements' free nodes made that route fail.)
The issue's two-zone embankment is built in N layers (tools/embankment.py) and run by cfrd
with NEWTOP = 1 (a node's displacement counts from its creation: the plain sum) and NEWTOP = 0
(from the completion of its layer: the sum over the layers above it only); each against the
CalculiX sums: max |du| / max |u| <= 1e-6 (CalculiX prints 7 digits).

  python3 tools/ccx_staged.py --cfrd bin/cfrd [--elements 1000 --layers 10] [--workdir DIR]
"""
import os
import subprocess
import sys

import numpy as np

import embankment as emb
from cfrdtools import ccx, results, runner
from cfrdtools.checks import Checks, parser


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


def main(argv=None):
    ap = parser(__doc__, cfrd=True, workdir="build/ccx-staged")
    ap.add_argument("--elements", type=int, default=1000)
    ap.add_argument("--layers", type=int, default=10)
    a = ap.parse_args(argv)
    os.makedirs(a.workdir, exist_ok=True)
    check = Checks("ccx")
    mesh = emb.embankment_mesh(a.elements, free=True)
    mesh.layers = a.layers
    layer_of_elem = np.array([mesh.layer_of_row(e // mesh.ncol) for e in range(mesh.nelem)])
    layer_of_node = np.full(mesh.nnode, 10 ** 9)
    for e in range(mesh.nelem):
        layer_of_node[mesh.conn[e] - 1] = np.minimum(layer_of_node[mesh.conn[e] - 1],
                                                     layer_of_elem[e])
    total = np.zeros((mesh.nnode, 2))          # NEWTOP = 1: every run counts
    above = np.zeros((mesh.nnode, 2))          # NEWTOP = 0: runs of later layers only
    for k in range(1, a.layers + 1):
        name = os.path.join(a.workdir, f"layers-{k:03d}")
        nodes = ccx_submesh_deck(mesh, layer_of_elem, k, name + ".inp")
        done = subprocess.run(["ccx", "-i", os.path.basename(name)], cwd=a.workdir,
                              capture_output=True, text=True)
        if done.returncode != 0 or not os.path.exists(name + ".dat"):
            check("staged", False, f"CalculiX failed on layers 1..{k}: "
                  f"{done.stdout.strip()[-200:]}")
            return 1
        disp = ccx.read_displacements(name + ".dat")
        for n in nodes:
            total[n - 1] += disp[n][:2]
            if layer_of_node[n - 1] < k:
                above[n - 1] += disp[n][:2]
    for newtop, ref in ((1, total), (0, above)):
        lines = emb.deck_lines(mesh)
        i = lines.index("CONTROL") + 1
        lines[i] += f", {newtop}"          # free format: NEWTOP after UNITS
        h5 = runner.run_text(a.cfrd, os.path.join(a.workdir, f"staged-newtop{newtop}.dat"),
                             lines)
        with results.open_results(h5) as f:
            err = np.max(np.abs(results.read(f, "displacement") - ref)) / np.max(np.abs(ref))
        check(f"staged-newtop{newtop}", err <= 1e-6, f"{a.layers} layers, {mesh.nelem} elements:"
              f" max |du|/max|u| = {err:.2e} (tol 1e-6; CalculiX superposition of {a.layers} runs)")
    return check.status


if __name__ == "__main__":
    sys.exit(main())
