"""A confirming new-user pass over the command line (tenth): an option refused by a rule that
depends on another argument (``sim fault --arg``, ``param set --width``) in the parser's one
form; a number refused after it was read (a PMC address, a macro or a diagnostic number) named
as it was typed; a diagnostic read and a status read named as FANUC's library names them
(``cnc_diagnoss``, ``cnc_statinfo``) on both transports.

Each test runs ``focas-net`` as a user does (a subprocess) and checks its one line and its
exit code.
"""

from __future__ import annotations

from typing import Final

import pytest
from cli_support import at, fails, ok
from support import serving

from focas_net.cli import EXIT_CNC, EXIT_USAGE

PROTOCOLS: Final = (["--protocol", "packed"], ["--protocol", "native"])

# -- an option's refusal, in one form ------------------------------------------------------------


def _refused(command: str, argument: str, why: str) -> str:
    """An argument's refusal in the parser's form."""
    return f"focas-net {command}: error: argument {argument}: {why}; see focas-net {command} --help"


@pytest.mark.parametrize(
    ("argv", "said"),
    [
        (
            ("sim", "fault", "error", "--arg", "0"),
            _refused(
                "sim fault", "--arg", "an error fault's EW code is a nonzero -32768..32767, got 0"
            ),
        ),
        (
            ("sim", "fault", "delay", "--arg", "1.5"),
            _refused("sim fault", "--arg", "not a whole number: '1.5'"),
        ),
        (
            ("sim", "fault", "delay"),
            _refused(
                "sim fault", "--arg", "a delay fault needs its delay in milliseconds (0..60000)"
            ),
        ),
        (
            ("sim", "fault", "drop", "--arg", "5"),
            _refused("sim fault", "--arg", "does not apply to a drop fault"),
        ),
        (
            ("param", "set", "3401.1", "1", "--width", "4"),
            _refused("param set", "--width", "does not apply to a bit write (NUMBER.BIT)"),
        ),
        (
            ("param", "set", "3401.1", "2"),
            _refused(
                "param set",
                "VALUE",
                "expected 1, on, true, yes or set, or 0, off, false, no or clear, got '2'",
            ),
        ),
        (
            ("pmc", "write", "R", "0", "1", "256"),
            _refused("pmc write", "BYTE", "byte value '256' outside 0..255"),
        ),
        (
            ("status", "--tls-ca", "ca.pem", "--tls-insecure"),
            _refused("status", "--tls-insecure", "not allowed with --tls-ca"),
        ),
    ],
)
async def test_an_option_refused_with_another_argument_is_worded_as_the_parser_words_it(
    argv: tuple[str, ...], said: str
) -> None:
    """``sim fault error --arg 0`` said ``focas-net: --arg: ...`` where ``--count 0`` says
    ``focas-net sim fault: error: argument --count: ...``, and ``param set 3401.1 2`` said
    ``focas-net: VALUE: ...`` where ``pmc bit R 0.1 2`` says ``focas-net pmc bit: error:
    argument VALUE: ...``: one form for an argument's refusal, whether the parser or the
    command found it (nothing is connected to)."""
    assert await fails(EXIT_USAGE, *argv, "--port", "1", prefix="focas-net") == said


# -- a number named as typed ---------------------------------------------------------------------


@pytest.mark.parametrize(
    ("argv", "said"),
    [
        (
            ("pmc", "read", "R", "0x10000", "1"),
            "0x10000 reads as 65536: PMC start address 65536 is outside 0..65535",
        ),
        (
            ("pmc", "read", "R", "0", "0x10001"),
            "0x10001 reads as 65537: PMC byte count 65537 is outside 1..65536",
        ),
        (
            ("pmc", "read", "R", "0xFFFF", "0x2"),
            "0xFFFF reads as 65535, 0x2 as 2: 2 PMC bytes from 65535 run to 65536, "
            "past 65535 (the last PMC address)",
        ),
        (
            ("pmc", "write", "R", "0x10000", "1"),
            "0x10000 reads as 65536: PMC start address 65536 is outside 0..65535",
        ),
        (
            ("pmc", "bit", "R", "0x10000.1"),
            "0x10000 reads as 65536: PMC start address 65536 is outside 0..65535",
        ),
        (
            ("macro", "get", "0x8000"),
            "0x8000 reads as 32768: macro variable number 32768 is outside -32768..32767",
        ),
        (
            ("diag", "0b1000000000000000"),
            "0b1000000000000000 reads as 32768: diagnostic number 32768 is outside 0..32767",
        ),
        (
            ("param", "get", "0x8000.1"),
            "0x8000 reads as 32768: parameter number 32768 is outside 0..32767",
        ),
        (
            ("param", "set", "0o100000", "1"),
            "0o100000 reads as 32768: parameter number 32768 is outside 0..32767",
        ),
    ],
)
async def test_a_positional_number_refused_is_named_as_typed(
    argv: tuple[str, ...], said: str
) -> None:
    """``pmc read R 0x10000 1`` said ``PMC start address 65536 is outside 0..65535``, a
    number the user never typed: the refusal leads with the text typed, as an option's
    does (``0x100 reads as 256: ...``)."""
    async with serving() as served:
        for protocol in PROTOCOLS:
            line = await fails(EXIT_USAGE, *argv, *at(served), *protocol, prefix="focas-net")
            assert f": {said}; see" in line, (protocol, line)


