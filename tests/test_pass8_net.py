"""Transports and hints, eighth pass: what a new user meets with wrong peers, odd addresses,
``serve``'s options and Ctrl-C.

Ctrl-C twice: a terminal's user presses it again when the first seems slow. The second one,
a few milliseconds after the first, must change nothing: ``serve`` (one process or
``--workers``), ``watch`` and ``alarms --follow`` still exit 0 with nothing on stderr (the
second one used to kill the process by SIGINT once the interpreter finalized, to raise a
KeyboardInterrupt past the command, or, in ``serve --workers``' parent, to wait for ever on
a lock the first signal's handler held).

Servers here bind 127.0.0.1 on ephemeral ports; ``focas-net`` runs as a subprocess where its
exit code is checked.
"""

from __future__ import annotations

import asyncio
import os
import signal
import sys
from pathlib import Path
from typing import Final

import pytest
from cli_support import one_line, run_focas_net
from support import LoopbackPeer, serve_process, serving

from focas_net.cli import EXIT_PROTOCOL, _reasons, _run, _signals, build_parser
from focas_net.cli._args import parse_host
from focas_net.client import FocasClient, NativeClient
from focas_net.errors import EW, CncError, ProtocolError
from focas_net.server import FocasServer
from focas_net.sim import default_machine

#: Upper bound of a subprocess's start (an interpreter and the package imported) and end.
PROCESS_TIMEOUT: Final = 30.0


@pytest.mark.usefixtures("signals_restored")
def test_the_first_signal_stops_and_every_later_one_is_ignored_for_good() -> None:
    calls: list[str] = []

    def stop() -> None:
        calls.append("stop")
        signal.raise_signal(signal.SIGINT)  # a second Ctrl-C while the first is handled

    with _signals.on_first_signal(stop):
        signal.raise_signal(signal.SIGINT)
        signal.raise_signal(signal.SIGTERM)
    assert calls == ["stop"]
    # ignored after the block too: nothing is left for a late one to interrupt or kill
    assert signal.getsignal(signal.SIGINT) == signal.SIG_IGN
    assert signal.getsignal(signal.SIGTERM) == signal.SIG_IGN
    signal.raise_signal(signal.SIGINT)  # would raise KeyboardInterrupt were it not ignored


@pytest.mark.usefixtures("signals_restored")
def test_a_block_without_a_signal_puts_the_handlers_back() -> None:
    before = signal.getsignal(signal.SIGINT)
    with _signals.on_first_signal(lambda: None):
        assert signal.getsignal(signal.SIGINT) is not before
    assert signal.getsignal(signal.SIGINT) is before
    assert signal.getsignal(signal.SIGTERM) == signal.SIG_DFL


@pytest.mark.usefixtures("signals_restored")
def test_a_signal_stops_the_innermost_block() -> None:
    calls: list[str] = []
    with _signals.on_first_signal(lambda: calls.append("outer")):
        with _signals.on_first_signal(lambda: calls.append("inner")):
            signal.raise_signal(signal.SIGTERM)
    assert calls == ["inner"]


async def _ctrl_c_until_it_ends(proc: asyncio.subprocess.Process) -> tuple[int, str]:
    """Ctrl-C, then again every millisecond until the process is gone (a bounded number of
    times), so that a later one lands in every phase of its end; its exit code and stderr."""
    assert proc.stderr is not None
    errors = asyncio.ensure_future(proc.stderr.read())
    ended = asyncio.ensure_future(proc.wait())
    for _ in range(int(PROCESS_TIMEOUT * 1000)):
        if ended.done():
            break
        # os.kill, not send_signal: Popen's would reap the process behind asyncio's back
        # (whose wait then reports 255); a zombie not yet reaped takes the signal harmlessly.
        try:
            os.kill(proc.pid, signal.SIGINT)
        except ProcessLookupError:  # reaped, its end not yet reported to the loop
            break
        await asyncio.wait([ended], timeout=0.001)
    async with asyncio.timeout(PROCESS_TIMEOUT):
        code = await ended
        err = await errors
    return code, err.decode()


@pytest.mark.parametrize(
    "options", [(), ("--fleet", "2", "--workers", "2")], ids=["one-process", "workers"]
)
async def test_serve_exits_zero_on_ctrl_c_pressed_twice(options: tuple[str, ...]) -> None:
    lines = 2 if options else 1
    async with serve_process(*options, lines=lines, start_timeout=PROCESS_TIMEOUT) as (proc, _):
        assert await _ctrl_c_until_it_ends(proc) == (0, "")


async def _client(*argv: str) -> asyncio.subprocess.Process:
    return await asyncio.create_subprocess_exec(
        sys.executable, "-m", "focas_net", *argv,
        stdout=asyncio.subprocess.PIPE, stderr=asyncio.subprocess.PIPE,
    )  # fmt: skip


