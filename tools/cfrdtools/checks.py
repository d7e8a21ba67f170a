"""The check scripts' verdicts and command line: one `PASS|FAIL PREFIX/NAME: detail` line per
check (tools/run_tests.sh counts every such line), exit status 1 after a FAIL."""

import argparse
import os
import shutil


class Checks:
    """check(name, ok, detail) prints the verdict line (not when quiet: checks that make up
    one verdict of another) and returns ok; `status` is the exit status (1 after any FAIL)."""

    def __init__(self, prefix="", quiet=False):
        self.prefix = prefix + "/" if prefix else ""
        self.failed, self.quiet = 0, quiet

    def __call__(self, name, ok, detail=""):
        ok = bool(ok)
        self.failed += not ok
        if not self.quiet:
            print(f"{'PASS' if ok else 'FAIL'} {self.prefix}{name}"
                  + (f": {detail}" if detail else ""), flush=True)
        return ok

    def guard(self, name, fn, *args):
        """fn(*args); an exception is a FAIL of `name` with its reason, never a skip."""
        try:
            return fn(*args)
        except Exception as exc:  # noqa: BLE001 - one verdict line whatever failed
            self(name, False, f"{type(exc).__name__}: {exc}")

    @property
    def status(self):
        return 1 if self.failed else 0


def parser(doc, cfrd=None, workdir=None, **kw):
    """An argument parser described by the first line of `doc`, with --cfrd (required when
    cfrd is True, else its default) and --workdir (when given a default)."""
    ap = argparse.ArgumentParser(description=doc.split("\n")[0], **kw)
    if cfrd is not None:
        ap.add_argument("--cfrd", **({"required": True} if cfrd is True else
                                     {"default": cfrd}))
    if workdir is not None:
        ap.add_argument("--workdir", **({"required": True} if workdir is True else
                                        {"default": workdir}))
    return ap


def fresh(path):
    """An empty folder at path (what was there removed); returns path."""
    shutil.rmtree(path, ignore_errors=True)
    os.makedirs(path)
    return path
