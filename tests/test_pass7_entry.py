"""Ctrl-C while ``focas-net`` is still importing the package ends it with exit 130 and nothing
printed, as Ctrl-C does once it runs (docs/cli.md), not with a traceback of the import; a
SIGINT the shell told it to ignore stays ignored."""

from __future__ import annotations

import subprocess
import sys
import tomllib
from pathlib import Path

from cli_support import SUBPROCESS_TIMEOUT

from focas_net.cli import EXIT_INTERRUPTED

ROOT = Path(__file__).resolve().parent.parent

#: Runs the command's entry with a SIGINT delivered while ``focas_net.cli`` is being imported.
INTERRUPTED_IMPORT = """
import builtins, os, signal, sys
real = builtins.__import__
def importing(name, *args, **kwargs):
    if name == "focas_net.cli":
        os.kill(os.getpid(), signal.SIGINT)
    return real(name, *args, **kwargs)
builtins.__import__ = importing
import focas_net_entry
sys.argv = ["focas-net", "--version"]
sys.exit(focas_net_entry.main())
"""


def run(code: str, *, ignore_sigint: bool = False) -> subprocess.CompletedProcess[str]:
    prefix = "import signal; signal.signal(signal.SIGINT, signal.SIG_IGN)\n"
    return subprocess.run(
        [sys.executable, "-c", (prefix if ignore_sigint else "") + code],
        capture_output=True,
        text=True,
        cwd=ROOT,
        timeout=SUBPROCESS_TIMEOUT,
        check=False,
    )


def test_the_command_is_the_entry_module() -> None:
    project = tomllib.loads((ROOT / "pyproject.toml").read_text())
    assert project["project"]["scripts"] == {"focas-net": "focas_net_entry:main"}


def test_ctrl_c_while_importing_is_exit_130_and_silent() -> None:
    done = run(INTERRUPTED_IMPORT)
    assert (done.returncode, done.stdout, done.stderr) == (EXIT_INTERRUPTED, "", "")


def test_an_ignored_sigint_stays_ignored_and_the_command_runs() -> None:
    done = run(INTERRUPTED_IMPORT, ignore_sigint=True)
    assert done.returncode == 0, done.stderr
    assert done.stdout.startswith("focas-net ")


def test_without_a_sigint_it_runs_the_command_line() -> None:
    done = run(
        "import sys, focas_net_entry\nsys.argv = ['focas-net', '--version']\n"
        "sys.exit(focas_net_entry.main())"
    )
    assert done.returncode == 0 and done.stdout.startswith("focas-net "), done
