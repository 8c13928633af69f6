"""A new user's seventh pass over the command line: what FOCAS/2 cannot carry is named as
typed, every number keeps the number rule's reason, a call that waits for a reconnect says
why the reconnect fails, and Ctrl-C ends a command at any moment with the documented code.

Each test runs ``focas-net`` as a user does (a subprocess) and checks its one line and its
exit code; the client's reconnect message is checked on both transports."""

from __future__ import annotations

import asyncio
import os
import signal
from decimal import Decimal
from pathlib import Path

import pytest
from cli_support import (
    SUBPROCESS_TIMEOUT,
    at,
    fails,
    focas_net_process,
    killed_at_exit,
    ok,
    one_line,
    run_focas_net,
)
from support import LoopbackPeer, Served, serving

from focas_net._typed import MAX_DIGITS, decimal_number, whole_number
from focas_net.cli import EXIT_INTERRUPTED, EXIT_OK, EXIT_USAGE
from focas_net.client import CncClient, FocasClient, NativeClient, ReconnectPolicy
from focas_net.errors import FocasConnectionError

NATIVE = ["--protocol", "native"]


# -- what FOCAS/2 cannot carry, named as typed --------------------------------------------------


async def test_pmc_write_force_names_the_option_native_cannot_carry(server: Served) -> None:
    line = await fails(
        EXIT_USAGE,
        "pmc",
        "write",
        "X",
        "0",
        "1",
        "--force",
        *at(server),
        *NATIVE,
        prefix="focas-net",
    )
    assert line.startswith(
        "focas-net pmc write: error: pmc write --force is not available with --protocol "
        "native (FOCAS/2 Ethernet): --force writes through a simulator control command"
    ), line
    # without --force the command is carried
    assert (
        await ok("pmc", "write", "R", "0", "1", *at(server), *NATIVE) == "wrote 1 byte to R0: 01\n"
    )


async def test_sim_override_on_native_says_it_is_a_simulator_control(server: Served) -> None:
    line = await fails(
        EXIT_USAGE, "sim", "override", "--feed", "50", *at(server), *NATIVE, prefix="focas-net"
    )
    assert line == (
        "focas-net sim override: error: sim override is not available with --protocol native "
        "(FOCAS/2 Ethernet): the simulator controls are packed-protocol commands; see "
        "focas-net sim override --help"
    )


# -- numbers: the one rule's reason everywhere ------------------------------------------------


@pytest.mark.parametrize(
    ("option", "typed", "said"),
    [
        ("--port", "\u0661", "not a port number: '\u0661' holds a digit beyond ASCII"),
        ("--port", "", "not a port number: '' (nothing typed)"),
        ("--path", "\u0662", "not a path number: '\u0662' holds a digit beyond ASCII"),
        ("--path", " ", "not a path number: ' ' (nothing typed)"),
    ],
)
async def test_a_port_or_path_keeps_the_number_rules_reason(
    option: str, typed: str, said: str
) -> None:
    line = await fails(EXIT_USAGE, "status", option, typed, prefix="focas-net status: error: ")
    assert f"argument {option}: {said}" in line, line


@pytest.mark.parametrize(
    ("kind", "typed", "said"),
    [
        ("delay", "1.5", "--arg: not a whole number: '1.5'"),
        ("delay", "", "--arg: not a whole number: '' (nothing typed)"),
        ("delay", "\u0665", "--arg: '\u0665' holds a digit beyond ASCII"),
        ("error", "EW_BUSYY", "--arg: unknown EW code 'EW_BUSYY'"),
    ],
)
async def test_a_fault_argument_that_is_no_number_names_arg(
    server: Served, kind: str, typed: str, said: str
) -> None:
    line = await fails(
        EXIT_USAGE, "sim", "fault", kind, "--arg", typed, *at(server), prefix="focas-net"
    )
    assert line.startswith(f"focas-net sim fault: error: argument {said}"), line


# -- a call that waits for a reconnect says why the reconnect fails ------------------------------


@pytest.mark.parametrize("client_type", [FocasClient, NativeClient])
async def test_a_call_timing_out_while_reconnecting_names_the_last_attempts_failure(
    client_type: type[FocasClient] | type[NativeClient],
) -> None:
    policy = ReconnectPolicy(initial_delay=0.01, max_delay=0.05, jitter=0.0)
    async with serving() as served:
        client: CncClient = client_type(served.host, served.port, timeout=0.3, reconnect=policy)
        await client.connect()
        await served.server.aclose()
    try:
        said = ""
        for _ in range(40):  # bounded: each call ends within its 0.3 s timeout
            try:
                await client.read_status()
            except FocasConnectionError as exc:
                said = str(exc)
            if "the last reconnect attempt failed" in said:
                break
        assert said.startswith(f"still reconnecting to {served.host}:{served.port}"), said
        assert (
            f"the last reconnect attempt failed: cannot connect to {served.host}:"
            f"{served.port}: connection refused)"
        ) in said
    finally:
        await client.aclose()