@pytest.mark.parametrize(
    "command",
    [("watch", "--json", "--interval", "0.1"), ("alarms", "--follow")],
    ids=["watch", "follow"],
)
async def test_until_told_commands_exit_zero_on_ctrl_c_pressed_twice(
    command: tuple[str, ...],
) -> None:
    async with serving() as served:
        served.machine.raise_alarm(0, 2, 1001, "SPINDLE ALARM")  # follow's first line
        proc = await _client(*command, "--host", "127.0.0.1", "--port", str(served.port))
        assert proc.stdout is not None
        async with asyncio.timeout(PROCESS_TIMEOUT):
            assert await proc.stdout.readline()  # it polls: its first line is out
        assert await _ctrl_c_until_it_ends(proc) == (0, "")


# -- a refusal's reason, for every code a peer may answer -----------------------------------

#: One command line of each command whose refusals have a table (focas_net/cli/_reasons.py).
_COMMAND_LINES: Final = {
    "param get": "param get 1020",
    "param set": "param set 1020 1",
    "diag": "diag 300",
    "macro get": "macro get 100",
    "macro set": "macro set 100 1",
    "macro clear": "macro clear 100",
    "pmc read": "pmc read R 0 1",
    "pmc write": "pmc write R 0 1",
    "pmc bit": "pmc bit R 0.1 1",
    "program load": "program load {program}",
    "program select": "program select 1",
    "program delete": "program delete 1",
    "program show": "program show 1",
    "sim panel": "sim panel",
    "sim alarm": "sim alarm EX1001",
    "sim clear": "sim clear",
    "sim cycle start": "sim cycle start",
    "sim cycle hold": "sim cycle hold",
    "sim cycle reset": "sim cycle reset",
    "sim override": "sim override",
    "sim fault": "sim fault drop",
    "sim faults": "sim faults",
    "versamax": "versamax 0 0",
    "unlock": "unlock ABCD",
}


def test_every_command_with_reasons_has_a_command_line_here() -> None:
    assert set(_COMMAND_LINES) == set(_reasons.FAMILIES)


@pytest.mark.parametrize("command", sorted(_COMMAND_LINES))
def test_every_code_a_peer_may_answer_has_a_reason_or_none_never_a_traceback(
    command: str, tmp_path: Path
) -> None:
    """A CNC, or a peer that is none, may answer any command any EW code: what the command
    prints then is the code and, where its table has one, a reason built from the command's
    own arguments (``param get`` has no ``--width``, ``macro get`` no value to name)."""
    program = tmp_path / "O1000.nc"
    program.write_text("O1000\nM30\n%\n")
    args = build_parser().parse_args(_COMMAND_LINES[command].format(program=program).split())
    assert _run.command_name(args) == command
    for ew in EW:
        if ew == EW.OK:
            continue
        said = _reasons.reason(command, args, CncError.from_ew(ew, "cnc_call"))
        assert said is None or said.strip(), (command, ew)


# -- a peer that sends back what it is sent -------------------------------------------------


class Echo(LoopbackPeer):
    """An echo server: every byte it reads, it sends back."""

    async def _serve(self, reader: asyncio.StreamReader, writer: asyncio.StreamWriter) -> None:
        try:
            for _ in range(1000):  # bounded: a command sends a few requests
                data = await reader.read(4096)
                if not data:
                    break
                writer.write(data)
                await writer.drain()
        except OSError:
            pass
        finally:
            writer.close()


ECHO_WORDS: Final = (
    "does not speak the FOCAS protocol (it sent back the request it was sent, as an echo "
    "server does"
)


@pytest.mark.parametrize("protocol", ["packed", "native"])
@pytest.mark.parametrize(
    "command",
    # a request without payload (its echo has no EW code), one whose echo read as EW_LENGTH
    # (which ended in a traceback: param get has no --width), one read as EW_DATA
    ["status", "param get 2", "pmc read R 5 1"],
)
async def test_an_echo_server_does_not_speak_focas_on_both_transports(
    protocol: str, command: str
) -> None:
    async with Echo() as peer:
        code, out, err = await run_focas_net(
            *command.split(), "--port", str(peer.port), "--protocol", protocol, "--timeout", "2"
        )
    assert (code, out) == (EXIT_PROTOCOL, "")
    line = one_line(err)
    assert line.startswith(f"focas-net: 127.0.0.1:{peer.port} {ECHO_WORDS}"), line


async def test_an_echoed_unlock_is_no_wrong_password() -> None:
    async with Echo() as peer:
        client = FocasClient("127.0.0.1", peer.port, timeout=2.0)
        async with client:
            with pytest.raises(ProtocolError, match=r"as an echo server does: cnc_wrunlockparam"):
                await client.unlock("ABCD")
            with pytest.raises(ProtocolError, match=r"as an echo server does: cnc_rdmacro"):
                await client.read_macro(500)  # 4 bytes: no EW code alone repeats them


