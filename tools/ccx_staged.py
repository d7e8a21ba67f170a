#!/usr/bin/env python3
"""CalculiX as the independent peer of layer-by-layer construction (issue 4).

For a linear elastic body built in layers, the staged solution is a superposition: placing
layer k adds the static solution of the mesh of layers 1..k under the weight of layer k alone,
every node starting from zero when it first appears. So N ordinary CalculiX runs, run k on the
sub-mesh of layers 1..k with gravity on layer k only, summed node by node, give the staged
displacements with no staging feature of CalculiX at all. (CalculiX 2.20 adds elements
strain-free only in NLGEOM steps, and its removed elements' free nodes made that route fail;
the superposition needs neither.)

It builds the issue's two-zone embankment in N layers with tools/embankment.py, runs cfrd on
it with NEWTOP = 1 (a node's displacement counts from its creation: the plain sum) and
NEWTOP = 0 (from the completion of its layer: the sum over the layers above it only), and
compares each with the CalculiX sums: max |du| / max |u| <= 1e-6 (CalculiX prints 7 digits).

  python3 tools/ccx_staged.py --cfrd bin/cfrd [--elements 1000 --layers 10] [--workdir DIR]
"""
import argparse
import os
import subprocess
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
import embankment as emb
from cfrdtools import results, runner


def ccx_submesh_deck(mesh, layer_of_elem, k, path):
    """The mesh of layers 1..k, base fixed, gravity on layer k only (CPE4, thickness 1)."""
    keep = np.nonzero(layer_of_elem <= k)[0]
    nodes = np.unique(mesh.conn[keep].ravel())
    out = ["** layers 1.." + str(k) + " of " + mesh.title, "*NODE"]
    for n in nodes:
        x, y = mesh.coords[n - 1]
        out.append(f"{n}, {emb.ccx_real(x)}, {emb.ccx_real(y)}, 0.0")
    for m in sorted(mesh.materials):
        for top in (False, True):
            sel = [e for e in keep if mesh.mat[e] == m and (layer_of_elem[e] == k) == top]
            if not sel:
                continue
            out.append(f"*ELEMENT, TYPE=CPE4, ELSET=E{m}{'T' if top else 'B'}")
            out += [f"{e + 1}, " + ", ".join(str(v) for v in mesh.conn[e]) for e in sel]
    sets = [f"E{m}{t}" for m in sorted(mesh.materials) for t in "BT"
            if any(ln.endswith(f"ELSET=E{m}{t}") for ln in out)]
    out += ["*ELSET, ELSET=EALL"] + sets
    out += ["*ELSET, ELSET=ETOP"] + [s for s in sets if s.endswith("T")]
    base = [n for n in mesh.base_nodes() if n in set(nodes)]
    out += ["*NSET, NSET=NBASE"] + [", ".join(str(n) for n in base[i:i + 10])
                                    for i in range(0, len(base), 10)]
    out += ["*NSET, NSET=NALL"] + [", ".join(str(n) for n in nodes[i:i + 10])
                                   for i in range(0, len(nodes), 10)]
    for m in sorted(mesh.materials):
        e, nu, gam, _ = mesh.materials[m]
        out += [f"*MATERIAL, NAME=MAT{m}", "*ELASTIC", f"{emb.ccx_real(e)}, {emb.ccx_real(nu)}",
                "*DENSITY", emb.ccx_real(float(gam) / emb.GRAVITY_G)]
        for t in "BT":
            if f"E{m}{t}" in sets:
                out += [f"*SOLID SECTION, ELSET=E{m}{t}, MATERIAL=MAT{m}", "1.0"]
    out += ["*BOUNDARY", "NBASE, 1, 2", "*STEP", "*STATIC", "*DLOAD",
            f"ETOP, GRAV, {emb.GRAVITY_G!r}, 0., -1., 0.", "*NODE PRINT, NSET=NALL", "U",
            "*END STEP"]
    with open(path, "w") as f:
        f.write("\n".join(out) + "\n")
    return nodes


def run_cfrd(cfrd, mesh, newtop, workdir):
    lines = emb.deck_lines(mesh)
    i = lines.index("CONTROL") + 1
    lines[i] = lines[i] + f", {newtop}"          # free format: NEWTOP after UNITS
    deck = os.path.join(workdir, f"staged-newtop{newtop}.dat")
    with results.open_results(runner.run_text(cfrd, deck, lines)) as f:
        return results.read(f, "displacement")


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--cfrd", required=True)
    ap.add_argument("--elements", type=int, default=1000)
    ap.add_argument("--layers", type=int, default=10)
    ap.add_argument("--workdir", default="build/ccx-staged")
    a = ap.parse_args(argv)
    os.makedirs(a.workdir, exist_ok=True)
    mesh = emb.embankment_mesh(a.elements, free=True)
    mesh.layers = a.layers
    layer_of_elem = np.array([mesh.layer_of_row(e // mesh.ncol) for e in range(mesh.nelem)])
    layer_of_node = np.full(mesh.nnode, 10 ** 9)
    for e in range(mesh.nelem):
        for n in mesh.conn[e]:
            layer_of_node[n - 1] = min(layer_of_node[n - 1], layer_of_elem[e])

    total = np.zeros((mesh.nnode, 2))          # NEWTOP = 1: every run counts
    above = np.zeros((mesh.nnode, 2))          # NEWTOP = 0: runs of later layers only
    for k in range(1, a.layers + 1):
        name = os.path.join(a.workdir, f"layers-{k:03d}")
        nodes = ccx_submesh_deck(mesh, layer_of_elem, k, name + ".inp")
        done = subprocess.run(["ccx", "-i", os.path.basename(name)], cwd=a.workdir,
                              capture_output=True, text=True)
        if done.returncode != 0 or not os.path.exists(name + ".dat"):
            print(f"FAIL ccx/staged: CalculiX failed on layers 1..{k}: "
                  f"{done.stdout.strip()[-200:]}")
            return 1
        disp = emb.read_ccx_displacements(name + ".dat")
        for n in nodes:
            u = np.asarray(disp[n][:2])
            total[n - 1] += u
            if layer_of_node[n - 1] < k:
                above[n - 1] += u

    failed = 0
    for newtop, ref in ((1, total), (0, above)):
        u = run_cfrd(a.cfrd, mesh, newtop, a.workdir)
        err = np.max(np.abs(u - ref)) / np.max(np.abs(ref))
        ok = err <= 1e-6
        failed += not ok
        print(f"{'PASS' if ok else 'FAIL'} ccx/staged-newtop{newtop}: {a.layers} layers, "
              f"{mesh.nelem} elements: max |du|/max|u| = {err:.2e} (tol 1e-6; CalculiX "
              f"superposition of {a.layers} runs)")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
