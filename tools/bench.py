#!/usr/bin/env python3
"""Benchmark of cfrd (`make bench`): timings for docs/performance.md.

(a) Rectangular blocks of 1e3, 1e4, 1e5 square quads (one material, base fixed, gravity)
    run by cfrd --quiet: neq, nnz and the phase times from the .h5 solver attributes, the
    wall time of the whole process and its peak memory.
(b) The issue's embankment at 1e3, 1e4, 1e5 elements run by cfrd and by CalculiX (ccx):
    wall times, their ratio, peak memories, and the agreement max |du| / max |u|.
(c) The homogeneous IIIB E-B embankment in 20 layers: midpoint against Newton.
(d) Tianshengqiao-I, the whole 1996-1999 history, on the x1, x2, x4, x8 meshes
    (tools/tianshengqiao.py): stages, increments, factorisations, iterations, analysis and
    process wall time, time per dof, and the maximum settlement (mesh convergence); the
    Newton variant up to --tsq-newton-max.

(e) Tianshengqiao-I with each interface method on the same body mesh.
(f) The joint and contact decks with the effects of the EFFECTS card switched on one at a
    time over a base with all of them off: time, memory, factorisations, contact searches.

  python3 tools/bench.py --only-tianshengqiao      # table (d) alone
  python3 tools/bench.py --only-effects --repeat 5 # table (f) alone

  python3 tools/bench.py [--cfrd bin/cfrd] [--workdir build/bench] [--repeat 1]
                         [--sizes 1000,10000,100000] [--markdown FILE] [--no-ccx]

Each case runs --repeat times (default 1); the minimum wall time is reported. Decks above
99999 nodes or elements cannot be written in fixed columns (I5), so those use the '&' free
format (column "deck"). Peak memory is each child's own maximum RSS (GNU time %M, or
getrusage in a separate process), never a running maximum over several runs.
"""

import argparse

import numpy as np
import math
import os
import platform
import sys


HERE = os.path.dirname(os.path.abspath(__file__))
import ccx_peer as peer
import embankment as emb
from cfrdtools import results, runner

ROOT = os.path.dirname(HERE)


def machine():
    """CPU model, logical cores, memory: one line for the tables' caption."""
    model = platform.processor() or "unknown CPU"
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                if line.lower().startswith("model name"):
                    model = line.split(":", 1)[1].strip()
                    break
    except OSError:
        pass
    mem = "unknown"
    try:
        with open("/proc/meminfo") as f:
            for line in f:
                if line.startswith("MemTotal:"):
                    mem = f"{int(line.split()[1]) / 1024 ** 2:.1f} GiB"
                    break
    except OSError:
        pass
    cores = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count()
    return f"{model}, {cores} cores available, {mem} memory, {platform.system()} " \
           f"{platform.release()}, Python {platform.python_version()}"


def block_shape(n, ratio=2.5):
    """nx, ny with nx*ny == n when a factor pair exists, nx/ny nearest ratio (log scale)."""
    best = None
    for ny in range(1, int(math.isqrt(n)) + 1):
        if n % ny == 0:
            nx = n // ny
            score = abs(math.log(nx / ny / ratio))
            if best is None or score <= best[0] + 1e-12:   # ties: the squarer block
                best = (score, nx, ny)
    if best is None or best[0] > 1.0:      # no decent factor pair: round instead
        ny = max(1, round(math.sqrt(n / ratio)))
        return max(1, round(n / ny)), ny
    return best[1], best[2]


def writable_mesh(build):
    """build(free) -> mesh; fixed format when the deck fits its columns."""
    try:
        mesh = build(False)
        emb.deck_lines(mesh)
        return mesh, "fixed"
    except emb.FieldOverflow:
        return build(True), "free"


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


