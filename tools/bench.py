#!/usr/bin/env python3
"""Benchmark of cfrd (`make bench`): the timings of docs/performance.md.

(a) Rectangular blocks of 1e3, 1e4, 1e5 square quads (one material, base fixed, gravity):
    neq, nnz and the phase times from the .h5 solver attributes, the process's wall time and
    peak memory.
(b) The issue's embankment at 1e3, 1e4, 1e5 elements by cfrd and by CalculiX: wall times,
    their ratio, peak memories and the agreement max |du| / max |u|.
(c) The homogeneous IIIB E-B embankment in 20 layers: midpoint against Newton.
(d) Tianshengqiao-I, the whole 1996-1999 history, on the x1 .. x8 meshes: stages,
    increments, factorisations, iterations, analysis and process time, time per dof, the
    largest settlement; the Newton variant up to --tsq-newton-max. --convergence prints the
    mesh convergence of (d)'s midpoint runs found in --workdir (the August 1999 state: the
    largest settlement and where, on the mid-height row line El. 709.33 m, the gauges, the
    largest horizontal displacements; a Richardson estimate from the last three meshes).
(e) Tianshengqiao-I with each interface method on the same body mesh.
(f) The joint and contact decks with the effects of the EFFECTS card switched on one at a
    time over a base with all of them off.

  python3 tools/bench.py [--cfrd bin/cfrd] [--workdir build/bench] [--repeat 1]
                         [--sizes 1000,10000,100000] [--markdown FILE] [--no-ccx]
  python3 tools/bench.py --only-tianshengqiao      # table (d) alone (--only-interfaces (e),
  python3 tools/bench.py --convergence             #  --only-effects (f)); then (d)'s meshes

Each case runs --repeat times, the minimum wall time reported. Decks above 99999 nodes or
elements cannot be written in fixed columns (I5): those use the '&' free format (column
"deck"). Peak memory is each child's own maximum RSS (GNU time %M, or getrusage in a separate
process), never a running maximum over several runs.
"""

import argparse
import math
import os
import resource
import subprocess
import sys

import numpy as np

import ccx_peer as peer
import embankment as emb
from accuracy_cost import richardson
from cfrdtools import ccx, results, runner, tables
from cfrdtools.decks import EFFECTS, with_effects

IIIB = (2100 * 9.81 / 1000, 564.0, 0.35, 0.85, 204.0, 0.18, 1128.0, 51.0, 13.0)
MID_ROW = 709.3333333
PHASES = ("t_pattern", "t_assembly", "t_symbolic", "t_numeric", "t_solve")