# -- Ctrl-C at any moment -------------------------------------------------------------------


class _Silent(LoopbackPeer):
    """Accepts, reads what comes and never answers; ``seen`` is set at the first byte."""

    def __init__(self) -> None:
        self.seen = asyncio.Event()

    async def _serve(self, reader: asyncio.StreamReader, writer: asyncio.StreamWriter) -> None:
        try:
            while await reader.read(4096):
                self.seen.set()
        finally:
            writer.close()


async def _interrupted(*argv: str, signum: int = signal.SIGINT) -> tuple[int, str, str]:
    """``focas-net ARGV`` against a peer that never answers, sent ``signum`` once it asked."""
    async with _Silent() as peer:
        proc = await focas_net_process(*argv, "--port", str(peer.port), "--timeout", "60")
        async with killed_at_exit(proc), asyncio.timeout(SUBPROCESS_TIMEOUT):
            await peer.seen.wait()
            proc.send_signal(signum)
            out, err = await proc.communicate()
    assert proc.returncode is not None
    return proc.returncode, out.decode(), err.decode()


@pytest.mark.parametrize("protocol", [[], NATIVE])
@pytest.mark.parametrize("signum", [signal.SIGINT, signal.SIGTERM])
async def test_alarms_follow_stopped_while_it_connects_ends_with_0(
    protocol: list[str], signum: int
) -> None:
    """Docs: --follow runs until Ctrl-C or SIGTERM (exit 0), also before its first answer."""
    code, out, err = await _interrupted("alarms", "--follow", *protocol, signum=signum)
    assert (code, out, err) == (EXIT_OK, "", "")


async def test_watch_stopped_while_it_waits_for_its_first_frame_ends_with_0() -> None:
    code, out, err = await _interrupted("watch", signum=signal.SIGTERM)
    assert (code, err) == (EXIT_OK, "")
    assert "Traceback" not in out


@pytest.mark.parametrize("protocol", [[], NATIVE])
async def test_a_one_shot_command_interrupted_exits_130_without_a_traceback(
    protocol: list[str],
) -> None:
    code, out, err = await _interrupted("status", *protocol)
    assert (code, out, err) == (EXIT_INTERRUPTED, "", "")


async def test_the_exit_codes_in_help_list_130() -> None:
    text = await ok("status", "--help")
    assert "130 interrupted (Ctrl-C)" in " ".join(text.split())


# -- words the command would drop ------------------------------------------------------------


async def test_program_list_refuses_a_program_number_it_would_ignore(server: Served) -> None:
    line = await fails(EXIT_USAGE, "program", "list", "5", *at(server), prefix="focas-net")
    assert line == (
        "focas-net program: error: argument N|FILE: program list takes no program number or "
        "file, got '5' (program show N shows one); see focas-net program --help"
    )


# -- a CA file that holds no certificate ------------------------------------------------------


async def test_a_tls_ca_file_without_a_certificate_says_so_without_openssls_tags(
    tmp_path: Path,
) -> None:
    text = tmp_path / "notes.txt"
    text.write_text("root:x:0:0\n")
    broken = tmp_path / "broken.pem"
    broken.write_text("-----BEGIN CERTIFICATE-----\nabc\n-----END CERTIFICATE-----\n")
    line = await fails(
        EXIT_USAGE, "status", "--tls-ca", str(text), "--port", "1", prefix="focas-net"
    )
    assert line == (
        f"focas-net status: error: argument --tls-ca: {text}: no PEM certificate in it; "
        "see focas-net status --help"
    )
    line = await fails(
        EXIT_USAGE, "status", "--tls-ca", str(broken), "--port", "1", prefix="focas-net"
    )
    assert line.startswith(
        f"focas-net status: error: argument --tls-ca: {broken}: a certificate in it cannot be "
        "read ("
    )
    assert "_ssl.c" not in line and "[" not in line


# -- numbers longer than Python reads, alarm codes in other scripts ---------------------------

_HUGE = "9" * 5000


@pytest.mark.parametrize(
    "argv",
    [
        ["macro", "get", _HUGE],
        ["macro", "set", "100", _HUGE],
        ["param", "set", "1420", _HUGE, "--axis", "1"],
        ["pmc", "read", "R", "0x" + "f" * 5000],
        ["sim", "alarm", "PS" + _HUGE],
        ["status", "--port", _HUGE],
    ],
)
async def test_a_number_of_thousands_of_digits_is_refused_in_the_projects_words(
    server: Served, argv: list[str]
) -> None:
    code, out, err = await run_focas_net(*argv, *at(server))
    assert (code, out) == (EXIT_USAGE, "")
    line = one_line(err, "focas-net")
    assert "5000 digits: no value holds more than 100" in line, line[-200:]
    assert "set_int_max_str_digits" not in line


