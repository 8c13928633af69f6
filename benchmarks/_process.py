"""The benchmark scripts' child processes: their environment, and their end."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path
from typing import Any, Final

__all__ = ["ROOT", "child_env", "end", "log"]

#: The project's checkout: the children run there, and import ``benchmarks`` from it.
ROOT: Final = Path(__file__).resolve().parent.parent


def child_env() -> dict[str, str]:
    """This process's environment, with the checkout on ``PYTHONPATH`` and unbuffered output
    (a child's lines are read as it prints them)."""
    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join(filter(None, [str(ROOT), env.get("PYTHONPATH")]))
    env["PYTHONUNBUFFERED"] = "1"
    return env


def end(proc: subprocess.Popen[Any], grace: float = 5.0) -> None:
    """Terminate ``proc`` if it still runs; kill it if it is not gone within ``grace`` s."""
    if proc.poll() is not None:
        return
    proc.terminate()
    try:
        proc.wait(grace)
    except subprocess.TimeoutExpired:
        proc.kill()
        proc.wait(grace)


def log(message: str) -> None:
    """A progress line on standard error (standard output is the results')."""
    print(message, file=sys.stderr, flush=True)
