"""Running bin/cfrd and the scripts of tools/: find the binary, write a deck, run it, time it
(the fastest of several runs), and the machine it ran on."""

import os
import platform
import subprocess
import sys
import time
from concurrent.futures import ThreadPoolExecutor

TOOLS = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
ROOT = os.path.dirname(TOOLS)


class CfrdFailed(RuntimeError):
    """cfrd exited with a non-zero status; the message holds its stderr."""


def find_cfrd(cfrd=None):
    """The binary named, else bin/cfrd of the repository."""
    return cfrd or os.path.join(ROOT, "bin", "cfrd")


def write_deck(path, text):
    """Write the deck text (a string or a list of lines) to path; returns path."""
    if not isinstance(text, str):
        text = "\n".join(text) + "\n"
    os.makedirs(os.path.dirname(os.path.abspath(path)), exist_ok=True)
    with open(path, "w") as f:
        f.write(text)
    return path


def h5_of(deck):
    """The results file cfrd writes beside a deck."""
    return os.path.splitext(deck)[0] + ".h5"


def run(cfrd, deck, *args, check=True, quiet=True, limit=300):
    """Run cfrd on deck; returns the CompletedProcess with .wall (s) added.

    check=True raises CfrdFailed on a non-zero exit, with `limit` characters of stderr.
    """
    cmd = [cfrd] + (["--quiet"] if quiet else []) + list(args) + [deck]
    t0 = time.perf_counter()
    done = subprocess.run(cmd, capture_output=True, text=True)
    done.wall = time.perf_counter() - t0
    if check and done.returncode != 0:
        raise CfrdFailed(f"cfrd failed on {deck}: {done.stderr.strip()[:limit]}")
    return done


def best_of(cfrd, deck, repeat, longer=float("inf"), keep=lambda done: None):
    """Run cfrd on deck up to `repeat` times; returns (the fastest run, keep(run) called as
    soon as that run ended). A failed run is returned at once; after a run longer than
    `longer` seconds there is no further one."""
    best = None
    for _ in range(repeat):
        done = run(cfrd, deck, check=False)
        if done.returncode != 0:
            return done, keep(done)
        if best is None or done.wall < best[0].wall:
            best = done, keep(done)
        if done.wall > longer:
            break
    return best


def machine():
    """CPU model, logical cores, memory: one line for a table's caption."""
    def first(path, key, value):
        try:
            with open(path) as f:
                return next((value(line) for line in f if line.lower().startswith(key)), None)
        except OSError:
            return None
    model = first("/proc/cpuinfo", "model name", lambda ln: ln.split(":", 1)[1].strip()) \
        or platform.processor() or "unknown CPU"
    mem = first("/proc/meminfo", "memtotal:", lambda ln: f"{int(ln.split()[1]) / 1024 ** 2:.1f}"
                                                         " GiB") or "unknown"
    cores = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count()
    return f"{model}, {cores} cores available, {mem} memory, {platform.system()} " \
           f"{platform.release()}, Python {platform.python_version()}"


def run_text(cfrd, deck, text, **kw):
    """Write text to deck, run cfrd on it (run's keywords); returns the .h5 path."""
    run(cfrd, write_deck(deck, text), **kw)
    return h5_of(deck)


def run_many(cfrd, decks, jobs=1, **kw):
    """Run every deck, `jobs` at a time (threads: the work is in the child processes);
    returns the CompletedProcess of each, in order."""
    kw.setdefault("check", False)
    with ThreadPoolExecutor(max(1, jobs)) as pool:
        return list(pool.map(lambda d: run(cfrd, d, **kw), decks))


def signal_when(cmd, watch, text, signum, output, timeout=300.0):
    """Start cmd, its stdout and stderr into the file `output`; send it signum once the file
    `watch` holds `text` (killed if that has not happened within timeout s). Returns (exit
    status, the output, whether the signal was sent while cmd ran)."""
    with open(output, "w") as fh:
        proc = subprocess.Popen(cmd, stdout=fh, stderr=subprocess.STDOUT)
    sent, end = False, time.monotonic() + timeout
    while not sent and time.monotonic() < end and proc.poll() is None:
        sent = os.path.exists(watch) and text in open(watch).read()
        if sent:
            proc.send_signal(signum)
        else:
            time.sleep(0.01)
    if not sent and proc.poll() is None:
        proc.kill()
    return proc.wait(), open(output).read(), sent


def tool(name, *args, check=False, env=None):
    """Run the script tools/NAME with this Python; returns (exit status, stdout + stderr).
    check=True raises RuntimeError on a non-zero exit."""
    done = subprocess.run([sys.executable, os.path.join(TOOLS, name), *map(str, args)],
                          capture_output=True, text=True, env=env)
    if check and done.returncode:
        raise RuntimeError(f"{name} exit {done.returncode}: {done.stderr.strip()[-300:]}")
    return done.returncode, done.stdout + done.stderr


def tianshengqiao(deck, *options):
    """Write a Tianshengqiao-I deck with tools/tianshengqiao.py OPTIONS --deck DECK."""
    tool("tianshengqiao.py", *options, "--deck", deck, check=True)
    return deck
