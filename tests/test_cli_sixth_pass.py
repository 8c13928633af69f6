"""What a new user runs into, sixth pass: the command line as a child process against a real
server (127.0.0.1, ephemeral port) on both transports, its exit codes and its one-line
messages, and the Python clients beside it.

Each test names what a user typed and what the command must say.
"""

from __future__ import annotations

import asyncio
import re
from decimal import Decimal
from pathlib import Path

import pytest
from cli_support import at, fails, ok
from support import IO_TIMEOUT, LoopbackPeer, Served, serving

from focas_net.cli import EXIT_CNC, EXIT_PROTOCOL, EXIT_USAGE
from focas_net.client import FocasClient, NativeClient
from focas_net.sim import MachineError, load_machine
from focas_net.web import ActionError, Station, perform

#: The transports, as the command line chooses them.
PROTOCOLS = [[], ["--protocol", "native"]]


# -- a macro value far beyond what a variable holds ---------------------------------------------


@pytest.mark.parametrize("protocol", PROTOCOLS)
@pytest.mark.parametrize(
    "typed",
    [
        "1e99999999999",
        "1e-99999999999",
        "-1e-30",
        "9E+9999",
        "0e99999999999",
        "1e-9",
        "2.147483647e9",
    ],
)
async def test_a_macro_value_with_an_exponent_is_refused_as_typed(
    server: Served, protocol: list[str], typed: str
) -> None:
    """1e99999999999 raised decimal.Overflow (a traceback); 1e-99999999999 was written as 0.
    A CNC's keys write no exponent, and the page refuses one: so does the command line, before
    anything is sent, whatever the exponent."""
    server.machine.write_macro(100, Decimal(7))
    line = await fails(
        EXIT_USAGE, "macro", "set", "100", typed, *protocol, *at(server), prefix="focas-net"
    )
    assert line == (
        f"focas-net macro set: error: argument VALUE: #100: not a number: {typed!r} (no exponent: "
        "write the digits); see focas-net macro set --help"
    )
    assert server.machine.read_macro(100) == 7


@pytest.mark.parametrize("typed", ["0", "0.000000001", "2147483647", "-0.5", "+12.", ".25"])
async def test_a_macro_value_written_in_digits_is_written(server: Served, typed: str) -> None:
    out = await ok("macro", "set", "100", typed, *at(server))
    assert out.startswith("#100 = ") and out.endswith("(written)\n")
    assert server.machine.read_macro(100) == Decimal(typed)


async def test_both_clients_refuse_a_huge_exponent_before_sending(server: Served) -> None:
    async with (
        FocasClient(server.host, server.port, timeout=IO_TIMEOUT) as packed,
        NativeClient(server.host, server.port, timeout=IO_TIMEOUT) as native,
    ):
        for client in (packed, native):
            with pytest.raises(ValueError, match="does not fit a macro variable"):
                await client.write_macro(100, Decimal("1e-99999999999"))
            with pytest.raises(ValueError, match=r"not a number: '1e99999999999' \(no exponent"):
                await client.write_macro(100, "1e99999999999")


# -- an alarm message that is no line of text ----------------------------------------------------


@pytest.mark.parametrize(
    ("typed", "shown", "char"),
    [("a\nb", "'a\\nb'", "'\\n' (U+000A)"), ("tab\there", "'tab\\there'", "'\\t' (U+0009)"),
     ("\x7f", "'\\x7f'", "'\\x7f' (U+007F)")],
)  # fmt: skip
async def test_an_alarm_message_with_a_control_character_says_which(
    server: Served, typed: str, shown: str, char: str
) -> None:
    """It was EW_DATA (exit 1) with "its type, number or message is out of range"; the machine
    knew the character, and the page showed it."""
    words = (
        f"alarm message {shown} holds the control character {char}: a message is one line of text"
    )
    line = await fails(EXIT_USAGE, "sim", "alarm", "PS0102", typed, *at(server), prefix="focas-net")
    assert line == (
        f"focas-net sim alarm: error: argument MESSAGE: {words}; see focas-net sim alarm --help"
    )
    assert list(server.machine.active_alarms()) == []
    with pytest.raises(ActionError) as refused:  # the page's text, refused as the client's
        perform(
            Station(0, server.machine), "raise_alarm", {"alm_type": 3, "alm_no": 102, "msg": typed}
        )
    assert str(refused.value) == f"msg: {words}"
    with pytest.raises(MachineError) as kept:  # and the machine's own check says the same
        server.machine.raise_alarm(0, 3, 102, typed)
    assert str(kept.value).endswith(words)


