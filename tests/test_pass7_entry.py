"""Ctrl-C while ``focas-net`` is still importing the package ends it with exit 130 and nothing
printed, as Ctrl-C does once it runs (docs/cli.md), not with a traceback of the import; a
SIGINT the shell told it to ignore stays ignored."""

from __future__ import annotations

import tomllib
from pathlib import Path

from cli_support import INTERRUPTED_IMPORT, run_entry

from focas_net.cli import EXIT_INTERRUPTED

ROOT = Path(__file__).resolve().parent.parent


def test_the_command_is_the_entry_module() -> None:
    project = tomllib.loads((ROOT / "pyproject.toml").read_text())
    assert project["project"]["scripts"] == {"focas-net": "focas_net_entry:main"}


def test_ctrl_c_while_importing_is_exit_130_and_silent() -> None:
    done = run_entry(INTERRUPTED_IMPORT)
    assert (done.returncode, done.stdout, done.stderr) == (EXIT_INTERRUPTED, "", "")


def test_an_ignored_sigint_stays_ignored_and_the_command_runs() -> None:
    done = run_entry(INTERRUPTED_IMPORT, ignore_sigint=True)
    assert done.returncode == 0, done.stderr
    assert done.stdout.startswith("focas-net ")


def test_without_a_sigint_it_runs_the_command_line() -> None:
    done = run_entry(
        "import sys, focas_net_entry\nsys.argv = ['focas-net', '--version']\n"
        "sys.exit(focas_net_entry.main())"
    )
    assert done.returncode == 0 and done.stdout.startswith("focas-net "), done