async def test_a_number_typed_as_it_reads_is_named_once() -> None:
    """Typed in decimal, the number is not named twice (``65536 reads as 65536``)."""
    async with serving() as served:
        line = await fails(
            EXIT_USAGE, "pmc", "read", "R", "65536", "0x1", *at(served), prefix="focas-net"
        )
    assert line == (
        "focas-net pmc read: error: argument START: PMC start address 65536 is outside "
        "0..65535; see focas-net pmc read --help"
    ), line


# -- the diagnostic and status reads, named as FANUC's library names them ------------------------


async def test_a_refused_diagnostic_read_names_cnc_diagnoss_on_both_transports() -> None:
    """``diag 300 --axis 9`` named ``cnc_rddiag`` (the packed protocol's command) over the
    packed protocol and ``cnc_diagnoss`` over FOCAS/2: both name FANUC's function."""
    async with serving() as served:
        lines = [
            await fails(EXIT_CNC, "diag", "300", "--axis", "9", *at(served), *p) for p in PROTOCOLS
        ]
    for line in lines:
        assert line.startswith("focas-net: EW_ATTRIB (4): data attribute"), lines
        assert "(cnc_diagnoss: axis 9 is outside 1..3: the path has 3 axes)" in line, lines


async def test_a_refused_status_read_names_cnc_statinfo() -> None:
    """A status read answered with an EW code named ``cnc_rdcncstat`` over the packed
    protocol, where FANUC's library (and the FOCAS/2 client) names ``cnc_statinfo``."""
    async with serving() as served:
        await ok("sim", "fault", "error", "--arg", "EW_BUSY", *at(served))
        line = await fails(EXIT_CNC, "status", *at(served))
    assert line == "focas-net: EW_BUSY (-1): busy, retry (cnc_statinfo)", line


# -- an option's number named as typed, the alarm's axis too -------------------------------------


@pytest.mark.parametrize(
    ("argv", "said"),
    [
        (
            ("sim", "alarm", "SV0411", "--axis", "-0x1"),
            "argument --axis: -0x1 reads as -1: axis -1 is outside 0..32767 (0: an alarm of no "
            "axis)",
        ),
        (("status", "--path", "0x0"), "argument --path: 0x0 reads as 0: path 0 is outside 1..10"),
        (("status", "--path", "0xB"), "argument --path: 0xB reads as 11: path 11 is outside 1..10"),
        (
            ("param", "set", "1320", "1", "--width", "0x3"),
            "argument --width: invalid choice: 0x3 (choose from 1, 2, 4)",
        ),
    ],
)
async def test_an_option_refused_names_the_number_as_typed(
    argv: tuple[str, ...], said: str
) -> None:
    """``sim alarm SV0411 --axis -0x1`` said ``axis -1 is outside ...``, ``--path 0x0`` said
    ``path 0``, ``--width 0x3`` ``invalid choice: 3``, where ``param get 1 --axis -0x1`` leads
    with ``-0x1 reads as -1``: every number option names what was typed."""
    line = await fails(EXIT_USAGE, *argv, "--port", "1", prefix="focas-net")
    assert f"{said}; see" in line, line


@pytest.mark.parametrize(
    ("argv", "said"),
    [
        (("pmc", "read", "R", "+70000"), "argument START: PMC start address 70000 is outside"),
        (("sim", "override", "--feed", "+300"), "argument --feed: feed override 300 outside"),
    ],
)
async def test_a_number_with_a_plus_sign_is_not_read_back_to_the_user(
    argv: tuple[str, ...], said: str
) -> None:
    """``pmc read R +70000`` led with ``+70000 reads as 70000``: a sign changes nothing a
    user needs told; a base (``0x``) or digits beyond ASCII do."""
    async with serving() as served:
        line = await fails(EXIT_USAGE, *argv, *at(served), prefix="focas-net")
    assert said in line and "reads as" not in line, line


async def test_a_serve_option_refused_with_another_names_the_number_as_typed() -> None:
    """``serve --fleet 0x3 --port 65534`` said ``--fleet 3 from --port 65534 runs past
    65535``: the number leads as typed, as every refusal of a number read does."""
    line = await fails(EXIT_USAGE, "serve", "--fleet", "0x3", "--port", "65534", prefix="focas-net")
    assert line == (
        "focas-net serve: error: argument --fleet: 0x3 reads as 3: 3 machines from --port 65534 "
        "run past 65535 (the last machine would get port 65536); see focas-net serve --help"
    ), line