async def test_a_control_character_past_what_the_machine_keeps_is_cut_with_it(
    server: Served,
) -> None:
    """The machine keeps 32 characters: what it cuts off is not checked, on every front end."""
    typed = "x" * 32 + "\n"
    out = await ok("sim", "alarm", "PS0103", typed, *at(server))
    assert re.fullmatch(r"raised PS0103 x{32}\n", out), out


# -- a machine file's macro value written as a decimal ------------------------------------------

_MACROS = '[machine]\nname = "m"\naxes = ["X"]\n[macros]\n{ranges}values = {{ 500 = {value} }}\n'
_RANGE = "ranges = [{ first = 500, last = 999 }]\n"


@pytest.mark.parametrize(
    ("value", "words"),
    [
        ("1.5", "must be an integer or [mcr_val, dec_val] (1.5 is [15, 1]), got 1.5"),
        ("-2.25", "must be an integer or [mcr_val, dec_val] (-2.25 is [-225, 2]), got -2.25"),
        ("100.0", "must be an integer or [mcr_val, dec_val] (100.0 is [100, 0]), got 100.0"),
        ("1e300", "must be an integer or [mcr_val, dec_val], got 1e300"),
        ("nan", "must be an integer or [mcr_val, dec_val], got nan"),
    ],
)
async def test_a_macro_value_written_as_a_decimal_says_how_to_write_it(
    tmp_path: Path, value: str, words: str
) -> None:
    """It said "must be an integer, got a float (1.5)", with no word of [mcr_val, dec_val]."""
    path = tmp_path / "m.toml"
    path.write_text(_MACROS.format(ranges=_RANGE, value=value), encoding="utf-8")
    line = await fails(
        EXIT_USAGE, "serve", "--machine", str(path), "--port", "0", prefix="focas-net"
    )
    assert line.endswith(f"m.toml: macros.values.500: {words}"), line


async def test_a_macro_value_of_a_file_without_ranges_says_so(tmp_path: Path) -> None:
    path = tmp_path / "m.toml"
    path.write_text(_MACROS.format(ranges="", value="1"), encoding="utf-8")
    line = await fails(
        EXIT_USAGE, "serve", "--machine", str(path), "--port", "0", prefix="focas-net"
    )
    assert line.endswith("m.toml: macros.values.500: #500 is in no macro range (ranges gives none)")


# -- a peer whose answer starts as a FOCAS/2 frame and is none --------------------------------


class _Garbage(LoopbackPeer):
    """Answers any connection with A0 A0 A0 A0 and text, then closes it."""

    async def _serve(self, reader: asyncio.StreamReader, writer: asyncio.StreamWriter) -> None:
        writer.write(b"\xa0\xa0\xa0\xa0garbage-garbage-garbage")
        await writer.drain()
        writer.close()


@pytest.mark.parametrize(
    ("protocol", "rule"),
    [
        ([], "frame length 2694881440 outside 4..65536"),
        (["--protocol", "native"], "its answer is a frame of type 0x7262"),
    ],
)
async def test_a_peer_sending_a0_a0_a0_a0_and_text_does_not_speak_focas(
    protocol: list[str], rule: str
) -> None:
    """FOCAS/2 said "its answer does not start with A0 A0 A0 A0" (it did), showing bytes from
    the middle of the answer."""
    async with _Garbage() as peer:
        line = await fails(EXIT_PROTOCOL, "status", "--timeout", "2", *protocol, *at(peer))
    assert line == (
        f"focas-net: 127.0.0.1:{peer.port} does not speak the FOCAS protocol ({rule}; it sent "
        "A0 A0 A0 A0 67 61 72 62)"
    )


# -- an empty name where a file or a folder belongs ---------------------------------------------


@pytest.mark.parametrize(
    "argv",
    [
        ["serve", "--port", "0", "--machine", ""],
        ["serve", "--port", "0", "--state", " "],
        ["serve", "--port", "0", "--tls-cert", "", "--tls-key", "k.pem"],
        ["status", "--tls-ca", "", "--port", "1"],
    ],
)
async def test_an_empty_file_name_is_a_usage_error(argv: list[str]) -> None:
    """``--machine ''`` said ": cannot read: Is a directory"; ``--state ''`` was ignored."""
    line = await fails(EXIT_USAGE, *argv, prefix="focas-net")
    option = next(a for a in argv if a in ("--machine", "--state", "--tls-cert", "--tls-ca"))
    given = "' '" if option == "--state" else "''"
    assert f"argument {option}: an empty name is no file or folder, got {given};" in line, line


