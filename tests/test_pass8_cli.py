"""A new user's eighth pass over the command line: one number reader for every number a
command takes, one refusal alike on both transports, every refusal naming the argument as
--help names it, names read in any case, ``alarms --follow`` saying ``reconnected`` only once
the CNC answered, a message refused before an alarm is found active.

Each test runs ``focas-net`` as a user does (a subprocess) and checks its one line and its
exit code, on ``--protocol packed`` and ``--protocol native`` where the command runs on both.
"""

from __future__ import annotations

import asyncio
import json
import signal
from pathlib import Path
from typing import Final

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
from support import IO_TIMEOUT, Served, serving, wait_until

from focas_net.cli import EXIT_CNC, EXIT_CONNECTION, EXIT_OK, EXIT_USAGE, _run, main
from focas_net.server import FocasServer

PROTOCOLS: Final = (["--protocol", "packed"], ["--protocol", "native"])


# -- one number reader --------------------------------------------------------------------


@pytest.mark.parametrize("protocol", PROTOCOLS)
@pytest.mark.parametrize("typed", ["0x717", "0b11100010111", "0o3427", " 1815 ", "+1815"])
async def test_a_parameter_number_is_read_as_every_whole_number(
    server: Served, protocol: list[str], typed: str
) -> None:
    """As ``diag 0x12c`` and ``pmc read R 0x10`` read theirs (docs/cli.md, "Numbers as
    typed"): ``param get 0x717`` is parameter 1815, as is its bit ``0x717.4``."""
    plain = await ok("param", "get", "1815", "--axis", "1", *protocol, *at(server))
    assert await ok("param", "get", typed, "--axis", "1", *protocol, *at(server)) == plain
    bit = await ok("param", "get", "1815.4", "--axis", "1", *protocol, *at(server))
    typed_bit = f"{typed.strip()}.4"
    assert await ok("param", "get", typed_bit, "--axis", "1", *protocol, *at(server)) == bit


@pytest.mark.parametrize("protocol", PROTOCOLS)
async def test_a_negative_parameter_number_reads_as_a_negative_diagnostic_number(
    server: Served, protocol: list[str]
) -> None:
    """``param get -1`` named the form it expected while ``diag -1`` named the range: both
    name the range now, in the words the clients check it with."""
    diag = await fails(EXIT_USAGE, "diag", "-1", *protocol, *at(server), prefix="focas-net")
    param = await fails(
        EXIT_USAGE, "param", "get", "-1", *protocol, *at(server), prefix="focas-net"
    )
    assert diag == (
        "focas-net diag: error: argument NUMBER: diagnostic number -1 is outside 0..32767; "
        "see focas-net diag --help"
    )
    assert param == (
        "focas-net param get: error: argument NUMBER[.BIT]: parameter number -1 is outside "
        "0..32767; see focas-net param get --help"
    )


@pytest.mark.parametrize(
    ("typed", "why"),
    [
        ("", " (nothing typed)"),
        ("1e3", " (no exponent: write the digits)"),
        (
            "\u0661\u0668",
            " ('\u0661\u0668' holds a digit beyond ASCII ('\u0661', U+0661): write 0-9)",
        ),
    ],
)
async def test_a_parameter_number_refused_keeps_the_number_rules_reason(
    server: Served, typed: str, why: str
) -> None:
    line = await fails(EXIT_USAGE, "param", "get", typed, *at(server), prefix="focas-net")
    expected = (
        "focas-net param get: error: argument NUMBER[.BIT]: expected NUMBER or NUMBER.BIT "
        "(e.g. 1815 or 1815.0), got "
    )
    assert line == f"{expected}{typed!r}{why}; see focas-net param get --help"


@pytest.mark.parametrize("protocol", PROTOCOLS)
async def test_a_pmc_bit_address_in_hex_reads_as_pmc_read_reads_it(
    server: Served, protocol: list[str]
) -> None:
    server.machine.write_pmc("R", 16, b"\x02")  # bit 1 set
    assert await ok("pmc", "bit", "R", "0x10.1", *protocol, *at(server)) == "R16.1 = 1\n"


# -- one refusal alike on both transports ---------------------------------------------------


async def _same_on_both(code: int, *argv: str, server: Served) -> str:
    packed = await fails(code, *argv, "--protocol", "packed", *at(server))
    native = await fails(code, *argv, "--protocol", "native", *at(server))
    assert packed == native
    return packed


async def test_a_value_with_decimals_for_an_axis_parameter_without_axis_reads_alike(
    server: Served,
) -> None:
    """Packed answered EW_ATTRIB (its width read needed the axis) where FOCAS/2, which asks
    the type first, said 1.5 is no integer: both ask the type first now."""
    line = await _same_on_both(EXIT_USAGE, "param", "set", "1420", "1.5", server=server)
    assert line == "focas-net: parameter 1420 is not a real parameter: 1.5 is no integer"


