"""Transports and hints, a confirming pass: what a new user meets with passwords, wrong
peers, odd addresses and ``serve``'s options, in cases the earlier passes did not try.

Servers here bind 127.0.0.1 on ephemeral ports; ``focas-net`` runs as a subprocess where its
exit code is checked.
"""

from __future__ import annotations

import socket

import pytest
from cli_support import one_line, run_focas_net


def _closed_port() -> int:
    """A port of 127.0.0.1 nothing listens on (bound, then closed)."""
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        port: int = s.getsockname()[1]
    return port


@pytest.mark.parametrize(
    ("argv", "named"),
    [
        (("unlock", ""), "PASSWORD"),
        (("unlock", "ABCDE"), "PASSWORD"),
        (("param", "set", "1020", "5", "--password", "ABCDE"), "--password"),
        (("macro", "set", "100", "5", "--password", "é"), "--password"),
    ],
)
async def test_a_bad_password_is_a_usage_error_naming_its_argument_before_any_connect(
    argv: tuple[str, ...], named: str
) -> None:
    """``unlock ''`` connected first (exit 3 when the CNC was away, as if the password were
    good), and both refusals read `parameter password '': ...`, naming no argument, in words
    other than ``serve --param-password``'s."""
    typed = argv[argv.index("--password") + 1] if "--password" in argv else argv[1]
    command = " ".join(argv[:2]) if argv[0] != "unlock" else "unlock"
    code, out, err = await run_focas_net(*argv, "--port", str(_closed_port()))
    assert (code, out) == (2, "")
    assert one_line(err, f"focas-net {command}: error:") == (
        f"focas-net {command}: error: argument {named}: must be 1..4 ASCII characters, got "
        f"{typed!r}; see focas-net {command} --help"
    )