def bench_blocks(cfrd, sizes, workdir, repeat):
    rows = []
    for n in sizes:
        nx, ny = block_shape(n)
        mesh, form = writable_mesh(lambda free: emb.block_mesh(nx, ny, free=free))
        deck = os.path.join(workdir, f"block-{mesh.nelem}.dat")
        emb.write_cfrd_deck(mesh, deck)
        row = dict(case=f"{nx} x {ny}", nelem=mesh.nelem, nnode=mesh.nnode, form=form)
        def run_and_read():
            # Read the phase times right after each run, so that they belong to the run
            # whose wall time is reported (the fastest).
            wall, rss, h5 = peer.run_cfrd(cfrd, deck, workdir)
            return wall, rss, h5, peer.read_cfrd(h5)

        try:
            (wall, _, h5, res), rss = repeat_run(run_and_read, repeat)
            row.update(wall=wall, rss=rss, **res["solver"])
            # Sanity figure, not a test: sum of reactions against the block's weight.
            row["balance"] = abs(res["reaction"][:, 1].sum() - mesh.total_weight()) \
                / mesh.total_weight()
        except (peer.RunError, OSError, KeyError) as exc:
            row["error"] = str(exc)
        rows.append(row)
        print(f"  block {row['case']}: " + (row.get("error") or f"{sec(row['wall'])} s"),
              file=sys.stderr, flush=True)
    return rows


def bench_embankment(cfrd, sizes, workdir, repeat, with_ccx):
    rows = []
    for n in sizes:
        mesh, form = peer.mesh_for(n)
        name = f"embankment-{n}"
        deck = os.path.join(workdir, name + ".dat")
        emb.write_cfrd_deck(mesh, deck)
        row = dict(nelem=mesh.nelem, nnode=mesh.nnode, form=form)
        u_ccx = u = None
        if with_ccx:
            job = name + "-ccx"
            emb.write_ccx_deck(mesh, os.path.join(workdir, job + ".inp"))
            try:
                (t, _), rss = repeat_run(lambda: peer.run_ccx(workdir, job), repeat)
                row.update(t_ccx=t, rss_ccx=rss)
                u_ccx = emb.ccx_displacement_array(os.path.join(workdir, job + ".dat"),
                                                   mesh.nnode)
            except (peer.RunError, ValueError) as exc:
                row["error_ccx"] = str(exc)
        if cfrd:
            try:
                (t, _, h5), rss = repeat_run(lambda: peer.run_cfrd(cfrd, deck, workdir),
                                             repeat)
                row.update(t_cfrd=t, rss_cfrd=rss)
                u = peer.read_cfrd(h5)["u"]
            except (peer.RunError, OSError, KeyError) as exc:
                row["error_cfrd"] = str(exc)
        if u is not None and u_ccx is not None and u.shape == u_ccx.shape:
            row["du"] = peer.relative_difference(u, u_ccx)
        if row.get("t_cfrd") and row.get("t_ccx"):
            row["ratio"] = row["t_cfrd"] / row["t_ccx"]
        rows.append(row)
        print(f"  embankment {n}: cfrd {sec(row.get('t_cfrd'))} s, ccx {sec(row.get('t_ccx'))} s",
              file=sys.stderr, flush=True)
    return rows


def table(header, rows, align):
    """Plain aligned text table and the same as markdown."""
    widths = [max(len(h), *(len(r[i]) for r in rows)) for i, h in enumerate(header)]

    def fmt(cells):
        return "  ".join(c.rjust(w) if a == "r" else c.ljust(w)
                         for c, w, a in zip(cells, widths, align))
    text = [fmt(header), fmt(["-" * w for w in widths])] + [fmt(r) for r in rows]
    esc = lambda c: c.replace("|", "\\|")                  # noqa: E731
    md = ["| " + " | ".join(map(esc, header)) + " |",
          "|" + "|".join("---:" if a == "r" else ":---" for a in align) + "|"]
    md += ["| " + " | ".join(map(esc, r)) + " |" for r in rows]
    return "\n".join(text), "\n".join(md)


PHASES = ("t_pattern", "t_assembly", "t_symbolic", "t_numeric", "t_solve")


def block_table(rows):
    """Phase times from the run's HDF5 file; 'total' is pattern + assembly + symbolic +
    numeric + solve (the issue's 'assemble + factor + solve'), 'asm %' the share of pattern
    and assembly in it, 'wall' the whole process (reading, analysis, writing both files)."""
    header = ["mesh", "elements", "nodes", "deck", "neq", "nnz", "pattern s", "assembly s",
              "symbolic s", "numeric s", "solve s", "total s", "asm %", "wall s", "peak MB"]
    cells = []
    for r in rows:
        if "error" in r:
            cells.append([r["case"], str(r["nelem"]), str(r["nnode"]), r["form"]]
                         + ["-"] * (len(header) - 4))
            continue
        total = sum(r.get(k, float("nan")) for k in PHASES)
        share = 100.0 * (r.get("t_pattern", 0.0) + r.get("t_assembly", 0.0)) / total
        cells.append([r["case"], str(r["nelem"]), str(r["nnode"]), r["form"],
                      str(int(r.get("neq", 0))), str(int(r.get("nnz", 0)))]
                     + [sec(r.get(k)) for k in PHASES]
                     + [sec(total), f"{share:.0f}", sec(r["wall"]), mb(r["rss"])])
    return table(header, cells, "lrrlrr" + "r" * 9)