def test_the_number_rule_reads_a_hundred_digits_and_leading_zeros() -> None:
    assert whole_number("9" * MAX_DIGITS) == int("9" * MAX_DIGITS)
    assert whole_number("-0x" + "0" * 99 + "7") == -7
    assert decimal_number("0." + "0" * 98 + "1") == Decimal("1e-99")
    with pytest.raises(ValueError, match=r"\(101 digits: no value holds more than 100\)$"):
        decimal_number("1" * 101)
    with pytest.raises(ValueError, match=r"\(5001 digits: no value holds more than 100\)$"):
        whole_number("0" * 5000 + "7")


@pytest.mark.parametrize("typed", ["PS\u0661\u0660\u0660", "\u0663:100", "3:\u0661\u0660\u0660"])
async def test_an_alarm_code_with_digits_of_another_script_is_refused(
    server: Served, typed: str
) -> None:
    line = await fails(EXIT_USAGE, "sim", "alarm", typed, *at(server), prefix="focas-net")
    assert line == (
        f"focas-net sim alarm: error: argument ALARM: not an alarm code: {typed!r} (expected "
        "e.g. PS0100, 3:100 or T31:0005); see focas-net sim alarm --help"
    )
    assert server.machine.active_alarms() == []


async def test_an_alarm_number_of_many_digits_names_the_range(server: Served) -> None:
    line = await fails(EXIT_USAGE, "sim", "alarm", "PS99999999999", *at(server), prefix="focas-net")
    assert line == (
        "focas-net sim alarm: error: argument ALARM: alarm number 99999999999 is outside "
        "0..32767; see focas-net sim alarm --help"
    )


# -- a reader that goes away ------------------------------------------------------------------


@pytest.mark.parametrize("protocol", [[], NATIVE])
async def test_alarms_follow_ends_when_its_reader_goes_away(
    server: Served, protocol: list[str]
) -> None:
    """As ``watch`` does: the first event written after the reader closed (``| head -1``)
    ends it, exit 0, where it went on polling for ever."""
    reader, writer = os.pipe()
    proc = await focas_net_process(
        "alarms", "--follow", "--interval", "0.05", *protocol, *at(server), stdout=writer
    )
    os.close(writer)
    try:
        async with killed_at_exit(proc), asyncio.timeout(SUBPROCESS_TIMEOUT):
            await ok("sim", "alarm", "PS0101", *at(server))
            first = await asyncio.to_thread(os.read, reader, 4096)
            assert first == b"raised   PS0101\n"
            os.close(reader)  # the reader goes away
            reader = -1
            await ok("sim", "alarm", "PS0102", *at(server))
            _out, err = await proc.communicate()
            assert (proc.returncode, err) == (EXIT_OK, b"")
    finally:
        if reader >= 0:
            os.close(reader)


@pytest.mark.parametrize(
    ("argv", "word"),
    [
        (["macro", "set", "100", "--1"], "--1"),
        (["param", "set", "1420", "--axis", "1", "--5"], "--5"),
        (["pmc", "read", "R", "--.5"], "--.5"),
    ],
)
async def test_a_number_with_two_minus_signs_is_named(
    server: Served, argv: list[str], word: str
) -> None:
    """It read as an unknown option, and the refusal named the argument it left missing."""
    command = " ".join(argv[:2])
    line = await fails(EXIT_USAGE, *argv, *at(server), prefix=f"focas-net {command}: error: ")
    assert line.startswith(
        f"focas-net {command}: error: argument {word!r} is no option: a negative number is "
        f"written with one minus ({word[1:]})"
    ), line


@pytest.mark.parametrize("protocol", [[], NATIVE])
async def test_a_pmc_bit_past_7_names_the_address_as_typed(
    server: Served, protocol: list[str]
) -> None:
    line = await fails(
        EXIT_USAGE, "pmc", "bit", "r", "1.8", "1", *at(server), *protocol, prefix="focas-net"
    )
    assert line == (
        "focas-net pmc bit: error: argument BYTE.BIT: R1.8: bit 8 is outside 0..7: a PMC "
        "address is 1 byte wide; see focas-net pmc bit --help"
    )


#: The command line's reference.
_CLI_DOCS = Path(__file__).resolve().parent.parent / "docs" / "cli.md"


async def test_the_docs_quote_the_line_of_a_value_checked_after_parsing(server: Served) -> None:
    line = await fails(EXIT_USAGE, "param", "get", "abc", *at(server), prefix="focas-net")
    docs = await asyncio.to_thread(_CLI_DOCS.read_text)
    assert f"(`{line}`;" in " ".join(docs.split())
