"""The ``windpump`` command as the tests run it: in this process, or as a process of its own."""

from __future__ import annotations

import contextlib
import io
import os
import subprocess
import sys


def windpump_command(*args: str, cwd=None, process: bool = False) -> subprocess.CompletedProcess:
    """Run ``windpump ARGS``: its exit code, stdout and stderr as a ``CompletedProcess``.

    By default in this process (``windpump.command.cli.main`` with stdout and stderr captured,
    argparse's exits taken as exit codes): each new process cost ~2 s of an interpreter's
    start and numba's imports, ~2 of the command tests' ~3 minutes. ``process=True`` runs
    ``python -m windpump ARGS`` instead, for what only a process shows (the console script,
    ``serve``, a pool of workers) and for the test that holds the two ways together
    (tests/command/test_cli.py)."""
    if process:
        return subprocess.run(
            [sys.executable, "-m", "windpump", *args],
            capture_output=True,
            text=True,
            timeout=300,
            cwd=cwd,
        )
    from windpump.command.cli import main

    out, err = io.StringIO(), io.StringIO()
    here = os.getcwd()
    try:
        os.chdir(cwd or here)
        with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
            try:
                code = main(list(args))
            except SystemExit as leaving:  # argparse: --help (0), an argument it cannot read (2)
                code = leaving.code if isinstance(leaving.code, int) else int(bool(leaving.code))
    finally:
        os.chdir(here)
    return subprocess.CompletedProcess(["windpump", *args], code, out.getvalue(), err.getvalue())