async def test_an_axis_parameter_written_without_axis_is_the_writes_refusal_on_both(
    server: Served,
) -> None:
    line = await _same_on_both(EXIT_CNC, "param", "set", "1420", "1000", server=server)
    assert line == (
        "focas-net: EW_ATTRIB (4): data attribute / data type error (cnc_wrparam); "
        "parameter 1420 is an axis parameter: give --axis 1..3"
    )
    assert server.machine.read_param(1420, 1) == 24000  # nothing written


async def test_a_parameter_the_cnc_lacks_is_the_writes_refusal_on_both(server: Served) -> None:
    line = await _same_on_both(EXIT_CNC, "param", "set", "9999", "1", server=server)
    assert line.startswith("focas-net: EW_NUMBER (3): data number / address range error ")
    assert "(cnc_wrparam); the CNC has no parameter 9999" in line


# -- refusals naming the argument -------------------------------------------------------------


@pytest.mark.parametrize("protocol", PROTOCOLS)
@pytest.mark.parametrize(
    ("argv", "line"),
    [
        (
            ["pmc", "bit", "R", "0.1", "2"],
            "focas-net pmc bit: error: argument VALUE: expected 1, on, true, yes or set, or 0, "
            "off, false, no or clear, got '2'; see focas-net pmc bit --help",
        ),
        (
            ["param", "set", "1815.0", "2", "--axis", "1"],
            "focas-net param set: error: argument VALUE: expected 1, on, true, yes or set, or 0, "
            "off, false, no or clear, got '2'; see focas-net param set --help",
        ),
        (
            ["param", "set", "1420", "", "--axis", "1"],
            "focas-net param set: error: argument VALUE: not a number: '' (nothing typed); "
            "see focas-net param set --help",
        ),
        (
            ["param", "set", "1420", "abc"],
            "focas-net param set: error: argument VALUE: not a number: 'abc'; "
            "see focas-net param set --help",
        ),
        (
            ["pmc", "write", "R", "0", "--hex", ""],
            "focas-net pmc write: error: argument --hex: no data bytes given; "
            "see focas-net pmc write --help",
        ),
        (
            ["pmc", "write", "R", "0", "--hex", "0g"],
            "focas-net pmc write: error: argument --hex: not hex bytes: '0g'; "
            "see focas-net pmc write --help",
        ),
        (
            ["pmc", "write", "R", "0", "1", "256"],
            "focas-net pmc write: error: argument BYTE: byte value '256' outside 0..255; "
            "see focas-net pmc write --help",
        ),
    ],
)
async def test_a_refused_value_names_its_argument(
    server: Served, protocol: list[str], argv: list[str], line: str
) -> None:
    assert await fails(EXIT_USAGE, *argv, *protocol, *at(server), prefix="focas-net") == line


async def test_a_mode_that_is_none_names_mode(server: Served) -> None:
    line = await fails(EXIT_USAGE, "sim", "panel", "--mode", "2", *at(server), prefix="focas-net")
    assert line == (
        "focas-net sim panel: error: argument --mode: unknown mode 2 (one of MDI, MEM, EDIT, "
        "HND, JOG, TJOG, THND, INC, REF, RMT); see focas-net sim panel --help"
    )


# -- choices named as --help names them, read in any case -------------------------------------


@pytest.mark.parametrize(
    ("argv", "line"),
    [
        (
            ["sim", "fault", "drp"],
            "focas-net sim fault: error: argument KIND: unknown fault kind 'drp' (one of "
            "delay, drop, error, split); see focas-net sim fault --help",
        ),
        (
            ["sim", "cycle", "Stat"],
            "focas-net sim cycle: error: argument ACTION: unknown cycle action 'Stat' (one of "
            "start, hold, reset); see focas-net sim cycle --help",
        ),
        (
            ["program", "lst"],
            "focas-net program: error: argument ACTION: invalid choice: 'lst' (choose from "
            "'list', 'show', 'load', 'delete', 'select'); see focas-net program --help",
        ),
    ],
)
async def test_a_choice_that_is_none_is_named_as_the_help_names_it(
    server: Served, argv: list[str], line: str
) -> None:
    assert await fails(EXIT_USAGE, *argv, *at(server), prefix="focas-net") == line