async def test_program_load_of_an_empty_name_asks_for_the_file(server: Served) -> None:
    """It said "cannot read '': Is a directory"."""
    line = await fails(EXIT_USAGE, "program", "load", "", *at(server), prefix="focas-net")
    assert line == (
        "focas-net program: error: argument N|FILE: program load needs the file of the "
        "program, e.g. o1000.nc ('' names none); see focas-net program --help"
    )


# -- refusals that named a number or showed nothing --------------------------------------------


async def test_a_program_search_outside_mem_and_edit_names_the_mode(server: Served) -> None:
    """The machine said "program search in mode 0: MEM or EDIT"; it names the mode."""
    server.machine.set_panel(mode=0)
    with pytest.raises(MachineError) as refused:
        perform(Station(0, server.machine), "select_program", {"number": "O0001"})
    assert str(refused.value).endswith("program search refused: the mode is MDI, not MEM or EDIT")


async def test_an_active_alarm_of_no_message_says_so(server: Served) -> None:
    """It said "PS0100 is already active:  (a CNC ...", an empty message between two spaces."""
    server.machine.raise_alarm(0, 3, 100)
    out = await ok("sim", "alarm", "PS0100", "again", *at(server))
    assert out == (
        "PS0100 is already active (with no message) (a CNC shows one entry per alarm: clear it "
        "first to raise it with another message)\n"
    )


@pytest.mark.parametrize("protocol", PROTOCOLS)
async def test_a_bit_write_the_parameter_cannot_hold_names_the_bit(
    server: Served, protocol: list[str]
) -> None:
    """Setting bit 31 of 6711 (0..999999999) said "the CNC refused 1 for parameter 6711"."""
    server.machine.set_panel(mode=0, pwe=1)
    line = await fails(EXIT_CNC, "param", "set", "6711.31", "1", *protocol, *at(server))
    assert line.endswith(
        "the CNC refused parameter 6711 with bit 31 set to 1: the value that makes is outside "
        "the parameter's range"
    ), line


@pytest.mark.parametrize(("extra", "shown"), [("", "''"), ("a b", "'a b'"), ("x", "x")])
async def test_an_argument_too_many_is_shown_as_typed(
    server: Served, extra: str, shown: str
) -> None:
    """An empty one showed as nothing: "unrecognized arguments:;"."""
    line = await fails(
        EXIT_USAGE, "pmc", "bit", "R", "0.1", "1", extra, *at(server), prefix="focas-net"
    )
    assert f"error: unrecognized arguments: {shown}; see focas-net pmc bit --help" in line, line


# -- --path of a path the CNC has not, for the reads no path changes ------------------------------


@pytest.mark.parametrize("protocol", PROTOCOLS)
@pytest.mark.parametrize(
    "command", [["sysinfo"], ["pmc", "read", "R", "0", "1"], ["alarms", "--history", "5"]]
)
async def test_a_path_the_cnc_has_not_is_ew_path_for_every_command(
    server: Served, protocol: list[str], command: list[str]
) -> None:
    """``sysinfo --path 2`` on a machine of one path answered as if path 2 were there, while
    ``status --path 2`` said EW_PATH."""
    line = await fails(EXIT_CNC, *command, "--path", "2", *protocol, *at(server))
    assert line == (
        "focas-net: EW_PATH (11): path number error (cnc_setpath); the CNC has no path 2: it "
        "has path 1 only (leave out --path)"
    )


#: The example machine of two paths.
LATHE = Path(__file__).resolve().parent.parent / "examples" / "lathe_2path.toml"


async def test_the_second_path_of_a_lathe_is_read() -> None:
    machine = load_machine(LATHE)
    async with serving(machine) as served:
        for protocol in PROTOCOLS:
            assert "cnc_type" in await ok("sysinfo", "--path", "2", *protocol, *at(served))


@pytest.mark.parametrize(
    ("typed", "words"),
    [("", "not a whole number: '' (nothing typed)"), ("x", "not a whole number: 'x'")],
)
async def test_a_width_that_is_no_number_is_worded_as_every_number(
    server: Served, typed: str, words: str
) -> None:
    """``--width ''`` said argparse's "invalid int value: ''"."""
    line = await fails(
        EXIT_USAGE, "param", "set", "6711", "1", "--width", typed, *at(server), prefix="focas-net"
    )
    assert f"argument --width: {words};" in line, line