def block_shape(n, ratio=2.5):
    """nx, ny with nx*ny == n when a factor pair exists, nx/ny nearest ratio (log scale)."""
    best = None
    for ny in (ny for ny in range(1, int(math.isqrt(n)) + 1) if n % ny == 0):
        score = abs(math.log(n // ny / ny / ratio))
        if best is None or score <= best[0] + 1e-12:   # ties: the squarer block
            best = (score, n // ny, ny)
    if best is None or best[0] > 1.0:      # no decent factor pair: round instead
        ny = max(1, round(math.sqrt(n / ratio)))
        return max(1, round(n / ny)), ny
    return best[1], best[2]


def repeat_run(fn, repeat):
    """fn() -> (wall, rss, ...); min wall over repeat runs, the largest rss seen."""
    best, rss_max = None, None
    for _ in range(repeat):
        out = fn()
        if best is None or out[0] < best[0]:
            best = out
        if out[1] is not None:
            rss_max = out[1] if rss_max is None else max(rss_max, out[1])
    return best, rss_max


def mb(kb):
    return "-" if kb is None else f"{kb / 1024:.0f}"


def sec(t):
    if t is None or (isinstance(t, float) and math.isnan(t)):
        return "-"
    return f"{t:.3f}" if t < 10 else f"{t:.1f}"


def table(header, rows, align):
    """Plain aligned text table and the same as markdown."""
    return tables.aligned(header, rows, {k for k, a in enumerate(align) if a == "r"}), \
        tables.markdown(header, rows, align)


def figures(h5):
    """What the analysis did (results.summary: counts, times, solver sums over the stages), the
    largest settlement since placement and its elevation."""
    with results.open_results(h5) as f:
        st = results.stages(f)
        sv = [g["solver"].attrs for g in st]
        u, x = results.field(st[-1], "displacement_total"), f["mesh/coordinates"][...]
        k = int(u[:, 1].argmin())
        return dict(results.summary(f, (
            "numeric_factorisations", "updates", "contact_iterations", "searches", "t_contact",
            "t_symbolic", "t_numeric", "t_solve", "t_update", "t_assembly")),
                    nelem=f["mesh/connectivity"].shape[0], neq=int(sv[-1]["neq"]),
                    neq_max=max(int(a["neq"]) for a in sv),
                    # increments of the stages with contact unknowns (slab placed)
                    cinc=sum(int(g.attrs["increments"]) for g, a in zip(st, sv)
                             if results.total([a], "contact_iterations") > 0),
                    settl=float(-u[k, 1]), elev=float(x[k, 1]),
                    settl_u=float(-st[-1]["displacement"][:, 1].min()))


def failure(done):
    return (done.stderr.strip().splitlines() or ["?"])[-1][:90]


def bench_blocks(cfrd, sizes, workdir, repeat):
    """(a) Phase times from the HDF5 file; 'total' is pattern + assembly + symbolic + numeric
    + solve (the issue's 'assemble + factor + solve'), 'asm %' the share of pattern and
    assembly in it, 'wall' the whole process (reading, analysis, writing both files)."""
    rows = []
    for n in sizes:
        nx, ny = block_shape(n)
        try:
            mesh, form = emb.block_mesh(nx, ny), "fixed"
            emb.deck_lines(mesh)
        except emb.FieldOverflow:
            mesh, form = emb.block_mesh(nx, ny, free=True), "free"
        deck = os.path.join(workdir, f"block-{mesh.nelem}.dat")
        emb.write_cfrd_deck(mesh, deck)
        row = dict(case=f"{nx} x {ny}", nelem=mesh.nelem, nnode=mesh.nnode, form=form)

        def run_and_read():       # the phase times of each run, to report the fastest's
            wall, rss, h5 = peer.run_cfrd(cfrd, deck, workdir)
            return wall, rss, h5, peer.read_cfrd(h5)
        try:
            (wall, _, h5, res), rss = repeat_run(run_and_read, repeat)
            row.update(wall=wall, rss=rss, **res["solver"])
            # Sanity figure, not a test: sum of reactions against the block's weight.
            row["balance"] = abs(res["reaction"][:, 1].sum() - mesh.total_weight()) \
                / mesh.total_weight()
        except (ccx.RunError, OSError, KeyError) as exc:
            row["error"] = str(exc)
        rows.append(row)
        print(f"  block {row['case']}: " + (row.get("error") or f"{sec(row['wall'])} s"),
              file=sys.stderr, flush=True)
    cells = []
    for r in rows:
        cells.append([r["case"], str(r["nelem"]), str(r["nnode"]), r["form"]])
        if "error" in r:
            cells[-1] += ["-"] * 11
            continue
        total = sum(r.get(k, float("nan")) for k in PHASES)
        share = 100.0 * (r.get("t_pattern", 0.0) + r.get("t_assembly", 0.0)) / total
        cells[-1] += [str(int(r.get("neq", 0))), str(int(r.get("nnz", 0)))] + \
            [sec(r.get(k)) for k in PHASES] + [sec(total), f"{share:.0f}", sec(r["wall"]),
                                               mb(r["rss"])]
    return rows, table(["mesh", "elements", "nodes", "deck", "neq", "nnz", "pattern s",
                        "assembly s", "symbolic s", "numeric s", "solve s", "total s", "asm %",
                        "wall s", "peak MB"], cells, "lrrlrr" + "r" * 9)


def bench_embankment(cfrd, sizes, workdir, repeat, with_ccx):
    """(b) cfrd against CalculiX (CPE4) on the same mesh."""
    rows = []
    for n in sizes:
        mesh, form = peer.mesh_for(n)
        deck, job = os.path.join(workdir, f"embankment-{n}.dat"), f"embankment-{n}-ccx"
        emb.write_cfrd_deck(mesh, deck)
        row, u_ccx, u = dict(nelem=mesh.nelem, nnode=mesh.nnode, form=form), None, None
        if with_ccx:
            emb.write_ccx_deck(mesh, os.path.join(workdir, job + ".inp"))
            try:
                (t, _), rss = repeat_run(lambda: peer.run_ccx(workdir, job), repeat)
                row.update(t_ccx=t, rss_ccx=rss)
                u_ccx = ccx.displacement_array(os.path.join(workdir, job + ".dat"), mesh.nnode)
            except (ccx.RunError, ValueError) as exc:
                row["error_ccx"] = str(exc)
        if cfrd:
            try:
                (t, _, h5), rss = repeat_run(lambda: peer.run_cfrd(cfrd, deck, workdir), repeat)
                row.update(t_cfrd=t, rss_cfrd=rss)
                u = peer.read_cfrd(h5)["u"]
            except (ccx.RunError, OSError, KeyError) as exc:
                row["error_cfrd"] = str(exc)
        if u is not None and u_ccx is not None and u.shape == u_ccx.shape:
            row["du"] = peer.relative_difference(u, u_ccx)
        if row.get("t_cfrd") and row.get("t_ccx"):
            row["ratio"] = row["t_cfrd"] / row["t_ccx"]
        rows.append(row)
        print(f"  embankment {n}: cfrd {sec(row.get('t_cfrd'))} s, ccx {sec(row.get('t_ccx'))} s",
              file=sys.stderr, flush=True)
    cells = [[str(r["nelem"]), str(r["nnode"]), r["form"], sec(r.get("t_cfrd")),
              sec(r.get("t_ccx")), f"{r['ratio']:.2f}" if "ratio" in r else "-",
              mb(r.get("rss_cfrd")), mb(r.get("rss_ccx")),
              f"{r['du']:.1e}" if "du" in r else "-"] for r in rows]
    return rows, table(["elements", "nodes", "deck", "cfrd wall s", "ccx wall s", "cfrd/ccx",
                        "cfrd peak MB", "ccx peak MB", "max|du|/max|u|"], cells, "rrlrrrrrr")


def bench_staged(cfrd, sizes, workdir, newton_max=10000):
    """(c) The homogeneous IIIB E-B embankment built in 20 layers, midpoint (2 increments a
    layer) and Newton (SOLVER = 3, tolerance 1e-6)."""
    cells = []
    for n in sizes:
        for solver in ("midpoint", "newton")[:2 if n <= newton_max else 1]:
            # (Newton: about 40 min at 1e5 elements, docs/performance.md)
            mesh = emb.embankment_mesh(n, free=True)
            mesh.layers, mesh.layer_increments, mesh.eb = 20, 2, {1: IIIB, 2: IIIB}
            lines = emb.deck_lines(mesh)
            if solver == "newton":      # the free CONTROL card: NEWTOP 0, SOLVER 3, TOL, MAXIT
                lines[lines.index("CONTROL") + 1] += ", 0, 3, 1e-6, 20"
            deck = runner.write_deck(os.path.join(workdir, f"staged-{mesh.nelem}-{solver}.dat"),
                                     lines)
            done = runner.run(cfrd, deck, check=False)
            wall = done.wall
            if done.returncode != 0:
                cells.append([str(mesh.nelem), solver] + ["-"] * 6 +
                             [sec(wall), "-", "failed: " + failure(done)])
            else:
                r = figures(deck[:-4] + ".h5")
                inc, fact = r["increments"], r["factorisations"]
                cells.append([str(mesh.nelem), solver, str(inc), str(fact), str(r["iterations"]),
                              f"{r['iterations'] / inc:.2f}", f"{r['resid']:.1e}",
                              f"{r['settl_u']:.4f}", sec(wall), f"{wall / inc:.4f}",
                              f"{wall / fact:.4f}"])
            print(f"  staged {mesh.nelem} {solver}: {sec(wall)} s "
                  f"{failure(done) if done.returncode else ''}", file=sys.stderr, flush=True)
    return table(["elements", "solver", "increments", "factorisations", "Newton it.",
                  "it./increment", "max resid", "max settl. m", "wall s", "s/increment",
                  "s/factorisation"], cells, "rlrrrrrrrrr")


def tianshengqiao_runs(cfrd, decks, repeat):
    """Each (deck, label) run `repeat` times: (label, wall of the fastest, its figures or
    the failure, the children's peak RSS so far)."""
    out = []
    for deck, label in decks:
        done, fig = runner.best_of(cfrd, deck, repeat, keep=lambda d: failure(d) if d.returncode
                                   else figures(deck[:-4] + ".h5"))
        out.append((label, done.wall, fig, resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss))
        print(f"  tianshengqiao {' '.join(label)}: {sec(done.wall)} s "
              f"{fig if isinstance(fig, str) else ''}", file=sys.stderr, flush=True)
    return out


def bench_tianshengqiao(cfrd, refinements, workdir, repeat, newton_max=2):
    """(d) The history at each refinement: midpoint (the paper's method, the deck's default)
    and, up to newton_max, the Newton variant (SOLVER 3, TOL 1e-10)."""
    decks = [(runner.tianshengqiao(os.path.join(workdir, f"tianshengqiao-x{r}-{solver}.dat"),
                                   "--refine", r, "--solver", solver), (f"x{r}", solver))
             for r in refinements for solver in ("midpoint", "newton")
             if solver == "midpoint" or r <= newton_max]
    cells = []
    for label, wall, f, _ in tianshengqiao_runs(cfrd, decks, repeat):
        cells.append(list(label) + (["-"] * 7 + [sec(wall), "-", "failed: " + f, "-"]
                                    if isinstance(f, str) else
                                    [str(f[k]) for k in ("nelem", "neq", "stages", "increments",
                                                         "factorisations", "iterations")]
                                    + [sec(f["analysis"]), sec(wall),
                                       f"{1e6 * f['analysis'] / f['neq']:.0f}",
                                       f"{f['settl']:.4f}", f"{f['elev']:.1f}"]))
    return table(["mesh", "solver", "elements", "equations", "stages", "increments",
                  "factorisations", "Newton it.", "analysis s", "process s", "us/dof",
                  "max settl. m", "at El. m"], cells, "llrrrrrrrrrrr")


def convergence(workdir, refinements):
    """The mesh convergence of (d)'s midpoint runs in workdir (markdown)."""
    rows = []
    for r in refinements:
        h5 = os.path.join(workdir, f"tianshengqiao-x{r}-midpoint.h5")
        if not os.path.exists(h5):
            continue
        with results.open_results(h5) as f:
            x = f["mesh/coordinates"][...]
            u = results.field(results.last_stage(f), "displacement_total")
            names, nodes = results.gauges(f)
            k, row = int(np.argmin(u[:, 1])), np.abs(x[:, 1] - MID_ROW) < 1e-3
            out = {"elements": f["mesh/connectivity"].shape[0], "max settlement m": -u[k, 1],
                   "at x, El. m": f"{x[k, 0]:.1f}, {x[k, 1]:.1f}",
                   "max settl. El. 709.3 m": float(np.max(-u[row, 1]))}
        for name, node in zip(names, nodes):
            out[f"{name} settl. m" if "-V" in name else f"{name} ux m"] = \
                -u[node, 1] if "-V" in name else u[node, 0]
        out["max ux downstream m"], out["max ux upstream m"] = float(u[:, 0].max()), \
            float(-u[:, 0].min())
        rows.append((r, out))
    lines = [tables.row(["quantity"] + [f"x{r}" for r, _ in rows] + ["Richardson"]),
             "|:---|" + "---:|" * (len(rows) + 1)]
    for key in rows[0][1] if rows else ():
        vals = [f[key] for _, f in rows]
        rich = richardson(*vals[-3:]) if len(vals) >= 3 and all(
            isinstance(v, float) for v in vals[-3:]) else None
        lines.append(tables.row([key] + [v if isinstance(v, str) else f"{v:.4f}" if isinstance(
            v, float) else str(v) for v in vals] + [f"{rich[0]:.4f}" if rich else "-"]))
    return "\n".join(lines)


def bench_interfaces(cfrd, refinements, workdir, repeat, interfaces=("bonded", "joint",
                                                                      "contact")):
    """(e) The history with each slab-cushion interface on the same body mesh: the solver
    and contact figures summed over the stages."""
    decks = [(runner.tianshengqiao(os.path.join(workdir, f"tianshengqiao-x{r}-{i}.dat"),
                                   "--refine", r, "--interface", i), (f"x{r}", i))
             for r in refinements for i in interfaces]
    cells = []
    for (mesh, interface), wall, f, _ in tianshengqiao_runs(cfrd, decks, repeat):
        if isinstance(f, str):
            cells.append([mesh, interface] + ["-"] * 11 + [sec(wall) + " failed: " + f])
            continue
        contact = interface == "contact"
        cells.append([mesh, interface] + [str(int(f[k])) for k in (
            "nelem", "neq_max", "increments", "numeric_factorisations", "updates")] + (
            [str(int(f["contact_iterations"])), "%.2f" % (f["contact_iterations"] / max(
                f["cinc"], 1)), f"{f['t_contact']:.3f}"] if contact else ["-"] * 3) + [
            sec(f["t_assembly"]), sec(sum(f[k] for k in ("t_symbolic", "t_numeric", "t_solve",
                                                        "t_update"))),
            sec(f["analysis"]), sec(wall)])
    return table(["mesh", "interface", "elements", "equations", "increments", "factorisations",
                  "updates", "contact solves", "solves/increment", "search s", "assembly s",
                  "solver s", "analysis s", "process s"], cells, "llrrrrrrrrrrrr")


# (f) Only the effects a deck asks for: the EFFECTS card (docs/cards.md), each effect switched
# on alone over a base with all of them off. UNLOAD acts only on the nonlinear law, so its row
# switches both on.
EFFECT_OFF = dict(ROCKFILL="LINEAR", UNLOAD="OFF", WATER="OFF", INTERFACE="BONDED",
                  FRICTION="OFF", SLIP="SMALL", PHASES="OFF")
EFFECT_ROWS = (("all off", ()), ("+ nonlinear rockfill", ("ROCKFILL",)),
               ("+ unload-reload", ("ROCKFILL", "UNLOAD")), ("+ water", ("WATER",)),
               ("+ joints", ("INTERFACE",)), ("+ friction", ("FRICTION",)),
               ("+ large slip", ("SLIP",)), ("+ slab phases", ("PHASES",)),
               ("all on (the deck)", EFFECTS))


def bench_effects(cfrd, refinements, workdir, repeat):
    """(f) The joint and contact decks with the effects switched on one at a time: process
    wall time (minimum of `repeat`), peak memory, and what the analysis did."""
    applies = dict(joint=("ROCKFILL", "UNLOAD", "WATER", "INTERFACE", "PHASES"),
                   contact=("ROCKFILL", "UNLOAD", "WATER", "FRICTION", "SLIP", "PHASES"))
    cells = []
    for r in refinements:
        for interface in ("joint", "contact"):
            base = os.path.join(workdir, f"effects-x{r}-{interface}.dat")
            text = open(runner.tianshengqiao(base, "--refine", r, "--interface", interface)).read()
            for label, on in EFFECT_ROWS:
                if any(e not in applies[interface] for e in on) and on != EFFECTS:
                    continue
                deck = runner.write_deck(os.path.join(
                    workdir, f"effects-x{r}-{interface}-{len(cells)}.dat"), with_effects(
                    text, **{e: EFFECT_OFF[e] for e in applies[interface] if e not in on}))
                try:         # the figures of each run, so that they belong to the run reported
                    (wall, _, fig), rss = repeat_run(lambda: peer.run_cfrd(cfrd, deck, workdir)[:2]
                                                     + (figures(deck[:-4] + ".h5"),), repeat)
                except (ccx.RunError, OSError) as exc:
                    cells.append([f"x{r}", interface, label] + ["-"] * 6
                                 + [f"failed: {str(exc)[:60]}"])
                    continue
                cells.append([f"x{r}", interface, label] + [str(int(fig[k])) for k in (
                    "stages", "increments", "numeric_factorisations", "searches")] + [
                    f"{fig['t_contact']:.3f}", sec(fig["analysis"]), sec(wall), mb(rss)])
                print(f"  effects x{r} {interface} {label}: {sec(wall)} s", file=sys.stderr,
                      flush=True)
    return table(["mesh", "deck", "effects", "stages", "increments", "factorisations",
                  "searches", "contact s", "analysis s", "process s", "peak MB"], cells,
                 "lllrrrrrrrr")


def ccx_version():
    try:
        out = subprocess.run(["ccx", "-v"], capture_output=True, text=True, timeout=20).stdout
        ver = [w for w in out.split() if w[:1].isdigit()]
        return ver[-1] if ver else "(version unknown)"
    except (OSError, subprocess.SubprocessError):
        return "(not found)"


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--cfrd", default=os.path.join(runner.ROOT, "bin", "cfrd"))
    ap.add_argument("--workdir", default=os.path.join(runner.ROOT, "build", "bench"))
    ap.add_argument("--repeat", type=int, default=1, help="runs per case, minimum taken")
    ap.add_argument("--sizes", default="1000,10000,100000",
                    help="comma-separated element counts (default 1000,10000,100000)")
    ap.add_argument("--markdown", help="also write the tables as markdown to this file")
    ap.add_argument("--no-ccx", action="store_true", help="skip CalculiX")
    ap.add_argument("--staged-sizes", default="1000,10000,100000",
                    help="element counts of the staged E-B embankment (empty: skip)")
    ap.add_argument("--newton-max", type=int, default=10000,
                    help="largest staged case also run with Newton iterations")
    ap.add_argument("--tsq-refine", default="1,2,4,8",
                    help="Tianshengqiao-I refinements for table (d) (empty: skip)")
    ap.add_argument("--tsq-newton-max", type=int, default=2,
                    help="largest Tianshengqiao-I refinement also run with Newton")
    ap.add_argument("--only-tianshengqiao", action="store_true", help="table (d) only")
    ap.add_argument("--convergence", action="store_true",
                    help="the mesh convergence of table (d)'s runs in --workdir only")
    ap.add_argument("--interface-refine", default="1,4",
                    help="Tianshengqiao-I refinements for table (e), the interface methods"
                         " (empty: skip)")
    ap.add_argument("--only-interfaces", action="store_true", help="table (e) only")
    ap.add_argument("--effects-refine", default="1,2",
                    help="Tianshengqiao-I refinements for table (f), the effects (empty: skip)")
    ap.add_argument("--only-effects", action="store_true", help="table (f) only")
    args = ap.parse_args(argv)
    tsq, ifr, efr = ([int(x) for x in s.split(",") if x.strip()] for s in (
        args.tsq_refine, args.interface_refine, args.effects_refine))
    if args.convergence:
        print(convergence(args.workdir, tsq))
        return 0
    os.makedirs(args.workdir, exist_ok=True)
    mach = runner.machine()
    cfrd = args.cfrd if os.access(args.cfrd, os.X_OK) else None
    tsq_tables = (
        (args.only_tianshengqiao, tsq, lambda: bench_tianshengqiao(
            cfrd, tsq, args.workdir, args.repeat, args.tsq_newton_max),
         "(d) Tianshengqiao-I, the whole 1996-1999 history", "**(d) Tianshengqiao-I, the "
         "whole 1996-1999 history** (tools/tianshengqiao.py meshes; midpoint as in the paper, "
         "Newton to 1e-10).", "(d) Tianshengqiao-I, 1996-1999 history"),
        (args.only_interfaces, ifr, lambda: bench_interfaces(cfrd, ifr, args.workdir,
                                                             args.repeat),
         "(e) Tianshengqiao-I, the interface methods on the same body mesh", "**(e) "
         "Tianshengqiao-I, the interface methods** (bonded, Goodman joints, contact; the same "
         "body mesh; sums over the stages).", "(e) Tianshengqiao-I, interface methods"),
        (args.only_effects, efr, lambda: bench_effects(cfrd, efr, args.workdir, args.repeat),
         "(f) Tianshengqiao-I, the effects switched on one at a time", "**(f) Tianshengqiao-I, "
         "the effects switched on one at a time** (the EFFECTS card; the joint and contact "
         "decks of the same body mesh).", "(f) Tianshengqiao-I, the effects switched on one "
         "at a time"))
    for only, _, bench, _, _, title in tsq_tables[::-1]:
        if only:        # one table alone: printed, and as markdown to --markdown
            cfrd = args.cfrd
            t, m = bench()
            print(mach)
            print(title)
            print(t)
            if args.markdown:
                with open(args.markdown, "w") as f:
                    f.write(f"Machine: {mach}.\n\n{m}\n")
            return 0
    if cfrd is None:
        print(f"bench: no program at {args.cfrd} (build it with `make build`); "
              f"cfrd columns left empty", file=sys.stderr)
    notes = [f"Machine: {mach}.", f"Wall times are the minimum of {args.repeat} run(s) of the "
             f"whole process (reading the deck to writing the results); peak memory is the "
             f"process's maximum resident set. CalculiX {ccx_version()} with its default solver"
             f" (OMP_NUM_THREADS {os.environ.get('OMP_NUM_THREADS', 'unset')})."]
    sizes = [int(s) for s in args.sizes.split(",") if s.strip()]
    block_rows, (t_a, m_a) = bench_blocks(cfrd, sizes, args.workdir, args.repeat) if cfrd \
        else ([], (None, None))
    emb_rows, (t_b, m_b) = bench_embankment(cfrd, sizes, args.workdir, args.repeat,
                                            not args.no_ccx)
    out_text, out_md = [mach, ""], ["\n".join(notes), ""]
    if block_rows:
        out_text += ["(a) cfrd on rectangular blocks of square quads, base fixed, gravity", t_a,
                     ""] + [f"block {r['case']}: {r['error']}" for r in block_rows if "error" in r]
        out_md += ["**(a) cfrd on rectangular blocks** of square quads (1 m), one material, "
                   "base fixed, gravity; phase times from the HDF5 solver attributes.", "", m_a,
                   ""]
    out_text += ["(b) embankment (H 178 m, slopes 1:1.4, two zones), cfrd vs CalculiX", t_b]
    out_text += [f"embankment {r['nelem']}: {r[key]}" for r in emb_rows
                 for key in ("error_cfrd", "error_ccx") if key in r]
    out_md += ["**(b) The embankment** (H 178 m, crest 12 m, slopes 1V:1.4H, two zones, "
               "gravity): cfrd against CalculiX (CPE4) on the same mesh.", "", m_b, ""]
    staged_sizes = [int(x) for x in args.staged_sizes.split(",") if x.strip()]
    if cfrd and staged_sizes:
        t, m = bench_staged(cfrd, staged_sizes, args.workdir, args.newton_max)
        out_text += ["", "(c) IIIB E-B embankment in 20 layers, 2 increments a layer", t]
        out_md += ["**(c) The homogeneous IIIB E-B embankment built in 20 layers** (2 "
                   "increments a layer): midpoint against Newton.", "", m, ""]
    for _, levels, bench, title, caption, _ in tsq_tables:
        if cfrd and levels:
            t, m = bench()
            out_text += ["", title, t]
            out_md += [caption, "", m, ""]
    print("\n".join(out_text))
    if args.markdown:
        with open(args.markdown, "w") as f:
            f.write("\n".join(out_md).rstrip() + "\n")
    failed = any("error" in r for r in block_rows) or \
        any("error_cfrd" in r or "error_ccx" in r for r in emb_rows)
    return 1 if failed or cfrd is None else 0


if __name__ == "__main__":
    sys.exit(main())
