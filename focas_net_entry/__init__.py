"""The ``focas-net`` command's first step, run before the focas_net package is imported: Ctrl-C
while Python imports the package (about the first half second) ends the command as Ctrl-C
does later, with exit 130 and nothing printed (docs/cli.md), or 0 for a command that runs
until told (``serve``, ``gateway``, ``watch``, ``alarms --follow``), rather than with a
traceback of the import under way."""

from __future__ import annotations

import signal
import sys
from collections.abc import Sequence
from types import FrameType

__all__ = ["main"]

#: The exit code of a command Ctrl-C ended (focas_net.cli.EXIT_INTERRUPTED).
_INTERRUPTED = 130


#: The commands that run until told, which Ctrl-C ends with exit 0 at any moment (docs/cli.md).
_UNTIL_TOLD = frozenset({"serve", "gateway", "watch"})


def _runs_until_told(argv: Sequence[str]) -> bool:
    """Whether ``argv`` (the arguments, without the program) names a command that runs until
    told: ``serve``, ``gateway``, ``watch``, or ``alarms`` with ``--follow`` (or a prefix of
    it, as the parser takes one); read before the package is imported."""
    command = next((word for word in argv if not word.startswith("-")), None)
    if command in _UNTIL_TOLD:
        return True
    return command == "alarms" and any(
        len(word) > 3 and "--follow".startswith(word.partition("=")[0]) for word in argv
    )


def _interrupted(signum: int, frame: FrameType | None) -> None:
    signal.signal(signal.SIGINT, signal.SIG_IGN)  # a second Ctrl-C: the exit is under way
    raise SystemExit(0 if _runs_until_told(sys.argv[1:]) else _INTERRUPTED)


def main() -> int:
    """Import the command line and run it; a SIGINT before it runs ends it quietly. A SIGINT
    the shell told the command to ignore (a background job) stays ignored. Once Ctrl-C ended
    the command (exit 130), a second one, a few milliseconds later while the process ends,
    changes nothing: it is ignored, where it would otherwise raise past the command's own
    handling (a traceback) or, once the interpreter had begun to finalize, kill the process
    by the signal instead of exit 130."""
    quiet = signal.getsignal(signal.SIGINT) is signal.default_int_handler
    if quiet:
        signal.signal(signal.SIGINT, _interrupted)
    from focas_net.cli import main as run

    if quiet:
        signal.signal(signal.SIGINT, signal.default_int_handler)
    try:
        code = run()
    except KeyboardInterrupt:  # a second Ctrl-C while the command handled the first
        code = _INTERRUPTED
    if code == _INTERRUPTED and _runs_until_told(sys.argv[1:]):
        code = 0  # Ctrl-C before the command's own handling began: it ends as it would then
    if quiet and code == _INTERRUPTED:
        signal.signal(signal.SIGINT, signal.SIG_IGN)
    return code