def embankment_table(rows):
    header = ["elements", "nodes", "deck", "cfrd wall s", "ccx wall s", "cfrd/ccx",
              "cfrd peak MB", "ccx peak MB", "max|du|/max|u|"]
    cells = []
    for r in rows:
        cells.append([str(r["nelem"]), str(r["nnode"]), r["form"], sec(r.get("t_cfrd")),
                      sec(r.get("t_ccx")),
                      f"{r['ratio']:.2f}" if "ratio" in r else "-",
                      mb(r.get("rss_cfrd")), mb(r.get("rss_ccx")),
                      f"{r['du']:.1e}" if "du" in r else "-"])
    return table(header, cells, "rrlrrrrrr")


def bench_staged(cfrd, sizes, workdir, newton_max=10000):
    """(c) The homogeneous IIIB E-B embankment built in 20 layers, midpoint (2 increments a
    layer) and Newton (SOLVER = 3, tolerance 1e-6): wall time, increments, factorisations,
    Newton iterations, time per increment and per factorisation."""
    import h5py
    rows = []
    for n in sizes:
        for solver in ("midpoint", "newton"):
            if solver == "newton" and n > newton_max:
                continue           # about 40 min at 1e5 elements (docs/performance.md)
            mesh = emb.embankment_mesh(n, free=True)
            mesh.layers, mesh.layer_increments = 20, 2
            iiib = (2100 * 9.81 / 1000, 564.0, 0.35, 0.85, 204.0, 0.18, 1128.0, 51.0, 13.0)
            mesh.eb = {1: iiib, 2: iiib}
            deck = os.path.join(workdir, f"staged-{mesh.nelem}-{solver}.dat")
            lines = emb.deck_lines(mesh)
            if solver == "newton":
                # CONTROL card (free format): NEWTOP 0, SOLVER 3, TOL 1e-6, MAXIT 20.
                i = lines.index("CONTROL") + 1
                lines[i] = lines[i] + ", 0, 3, 1e-6, 20"
            done = runner.run(cfrd, runner.write_deck(deck, lines), check=False)
            wall = done.wall
            row = dict(nelem=mesh.nelem, solver=solver, wall=wall)
            if done.returncode != 0:
                row["error"] = done.stderr.strip().splitlines()[-1][:90]
            else:
                with h5py.File(deck[:-4] + ".h5") as f:
                    st = results.stages(f)
                    row["inc"] = sum(int(g.attrs["increments"]) for g in st)
                    row["fact"] = sum(int(g.attrs["factorisations"]) for g in st)
                    row["iter"] = sum(int(g.attrs["iterations"]) for g in st)
                    row["resid"] = max(float(g.attrs["max_residual"]) for g in st)
                    u = st[-1]["displacement"][...]
                    row["settl"] = float(-u[:, 1].min())
            rows.append(row)
            print(f"  staged {mesh.nelem} {solver}: {sec(wall)} s "
                  f"{row.get('error', '')}", file=sys.stderr, flush=True)
    header = ["elements", "solver", "increments", "factorisations", "Newton it.",
              "it./increment", "max resid", "max settl. m", "wall s", "s/increment",
              "s/factorisation"]
    cells = []
    for r in rows:
        if "error" in r:
            cells.append([str(r["nelem"]), r["solver"], "-", "-", "-", "-", "-", "-",
                          sec(r["wall"]), "-", "failed: " + r["error"]])
            continue
        cells.append([str(r["nelem"]), r["solver"], str(r["inc"]), str(r["fact"]),
                      str(r["iter"]), f"{r['iter'] / r['inc']:.2f}", f"{r['resid']:.1e}",
                      f"{r['settl']:.4f}", sec(r["wall"]), f"{r['wall'] / r['inc']:.4f}",
                      f"{r['wall'] / r['fact']:.4f}"])
    return table(header, cells, "rlrrrrrrrrr")


