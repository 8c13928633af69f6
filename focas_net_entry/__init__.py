"""The ``focas-net`` command's first step, run before the focas_net package is imported: Ctrl-C
while Python imports the package (about the first half second) ends the command as Ctrl-C
does later, with exit 130 and nothing printed (docs/cli.md), rather than with a traceback of
the import under way."""

from __future__ import annotations

import signal
from types import FrameType

__all__ = ["main"]

#: The exit code of a command Ctrl-C ended (focas_net.cli.EXIT_INTERRUPTED).
_INTERRUPTED = 130


def _interrupted(signum: int, frame: FrameType | None) -> None:
    signal.signal(signal.SIGINT, signal.SIG_IGN)  # a second Ctrl-C: the exit is under way
    raise SystemExit(_INTERRUPTED)


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
    if quiet and code == _INTERRUPTED:
        signal.signal(signal.SIGINT, signal.SIG_IGN)
    return code
