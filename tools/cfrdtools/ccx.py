"""CalculiX: input cards, running ccx (timed, peak memory) and reading its displacements
(shared by ccx_peer.py, embankment.py and bench.py)."""

import os
import re
import shutil
import subprocess
import sys
import tempfile
import time

import numpy as np

TIME_BIN = "/usr/bin/time"
GRAVITY_G = 9.81        # m/s2: unit weights (kN/m3) become densities under this gravity


class RunError(RuntimeError):
    pass


def real(value):
    """Shortest round-trip spelling if it fits CalculiX's 20-character fields, else 14
    significant digits (relative 5e-14)."""
    text = repr(float(value))
    return text if len(text) <= 20 else f"{float(value):.13e}"


def node_cards(xy, numbers=None, nset=None):
    """*NODE (in an NSET) of the points xy, numbered from 1 or by `numbers`."""
    numbers = range(1, len(xy) + 1) if numbers is None else numbers
    return [f"*NODE{f', NSET={nset}' if nset else ''}"] + [
        f"{k}, {real(x)}, {real(y)}, 0.0" for k, (x, y) in zip(numbers, xy)]


def element_cards(elset, conn, numbers):
    """CPE4 elements of an ELSET: connectivity rows (1-based nodes) with their numbers."""
    return [f"*ELEMENT, TYPE=CPE4, ELSET={elset}"] + [
        f"{e}, " + ", ".join(str(n) for n in c) for e, c in zip(numbers, conn)]


def set_cards(kind, name, members):
    """*NSET or *ELSET of the members, ten to a line."""
    members = [str(m) for m in members]
    return [f"*{kind}, {kind}={name}"] + [", ".join(members[i:i + 10])
                                             for i in range(0, len(members), 10)]


def material_cards(name, e, nu, gamma, elset=None, density=None):
    """A linear elastic material (unit weight gamma as density gamma / 9.81) and, with
    elset, its plane-strain section of thickness 1 m."""
    out = [f"*MATERIAL, NAME={name}", "*ELASTIC", f"{real(e)}, {real(nu)}", "*DENSITY",
           density or real(float(gamma) / GRAVITY_G)]
    return out + ([f"*SOLID SECTION, ELSET={elset}, MATERIAL={name}", "1.0"] if elset else [])


def timed_run(cmd, cwd=None, log=None):
    """Run cmd; return (wall seconds, peak RSS in kB or None).

    Peak memory comes from GNU time's %M (the child's own maximum RSS) when /usr/bin/time
    exists; otherwise from getrusage in a throw-away Python process that runs cmd, since
    RUSAGE_CHILDREN is a running maximum over all children of the calling process.
    """
    fd, rss_file = tempfile.mkstemp(prefix="rss")
    os.close(fd)
    if os.access(TIME_BIN, os.X_OK):
        full = [TIME_BIN, "-q", "-f", "%M", "-o", rss_file] + list(cmd)
    else:
        helper = ("import resource, subprocess, sys\n"
                  "rc = subprocess.call(sys.argv[2:])\n"
                  "open(sys.argv[1], 'w').write(str(resource.getrusage("
                  "resource.RUSAGE_CHILDREN).ru_maxrss))\n"
                  "sys.exit(rc)\n")
        full = [sys.executable, "-c", helper, rss_file] + list(cmd)
    out = open(log, "w") if log else subprocess.DEVNULL
    try:
        t0 = time.perf_counter()
        proc = subprocess.run(full, cwd=cwd, stdout=out, stderr=subprocess.STDOUT)
        wall = time.perf_counter() - t0
    finally:
        if log:
            out.close()
    try:
        text = open(rss_file).read().split()
        rss = int(text[-1]) if text else None
    except (OSError, ValueError):
        rss = None
    os.unlink(rss_file)
    if proc.returncode != 0:
        tail = ""
        if log:
            with open(log, errors="replace") as f:
                tail = " | ".join(f.read().strip().splitlines()[-3:])
        raise RunError(f"{' '.join(map(str, cmd))} exited with {proc.returncode}: {tail}")
    return wall, rss


def run_ccx(workdir, name):
    """ccx -i name in workdir; returns (wall s, peak kB). ccx exits 0 even on input errors,
    so its log is searched for *ERROR as well."""
    if shutil.which("ccx") is None:
        raise RunError("ccx not found (Debian package calculix-ccx)")
    log = os.path.join(workdir, name + ".ccx.log")
    for ext in (".dat", ".frd"):
        if os.path.exists(os.path.join(workdir, name + ext)):
            os.unlink(os.path.join(workdir, name + ext))
    wall, rss = timed_run(["ccx", "-i", name], cwd=workdir, log=log)
    with open(log, errors="replace") as f:
        text = f.read()
    if "*ERROR" in text:
        first = text[text.index("*ERROR"):].splitlines()[:3]
        raise RunError(f"ccx reported an error ({log}): {' '.join(s.strip() for s in first)}")
    return wall, rss


_DISP_HEAD = re.compile(r"^\s*displacements\s*\(vx,vy,vz\)\s*for set\s+(\S+)\s+and time",
                        re.IGNORECASE)


def ffloat(text):
    """A number of ccx's .dat; Fortran E output may drop the 'E' of 3-digit exponents:
    '1.234567-100'."""
    text = text.strip()
    if re.search(r"[0-9][+-][0-9]+$", text) and "E" not in text.upper():
        text = re.sub(r"([0-9])([+-][0-9]+)$", r"\1E\2", text)
    return float(text)


def read_displacements(path, nset="NALL"):
    """{node: (vx, vy, vz)} of the last 'displacements (vx,vy,vz) for set NSET' block."""
    blocks, current = [], None
    with open(path) as f:
        for line in f:
            head = _DISP_HEAD.match(line)
            if head:
                current = {} if head.group(1).upper() == nset.upper() else None
                if current is not None:
                    blocks.append(current)
            elif current is not None and line.split():
                parts = line.split()
                try:
                    vals = tuple(ffloat(p) for p in parts[1:4])
                    if len(vals) != 3:
                        raise ValueError
                    current[int(parts[0])] = vals
                except ValueError:
                    current = None          # the block ended (next heading of another kind)
    if not blocks:
        raise ValueError(f"{path}: no 'displacements (vx,vy,vz) for set {nset}' block")
    return blocks[-1]


def displacement_array(path, nnode, nset="NALL"):
    """(nnode, 2) displacements of nodes 1..nnode from ccx's .dat."""
    disp = read_displacements(path, nset)
    missing = [n for n in range(1, nnode + 1) if n not in disp]
    if missing:
        raise ValueError(f"{path}: {len(missing)} nodes missing from the displacement block "
                         f"(first: {missing[:5]})")
    return np.array([disp[n][:2] for n in range(1, nnode + 1)])