def bench_tianshengqiao(cfrd, refinements, workdir, repeat, newton_max=2):
    """(d) The Tianshengqiao-I history at each refinement: midpoint (the paper's method,
    the deck's default) and, up to newton_max, the Newton variant (SOLVER 3, TOL 1e-10)."""
    import subprocess
    import h5py
    import resource
    gen = os.path.join(HERE, "tianshengqiao.py")
    rows = []
    for r in refinements:
        for solver in ("midpoint", "newton"):
            if solver == "newton" and r > newton_max:
                continue
            deck = os.path.join(workdir, f"tianshengqiao-x{r}-{solver}.dat")
            subprocess.run([sys.executable, gen, "--refine", str(r), "--solver", solver,
                            "--deck", deck], check=True)
            best = None
            for _ in range(repeat):
                done = runner.run(cfrd, deck, check=False)
                wall = done.wall
                if best is None or wall < best[0]:
                    best = (wall, done)
            wall, done = best
            rss = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss
            row = dict(r=r, solver=solver, wall=wall, rss=rss)
            if done.returncode != 0:
                row["error"] = (done.stderr.strip().splitlines() or ["?"])[-1][:90]
            else:
                with h5py.File(deck[:-4] + ".h5") as f:
                    st = results.stages(f)
                    row["stages"] = len(st)
                    row["nelem"] = f["mesh/connectivity"].shape[0]
                    row["inc"] = sum(int(g.attrs["increments"]) for g in st)
                    row["fact"] = sum(int(g.attrs["factorisations"]) for g in st)
                    row["iter"] = sum(int(g.attrs["iterations"]) for g in st)
                    row["neq"] = int(st[-1]["solver"].attrs["neq"])
                    row["analysis"] = float(np.ravel(f["run"].attrs["wall_time"])[0])
                    u = st[-1]["displacement_total"][...]
                    x = f["mesh/coordinates"][...]
                    k = int(u[:, 1].argmin())
                    row["settl"] = float(-u[k, 1])
                    row["elev"] = float(x[k, 1])
            rows.append(row)
            print(f"  tianshengqiao x{r} {solver}: {sec(wall)} s {row.get('error', '')}",
                  file=sys.stderr, flush=True)
    header = ["mesh", "solver", "elements", "equations", "stages", "increments",
              "factorisations", "Newton it.", "analysis s", "process s", "us/dof",
              "max settl. m", "at El. m"]
    cells = []
    for row in rows:
        if "error" in row:
            cells.append([f"x{row['r']}", row["solver"]] + ["-"] * 7 + [sec(row["wall"])]
                         + ["-", "failed: " + row["error"], "-"])
            continue
        cells.append([f"x{row['r']}", row["solver"], str(row["nelem"]), str(row["neq"]),
                      str(row["stages"]), str(row["inc"]), str(row["fact"]),
                      str(row["iter"]), sec(row["analysis"]), sec(row["wall"]),
                      f"{1e6 * row['analysis'] / row['neq']:.0f}", f"{row['settl']:.4f}",
                      f"{row['elev']:.1f}"])
    text, md = table(header, cells, "llrrrrrrrrrrr")
    return text, md