async def test_an_ew_code_equal_to_a_two_byte_request_is_taken_as_the_cncs() -> None:
    """An answer of an EW code alone may equal a request of 2 bytes (``cnc_rdmacro`` of #5
    answered EW_DATA, 5): that is the CNC's refusal, not an echo."""
    async with Echo() as peer:
        async with FocasClient("127.0.0.1", peer.port, timeout=2.0) as client:
            with pytest.raises(CncError) as refused:
                await client.read_macro(5)
    assert refused.value.ew == EW.DATA


# -- a host typed with a colon and no port after it -----------------------------------------


@pytest.mark.parametrize(
    ("typed", "said"),
    [
        ("127.0.0.1:", "'127.0.0.1:' is a host with nothing after its colon"),
        ("[::1]:", "'[::1]:' is a host with nothing after its colon"),
        ("127.0.0.1:99999", "'127.0.0.1:99999' is a host and a port outside 1..65535"),
        ("127.0.0.1:0", "'127.0.0.1:0' is a host and a port outside 1..65535"),
        ("localhost:abc", "'localhost:abc' is a host, a colon and 'abc', which is no port number"),
        (
            "localhost:8193/",
            "'localhost:8193/' is a host, a colon and '8193/', which is no port number",
        ),
        (
            "127.0.0.1:٨١٩٣",
            "'127.0.0.1:٨١٩٣' is a host, a colon and '٨١٩٣', which is no port number",
        ),
    ],
)
def test_a_host_with_a_colon_but_no_port_is_never_an_ipv6_address_nor_given_that_port(
    typed: str, said: str
) -> None:
    """It read as `not an IPv6 address` (``127.0.0.1:``), or suggested ``--port 99999``."""
    host = typed.rpartition(":")[0].strip("[]")
    with pytest.raises(ValueError) as cli_refusal:
        parse_host(typed)
    assert str(cli_refusal.value) == f"{said}: give --host {host} and --port 1..65535"
    for client in (FocasClient, NativeClient):
        with pytest.raises(ValueError) as refusal:
            client(typed, 8193)
        assert str(refusal.value) == (
            f"host {said}: give the host {host!r} and a port 1..65535 apart"
        )


async def test_a_host_with_a_colon_and_no_port_at_the_command_line() -> None:
    code, out, err = await run_focas_net("status", "--host", "127.0.0.1:")
    assert (code, out) == (2, "")
    assert one_line(err, "focas-net status: error:") == (
        "focas-net status: error: argument --host: '127.0.0.1:' is a host with nothing after "
        "its colon: give --host 127.0.0.1 and --port 1..65535; see focas-net status --help"
    )


def test_a_host_to_listen_on_typed_with_port_0_points_to_port_0() -> None:
    """A server listens on port 0 too (an ephemeral port): ``serve --host 127.0.0.1:0`` and
    ``FocasServer(host="127.0.0.1:0")`` are told to give it apart, not that it is none."""
    parser = build_parser()
    with pytest.raises(SystemExit):
        parser.parse_args(["serve", "--host", "127.0.0.1:0"])
    with pytest.raises(ValueError, match=r"^'127\.0\.0\.1:0' is a host and a port: give --host"):
        parse_host("127.0.0.1:0", lowest=0)
    with pytest.raises(ValueError, match=r"and the port 0 apart$"):
        FocasServer([default_machine()], host="127.0.0.1:0")
    with pytest.raises(ValueError, match=r"outside 0\.\.65535: give --host 127\.0\.0\.1 and"):
        parse_host("127.0.0.1:65536", lowest=0)


# -- seconds typed as docs/cli.md's "Numbers as typed" says ----------------------------------


@pytest.mark.parametrize(
    ("argv", "option", "seconds"),
    [
        ("status --timeout 0x2", "timeout", 2.0),
        ("status --timeout 0b11", "timeout", 3.0),
        ("alarms --follow --interval 0o2", "interval", 2.0),
        ("serve --grace-period 0x5", "grace_period", 5.0),
        ("serve --idle-timeout 0x0", "idle_timeout", 0.0),
    ],
)
def test_a_whole_number_of_seconds_in_hex_binary_or_octal_is_taken(
    argv: str, option: str, seconds: float
) -> None:
    """Every number a command takes is read by one rule, seconds too: ``--timeout 0x2`` was
    refused as `not a number`, though ``--port 0x2001`` and ``macro set 100 0x10`` took it."""
    args = build_parser().parse_args(argv.split())
    assert getattr(args, option) == seconds


@pytest.mark.parametrize("client", [FocasClient, NativeClient])
def test_a_host_with_spaces_around_it_says_so_to_a_client(client: type[FocasClient]) -> None:
    """It read as `not a host name ... (a name is letters, digits and hyphens ...)`."""
    with pytest.raises(ValueError, match=r"^host ' 127\.0\.0\.1 ' has spaces around it: give"):
        client(" 127.0.0.1 ", 8193)