async def test_choices_are_read_in_any_case_as_modes_and_areas_are(server: Served) -> None:
    assert await ok("program", "LIST", *at(server)) == await ok("program", "list", *at(server))
    machine = await ok("position", "--kind", "machine", *at(server))
    assert await ok("position", "--kind", " MACHINE ", *at(server)) == machine
    native = await ok("status", "--protocol", "native", *at(server))
    assert await ok("status", "--protocol", "NATIVE", *at(server)) == native
    faults = json.loads(await ok("sim", "faults", "--scope", "Connection", "--json", *at(server)))
    assert faults == {"scope": "connection", "faults": []}
    out = await ok("sim", "fault", "DROP", "--scope", "CONNECTION", *at(server))
    assert out.startswith("the next answer on this connection: ")
    assert json.loads(await ok("sim", "cycle", "RESET", "--json", *at(server)))["action"] == "reset"


async def test_the_help_lists_the_choices_of_a_positional_named_in_upper_case() -> None:
    words = " ".join((await ok("sim", "fault", "--help")).split())
    assert (
        "positional arguments: KIND what happens to the answers: delay, drop, error or split"
        in words
    )
    words = " ".join((await ok("sim", "cycle", "--help")).split())
    assert "positional arguments: ACTION what to press: start, hold or reset" in words


# -- sim alarm ------------------------------------------------------------------------------


async def test_a_message_refused_is_refused_also_when_the_alarm_is_active(
    server: Served,
) -> None:
    """It was "already active" and exit 0, the bad message never checked."""
    await ok("sim", "alarm", "PS0100", *at(server))
    for message in ("\u00e9", "a\tb"):
        line = await fails(
            EXIT_USAGE, "sim", "alarm", "PS0100", message, *at(server), prefix="focas-net"
        )
        fresh = await fails(
            EXIT_USAGE, "sim", "alarm", "PS0101", message, *at(server), prefix="focas-net"
        )
        assert line == fresh
    assert [a.alm_no for a in server.machine.active_alarms()] == [100]


# -- serve --state --------------------------------------------------------------------------


async def test_a_state_folder_that_is_a_file_is_named_once(tmp_path: Path) -> None:
    afile = tmp_path / "afile"
    afile.write_text("not a folder\n")
    got, out, err = await run_focas_net("serve", "--port", "0", "--state", str(afile))
    assert (got, out) == (EXIT_USAGE, "")
    assert one_line(err, "focas-net serve: ") == (
        f"focas-net serve: error: --state {afile}: not a directory"
    )


async def test_a_state_folder_beneath_a_file_names_both(tmp_path: Path) -> None:
    afile = tmp_path / "afile"
    afile.write_text("not a folder\n")
    beneath = afile / "state"
    got, _out, err = await run_focas_net("serve", "--port", "0", "--state", str(beneath))
    assert got == EXIT_USAGE
    line = one_line(err, "focas-net serve: ")
    assert line.startswith(f"focas-net serve: error: --state {beneath}: ")
    assert line.count(str(beneath)) <= 2 and line.endswith("not a directory")


# -- alarms --follow: reconnected once the CNC answered ---------------------------------------


class _Silent:
    """A TCP server on one port of 127.0.0.1 that accepts, reads and never answers; counts
    the connections that ended (the client gave up on them)."""

    def __init__(self) -> None:
        self.ended = 0
        self._server: asyncio.Server | None = None

    async def _serve(self, reader: asyncio.StreamReader, writer: asyncio.StreamWriter) -> None:
        try:
            while await reader.read(4096):
                pass
        finally:
            self.ended += 1
            writer.close()

    async def start(self, port: int) -> None:
        self._server = await asyncio.start_server(self._serve, "127.0.0.1", port)

    async def stop(self) -> None:
        assert self._server is not None
        self._server.close()
        await self._server.wait_closed()