def bench_interfaces(cfrd, refinements, workdir, repeat,
                     interfaces=("bonded", "joint", "contact")):
    """(e) The Tianshengqiao-I history with each slab-cushion interface on the same body mesh
    (tools/tianshengqiao.py --interface): the solver and contact figures summed over the
    stages from the HDF5 solver attributes (docs/results.md)."""
    import subprocess
    import h5py
    gen = os.path.join(HERE, "tianshengqiao.py")
    rows = []
    for r in refinements:
        for interface in interfaces:
            deck = os.path.join(workdir, f"tianshengqiao-x{r}-{interface}.dat")
            subprocess.run([sys.executable, gen, "--refine", str(r), "--interface", interface,
                            "--deck", deck], check=True)
            row = dict(r=r, interface=interface)
            for _ in range(repeat):
                done = runner.run(cfrd, deck, check=False)
                wall = done.wall
                if done.returncode != 0:
                    row["error"] = (done.stderr.strip().splitlines() or ["?"])[-1][:90]
                    row["wall"] = wall
                    break
                if "wall" in row and wall >= row["wall"]:
                    continue
                # the figures of the fastest run
                row["wall"] = wall
                with h5py.File(deck[:-4] + ".h5") as f:
                    st = results.stages(f)
                    sv = [g["solver"].attrs for g in st]

                    def total(key, attrs=sv):
                        return sum(float(np.ravel(a.get(key, 0))[0]) for a in attrs)
                    row["nelem"] = f["mesh/connectivity"].shape[0]
                    row["neq"] = max(int(a["neq"]) for a in sv)
                    row["inc"] = sum(int(g.attrs["increments"]) for g in st)
                    row["fact"] = int(total("numeric_factorisations"))
                    row["updates"] = int(total("updates"))
                    row["cit"] = int(total("contact_iterations"))
                    # increments of the stages with contact unknowns (slab placed)
                    row["cinc"] = sum(int(g.attrs["increments"]) for g, a in zip(st, sv)
                                      if int(np.ravel(a.get("contact_iterations", 0))[0]) > 0)
                    row["t_contact"] = total("t_contact")
                    row["t_solver"] = (total("t_symbolic") + total("t_numeric")
                                       + total("t_solve") + total("t_update"))
                    row["t_assembly"] = total("t_assembly")
                    row["analysis"] = float(np.ravel(f["run"].attrs["wall_time"])[0])
            rows.append(row)
            print(f"  tianshengqiao x{r} {interface}: {sec(row['wall'])} s "
                  f"{row.get('error', '')}",
                  file=sys.stderr, flush=True)
    header = ["mesh", "interface", "elements", "equations", "increments", "factorisations",
              "updates", "contact solves", "solves/increment", "search s", "assembly s", "solver s",
              "analysis s", "process s"]
    cells = []
    for row in rows:
        if "error" in row:
            cells.append([f"x{row['r']}", row["interface"]] + ["-"] * 11
                         + [sec(row["wall"]) + " failed: " + row["error"]])
            continue
        contact = row["interface"] == "contact"
        cells.append([f"x{row['r']}", row["interface"], str(row["nelem"]), str(row["neq"]),
                      str(row["inc"]), str(row["fact"]), str(row["updates"]),
                      str(row["cit"]) if contact else "-",
                      f"{row['cit'] / max(row['cinc'], 1):.2f}" if contact else "-",
                      f"{row['t_contact']:.3f}" if contact else "-",
                      sec(row["t_assembly"]), sec(row["t_solver"]), sec(row["analysis"]),
                      sec(row["wall"])])
    return table(header, cells, "llrrrrrrrrrrrr")


# (f) Only the effects a deck asks for: the EFFECTS card (docs/cards.md), each effect switched
# on alone over a base with all of them off. UNLOAD acts only on the nonlinear law, so its row
# switches both on.
EFFECT_FIELDS = ("ROCKFILL", "UNLOAD", "WATER", "INTERFACE", "FRICTION", "SLIP", "PHASES")
EFFECT_OFF = dict(ROCKFILL="LINEAR", UNLOAD="OFF", WATER="OFF", INTERFACE="BONDED",
                  FRICTION="OFF", SLIP="SMALL", PHASES="OFF")
EFFECT_ROWS = (("all off", ()), ("+ nonlinear rockfill", ("ROCKFILL",)),
               ("+ unload-reload", ("ROCKFILL", "UNLOAD")), ("+ water", ("WATER",)),
               ("+ joints", ("INTERFACE",)), ("+ friction", ("FRICTION",)),
               ("+ large slip", ("SLIP",)), ("+ slab phases", ("PHASES",)),
               ("all on (the deck)", EFFECT_FIELDS))


def effects_deck(text, on, applies):
    """The deck with an EFFECTS card: the fields in `applies` off unless named in `on`."""
    card = "EFFECTS   " + "".join(
        f"{'' if k in on or k not in applies else EFFECT_OFF[k]:<10s}" for k in EFFECT_FIELDS)
    lines = text.split("\n")
    k = lines.index("CONTROL")
    return "\n".join(lines[:k + 1] + [card] + lines[k + 1:])


