"""CalculiX: run ccx on an input file, time it and its peak memory (shared by ccx_*.py, bench.py)."""

import os
import shutil
import subprocess
import sys
import tempfile
import time

TIME_BIN = "/usr/bin/time"


class RunError(RuntimeError):
    pass


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