@pytest.mark.parametrize("protocol", ["packed", "native"])
async def test_follow_says_reconnected_only_once_the_cnc_answered(
    protocol: str, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    """A peer that takes the TCP connect and says nothing is no CNC back: the packed
    follower said "reconnected" on the connect alone; now, as FOCAS/2's, once the CNC
    answered on the new connection."""
    monkeypatch.setattr(_run, "FOLLOW_MAX_FAILURES", 1000)
    printed: list[str] = []
    errors: list[str] = []

    def seen(text: str) -> bool:
        captured = capsys.readouterr()
        printed.append(captured.out)
        errors.append(captured.err)
        return text in "".join(printed) + "".join(errors)

    silent = _Silent()
    async with serving() as served:
        port, machine = served.port, served.machine
        machine.raise_alarm(0, 3, 100, "FIRST")
        argv = ["alarms", "--follow", "--interval", "0.05", "--timeout", "0.5", "--count", "2"]
        argv += ["--port", str(port), "--protocol", protocol]
        follow = asyncio.create_task(asyncio.to_thread(main, argv))
        await wait_until(lambda: seen("raised"), 4 * IO_TIMEOUT)
    await silent.start(port)
    try:
        await wait_until(lambda: seen("lost"), 4 * IO_TIMEOUT)
        await wait_until(lambda: silent.ended >= 2 and not seen("?"), 8 * IO_TIMEOUT)
        assert "reconnected" not in "".join(errors)  # two attempts met the silent peer
    finally:
        await silent.stop()
    back = FocasServer(machine, host="127.0.0.1", port=port, grace_period=1.0)
    async with back:
        await wait_until(lambda: seen("reconnected"), 8 * IO_TIMEOUT)
        machine.raise_alarm(0, 3, 101, "SECOND")
        async with asyncio.timeout(4 * IO_TIMEOUT):
            code = await follow
    assert code == EXIT_OK
    seen("")
    assert "".join(printed).splitlines() == ["raised   PS0100 FIRST", "raised   PS0101 SECOND"]
    lines = "".join(errors).splitlines()
    assert lines[0].startswith(f"focas-net: connection to 127.0.0.1:{port} lost")
    assert lines[-1] == f"focas-net: reconnected to 127.0.0.1:{port}"
    assert sum("reconnected" in line for line in lines) == 1


async def test_follow_gives_up_on_a_silent_peer_without_saying_reconnected(
    monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    """Every reconnect attempt meets a peer that never answers: the follower gives up
    (exit 3) and never said ``reconnected``."""
    monkeypatch.setattr(_run, "FOLLOW_RECONNECT_ATTEMPTS", 2)
    monkeypatch.setattr(_run, "FOLLOW_MAX_FAILURES", 1000)
    printed: list[str] = []

    def followed() -> bool:
        printed.append(capsys.readouterr().out)
        return "raised" in "".join(printed)

    silent = _Silent()
    async with serving() as served:
        port = served.port
        served.machine.raise_alarm(0, 3, 100, "FIRST")
        argv = ["alarms", "--follow", "--interval", "0.05", "--timeout", "0.5"]
        follow = asyncio.create_task(asyncio.to_thread(main, [*argv, "--port", str(port)]))
        await wait_until(followed, 4 * IO_TIMEOUT)
    await silent.start(port)
    try:
        async with asyncio.timeout(12 * IO_TIMEOUT):
            code = await follow
    finally:
        await silent.stop()
    err = capsys.readouterr().err
    assert code == EXIT_CONNECTION, err
    assert "reconnected" not in err
    assert "alarms --follow gave up after" in err.splitlines()[-1]


# -- Ctrl-C in the middle of the output, on FOCAS/2 ----------------------------------------


async def test_follow_on_focas2_stopped_after_its_first_event_ends_with_0(server: Served) -> None:
    server.machine.raise_alarm(0, 3, 100, "FIRST")
    argv = ["alarms", "--follow", "--json", "--interval", "0.05", "--protocol", "native"]
    proc = await focas_net_process(*argv, *at(server))
    assert proc.stdout is not None
    async with killed_at_exit(proc), asyncio.timeout(SUBPROCESS_TIMEOUT):
        first = json.loads(await proc.stdout.readline())
        assert first["event"] == "raised" and first["alarm"]["code"] == "PS0100"
        proc.send_signal(signal.SIGINT)
        out, err = await proc.communicate()
    assert (proc.returncode, out, err) == (EXIT_OK, b"", b"")


# -- what is required -------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("argv", "required"),
    [
        (["sim", "alarm"], "ALARM"),  # the MESSAGE may be left out (docs/cli.md)
        (["sim", "alarm", "--axis", "1"], "ALARM"),
        (["pmc", "write", "R"], "START"),  # the bytes may come with --hex instead
        (["pmc", "write"], "AREA, START"),
    ],
)
async def test_an_argument_that_may_be_left_out_is_not_named_required(
    argv: list[str], required: str
) -> None:
    line = await fails(EXIT_USAGE, *argv, "--port", "1", prefix="focas-net")
    command = " ".join(argv[:2])
    assert line == (
        f"focas-net {command}: error: the following arguments are required: {required}; "
        f"see focas-net {command} --help"
    )


async def test_an_alarm_message_after_the_axis_is_still_the_message(server: Served) -> None:
    out = await ok("sim", "alarm", "SV0411", "--axis", "2", "SERVO", "ALARM", *at(server))
    assert out == "raised SV0411 (axis 2) SERVO ALARM\n"


async def test_sim_clear_names_the_axis_of_each_alarm_it_cleared(server: Served) -> None:
    """``cleared PS0100, PS0100`` named two alarms alike: each is named as ``sim alarm``
    raised it."""
    assert await ok("sim", "alarm", "PS0100", "--axis", "1", *at(server)) == (
        "raised PS0100 (axis 1)\n"
    )
    await ok("sim", "alarm", "PS0100", *at(server))
    out = await ok("sim", "clear", "ps", *at(server))
    assert out == "cleared PS0100 (axis 1), PS0100; 0 still active\n"  # oldest raised first