def bench_effects(cfrd, refinements, workdir, repeat):
    """(f) The joint and contact decks of Tianshengqiao-I with the effects switched on one at
    a time: process wall time (minimum of `repeat`), peak memory, and what the analysis did
    (increments, numeric factorisations, contact searches, the time in the contact code)."""
    import subprocess
    import h5py
    gen = os.path.join(HERE, "tianshengqiao.py")
    applies = dict(joint=("ROCKFILL", "UNLOAD", "WATER", "INTERFACE", "PHASES"),
                   contact=("ROCKFILL", "UNLOAD", "WATER", "FRICTION", "SLIP", "PHASES"))
    cells = []
    for r in refinements:
        for interface in ("joint", "contact"):
            base = os.path.join(workdir, f"effects-x{r}-{interface}.dat")
            subprocess.run([sys.executable, gen, "--refine", str(r), "--interface", interface,
                            "--deck", base], check=True)
            with open(base) as f:
                text = f.read()
            for label, on in EFFECT_ROWS:
                if any(k not in applies[interface] for k in on) and on != EFFECT_FIELDS:
                    continue
                deck = os.path.join(workdir, f"effects-x{r}-{interface}-{len(cells)}.dat")
                with open(deck, "w") as f:
                    f.write(effects_deck(text, on, applies[interface]))
                def run_and_read(deck=deck):
                    # the figures of each run, so that they belong to the run reported
                    wall, rss, h5 = peer.run_cfrd(cfrd, deck, workdir)
                    with h5py.File(h5) as f:
                        st = results.stages(f)
                        sv = [g["solver"].attrs for g in st]
                        return wall, rss, dict(
                            stages=len(st),
                            inc=sum(int(g.attrs["increments"]) for g in st),
                            fact=sum(int(a["numeric_factorisations"]) for a in sv),
                            searches=sum(int(a.get("searches", 0)) for a in sv),
                            t_contact=sum(float(a.get("t_contact", 0.0)) for a in sv),
                            analysis=float(np.ravel(f["run"].attrs["wall_time"])[0]))
                try:
                    (wall, _, fig), rss = repeat_run(run_and_read, repeat)
                except (peer.RunError, OSError) as exc:
                    cells.append([f"x{r}", interface, label] + ["-"] * 6
                                 + [f"failed: {str(exc)[:60]}"])
                    continue
                cells.append([f"x{r}", interface, label, str(fig["stages"]), str(fig["inc"]),
                              str(fig["fact"]), str(fig["searches"]),
                              f"{fig['t_contact']:.3f}", sec(fig["analysis"]), sec(wall),
                              mb(rss)])
                print(f"  effects x{r} {interface} {label}: {sec(wall)} s", file=sys.stderr,
                      flush=True)
    header = ["mesh", "deck", "effects", "stages", "increments", "factorisations", "searches",
              "contact s", "analysis s", "process s", "peak MB"]
    return table(header, cells, "lllrrrrrrrr")


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--cfrd", default=os.path.join(ROOT, "bin", "cfrd"))
    ap.add_argument("--workdir", default=os.path.join(ROOT, "build", "bench"))
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
    ap.add_argument("--interface-refine", default="1,4",
                    help="Tianshengqiao-I refinements for table (e), the interface methods"
                         " (empty: skip)")
    ap.add_argument("--only-interfaces", action="store_true", help="table (e) only")
    ap.add_argument("--effects-refine", default="1,2",
                    help="Tianshengqiao-I refinements for table (f), the effects (empty: skip)")
    ap.add_argument("--only-effects", action="store_true", help="table (f) only")
    args = ap.parse_args(argv)
    tsq = [int(x) for x in args.tsq_refine.split(",") if x.strip()]
    ifr = [int(x) for x in args.interface_refine.split(",") if x.strip()]
    efr = [int(x) for x in args.effects_refine.split(",") if x.strip()]
    def only(title, bench):
        """One table alone: printed, and as markdown to --markdown."""
        os.makedirs(args.workdir, exist_ok=True)
        t, m = bench()
        print(machine())
        print(title)
        print(t)
        if args.markdown:
            with open(args.markdown, "w") as f:
                f.write(f"Machine: {machine()}.\n\n{m}\n")
        return 0
    if args.only_effects:
        return only("(f) Tianshengqiao-I, the effects switched on one at a time",
                    lambda: bench_effects(args.cfrd, efr, args.workdir, args.repeat))
    if args.only_interfaces:
        return only("(e) Tianshengqiao-I, interface methods",
                    lambda: bench_interfaces(args.cfrd, ifr, args.workdir, args.repeat))
    if args.only_tianshengqiao:
        return only("(d) Tianshengqiao-I, 1996-1999 history",
                    lambda: bench_tianshengqiao(args.cfrd, tsq, args.workdir, args.repeat,
                                                args.tsq_newton_max))
    sizes = [int(s) for s in args.sizes.split(",") if s.strip()]
    os.makedirs(args.workdir, exist_ok=True)
    cfrd = args.cfrd if os.access(args.cfrd, os.X_OK) else None
    if cfrd is None:
        print(f"bench: no program at {args.cfrd} (build it with `make build`); "
              f"cfrd columns left empty", file=sys.stderr)
    mach = machine()
    notes = [f"Machine: {mach}."]
    ccx_threads = os.environ.get("OMP_NUM_THREADS", "unset")
    notes.append(f"Wall times are the minimum of {args.repeat} run(s) of the whole process "
                 f"(reading the deck to writing the results); peak memory is the process's "
                 f"maximum resident set. CalculiX {ccx_version()} with its default solver "
                 f"(OMP_NUM_THREADS {ccx_threads}).")

    block_rows = bench_blocks(cfrd, sizes, args.workdir, args.repeat) if cfrd else []
    emb_rows = bench_embankment(cfrd, sizes, args.workdir, args.repeat, not args.no_ccx)

    out_text, out_md = [mach, ""], ["\n".join(notes), ""]
    if block_rows:
        t, m = block_table(block_rows)
        out_text += ["(a) cfrd on rectangular blocks of square quads, base fixed, gravity", t,
                     ""]
        out_md += ["**(a) cfrd on rectangular blocks** of square quads (1 m), one material, "
                   "base fixed, gravity; phase times from the HDF5 solver attributes.", "",
                   m, ""]
        for r in block_rows:
            if "error" in r:
                out_text.append(f"block {r['case']}: {r['error']}")
    t, m = embankment_table(emb_rows)
    out_text += ["(b) embankment (H 178 m, slopes 1:1.4, two zones), cfrd vs CalculiX", t]
    out_md += ["**(b) The embankment** (H 178 m, crest 12 m, slopes 1V:1.4H, two zones, "
               "gravity): cfrd against CalculiX (CPE4) on the same mesh.", "", m, ""]
    for r in emb_rows:
        for key in ("error_cfrd", "error_ccx"):
            if key in r:
                out_text.append(f"embankment {r['nelem']}: {r[key]}")
    staged_sizes = [int(x) for x in args.staged_sizes.split(",") if x.strip()]
    if cfrd and staged_sizes:
        t, m = bench_staged(cfrd, staged_sizes, args.workdir, args.newton_max)
        out_text += ["", "(c) IIIB E-B embankment in 20 layers, 2 increments a layer", t]
        out_md += ["**(c) The homogeneous IIIB E-B embankment built in 20 layers** (2 "
                   "increments a layer): midpoint against Newton.", "", m, ""]
    tianshengqiao_tables = (
        (tsq, lambda: bench_tianshengqiao(cfrd, tsq, args.workdir, args.repeat,
                                          args.tsq_newton_max),
         "(d) Tianshengqiao-I, the whole 1996-1999 history",
         "**(d) Tianshengqiao-I, the whole 1996-1999 history** (tools/tianshengqiao.py "
         "meshes; midpoint as in the paper, Newton to 1e-10)."),
        (ifr, lambda: bench_interfaces(cfrd, ifr, args.workdir, args.repeat),
         "(e) Tianshengqiao-I, the interface methods on the same body mesh",
         "**(e) Tianshengqiao-I, the interface methods** (bonded, Goodman joints, contact; "
         "the same body mesh; sums over the stages)."),
        (efr, lambda: bench_effects(cfrd, efr, args.workdir, args.repeat),
         "(f) Tianshengqiao-I, the effects switched on one at a time",
         "**(f) Tianshengqiao-I, the effects switched on one at a time** (the EFFECTS card; "
         "the joint and contact decks of the same body mesh)."))
    for levels, bench, title, caption in tianshengqiao_tables:
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


def ccx_version():
    import subprocess
    try:
        out = subprocess.run(["ccx", "-v"], capture_output=True, text=True, timeout=20).stdout
        ver = [w for w in out.split() if w[:1].isdigit()]
        return ver[-1] if ver else "(version unknown)"
    except (OSError, subprocess.SubprocessError):
        return "(not found)"


if __name__ == "__main__":
    sys.exit(main())
