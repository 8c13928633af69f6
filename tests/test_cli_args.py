"""What every ``focas-net`` command shares: the port type, exit codes, the command table."""

from __future__ import annotations

import argparse
import asyncio
import re
import socket

import pytest
from cli_support import run_focas_net
from support import serving

from focas_net.cli import (
    EXIT_CNC,
    EXIT_CONNECTION,
    EXIT_OK,
    EXIT_PROTOCOL,
    EXIT_USAGE,
    _args,
    _table,
    build_parser,
    main,
)
from focas_net.cli._run import Output

RUN_TIMEOUT = 30.0


async def _focas_net(*argv: str) -> tuple[int, str, str]:
    """``python -m focas_net ARGV`` to its exit: exit code, stdout, stderr."""
    return await run_focas_net(*argv, seconds=RUN_TIMEOUT)


def _closed_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        port: int = s.getsockname()[1]
    return port


# -- ports ----------------------------------------------------------------------------------


BAD_PORTS = [
    (("status", "--port", "70000"), "argument --port: port must be 1..65535, got '70000'"),
    (("status", "--port", "0"), "argument --port: port must be 1..65535, got '0'"),
    (("status", "--port", "0x10000"), "argument --port: port must be 1..65535, got '0x10000'"),
    (("status", "--port", "-1"), "argument --port: port must be 1..65535, got '-1'"),
    (("status", "--port", "http"), "argument --port: not a port number: 'http'"),
    (("pmc", "read", "R", "0", "--port", "8193x"), "not a port number: '8193x'"),
    (("serve", "--port", "70000"), "argument --port: port must be 0..65535, got '70000'"),
    (("serve", "--port", "-1"), "argument --port: port must be 0..65535, got '-1'"),
    (("serve", "--port", "http"), "argument --port: not a port number: 'http'"),
    (("serve", "--native-port", "65536"), "port must be 0..65535, got '65536'"),
]
#: Run as the user runs them; the others in-process (a process takes a second to start).
IN_A_PROCESS = [0, 4, 6, 9]


def _check_usage_error(argv: tuple[str, ...], message: str, code: int, out: str, err: str) -> None:
    """One line: the command, the error, where the help is (no usage block)."""
    assert (code, out) == (EXIT_USAGE, ""), (argv, err)
    command = " ".join(a for a in argv[:2] if a.isalpha())
    assert err.count("\n") == 1, (argv, err)
    assert err.startswith(f"focas-net {command}: error: "), (argv, err)
    assert err.endswith(f"{message}; see focas-net {command} --help\n"), (argv, err)


async def test_a_bad_port_is_a_usage_error_naming_what_was_typed() -> None:
    """One port type for the client commands and serve (the processes run side by side)."""
    cases = [BAD_PORTS[i] for i in IN_A_PROCESS]
    results = await asyncio.gather(*(_focas_net(*argv) for argv, _ in cases))
    for (argv, message), (code, out, err) in zip(cases, results, strict=True):
        _check_usage_error(argv, message, code, out, err)


@pytest.mark.parametrize(("argv", "message"), BAD_PORTS)
def test_a_bad_port_in_process(
    argv: tuple[str, ...], message: str, capsys: pytest.CaptureFixture[str]
) -> None:
    with pytest.raises(SystemExit) as info:
        main(list(argv))
    out, err = capsys.readouterr()
    assert isinstance(info.value.code, int)
    _check_usage_error(argv, message, info.value.code, out, err)


async def test_a_good_port_gets_past_the_arguments() -> None:
    """A client port that parses is connected to: refused is exit 3, not a usage error."""
    port = _closed_port()
    code, out, err = await _focas_net("status", "--port", hex(port), "--timeout", "5")
    assert (code, out) == (EXIT_CONNECTION, "")
    assert err.startswith("focas-net: ") and err.count("\n") == 1


@pytest.mark.parametrize(
    ("text", "port"), [("1", 1), ("8193", 8193), ("0x2001", 8193), (" 65535 ", 65535)]
)
def test_good_ports(text: str, port: int) -> None:
    assert build_parser().parse_args(["status", "--port", text]).port == port
    assert build_parser().parse_args(["serve", "--port", text]).port == port
    assert build_parser().parse_args(["serve", "--native-port", text]).native_port == port


def test_port_zero_is_for_listening_only() -> None:
    """0 asks the system for an ephemeral port: serve listens on it, a client cannot connect."""
    assert build_parser().parse_args(["serve", "--port", "0"]).port == 0
    assert build_parser().parse_args(["serve", "--native-port", "0"]).native_port == 0
    assert _args.parse_port("0", lowest=0) == 0
    with pytest.raises(ValueError, match=r"^port must be 1\.\.65535, got '0'$"):
        _args.parse_port("0")


def test_port_type_is_one_parser() -> None:
    for text, hint in (("abc", ""), ("", " (nothing typed)"), ("1.5", ""), ("80 80", "")):
        message = f"^{re.escape(f'not a port number: {text!r}{hint}')}$"
        with pytest.raises(ValueError, match=message):
            _args.parse_port(text)
        with pytest.raises(argparse.ArgumentTypeError, match=message):
            _args.PORT(text)
        with pytest.raises(argparse.ArgumentTypeError, match=message):
            _args.LISTEN_PORT(text)
    assert _args.PORT("0b11") == 3 and _args.LISTEN_PORT("0o17") == 15


# -- usage errors: one line each, naming what was typed --------------------------------------

USAGE_ERRORS = [
    (
        ("status", "--host", "bad host!"),
        "argument --host: not a host name: 'bad host!' (a name is letters, digits and "
        "hyphens, in parts between dots)",
    ),
    (
        ("status", "--host", "127.0.0.1:9400"),
        "argument --host: '127.0.0.1:9400' is a host and a port: give --host 127.0.0.1 --port 9400",
    ),
    (
        ("status", "--host", "[::1]:9400"),
        "argument --host: '[::1]:9400' is a host and a port: give --host ::1 --port 9400",
    ),
    (("versamax", "8", "0"), "argument RACK: must be 0..7, got 8"),
    (("versamax", "0", "10"), "argument SLOT: must be 0..9, got 10"),
    (
        ("sim", "fault", "delay", "--arg", "10", "--count", "100000"),
        "argument --count: a fault's count is 1..10000, got 100000",
    ),
    (("status", "--json", "extra"), "unrecognized arguments: extra"),
    (("sim", "alarm", "PS0100", "--bogus"), "unrecognized arguments: --bogus"),
    (("param",), "the following arguments are required: ACTION"),
    (
        ("serve", "--host", "bad host!"),
        "argument --host: not a host name: 'bad host!' (a name is letters, digits and hyphens, "
        "in parts between dots)",
    ),
    (
        ("param", "--port=9400", "get", "1420"),
        "--port is an option of the command: give it after the command "
        "(focas-net param get --port ...)",
    ),
]


async def test_a_usage_error_is_one_line_and_where_the_help_is() -> None:
    results = await asyncio.gather(*(_focas_net(*argv) for argv, _ in USAGE_ERRORS))
    for (argv, message), (code, out, err) in zip(USAGE_ERRORS, results, strict=True):
        _check_usage_error(argv, message, code, out, err)
    code, out, err = await _focas_net("--port", "9400", "status")
    assert (code, out) == (EXIT_USAGE, "")
    assert err == (
        "focas-net: error: --port is an option of the command: give it after the command "
        "(focas-net status --port ...); see focas-net --help\n"
    )
    code, out, err = await _focas_net()
    assert (code, out) == (EXIT_USAGE, "")
    assert err == (
        "focas-net: error: the following arguments are required: COMMAND; see focas-net --help\n"
    )


def test_a_command_takes_its_options_among_its_words() -> None:
    """A message after ``--axis`` is still the message (not an unknown argument)."""
    args = build_parser().parse_args(["sim", "alarm", "SV0411", "--axis", "2", "SERVO", "ALARM"])
    assert (args.alarm, args.message, args.axis) == ("SV0411", ["SERVO", "ALARM"], 2)
    args = build_parser().parse_args(["pmc", "write", "R", "--port", "9", "10", "1", "2"])
    assert (args.start, args.values, args.port) == (10, ["1", "2"], 9)


async def test_an_alarm_message_after_its_axis_is_raised() -> None:
    async with serving() as served:
        code, out, err = await _focas_net(
            "sim", "alarm", "SV0411", "--axis", "2", "SERVO", "ALARM", "--port", str(served.port)
        )
        assert (code, err) == (EXIT_OK, ""), err
        assert out == "raised SV0411 (axis 2) SERVO ALARM\n"
        assert [(a.axis_no, a.msg) for a in served.machine.active_alarms()] == [(2, "SERVO ALARM")]


# -- exit codes -----------------------------------------------------------------------------


def test_exit_codes() -> None:
    assert (EXIT_OK, EXIT_CNC, EXIT_USAGE, EXIT_CONNECTION, EXIT_PROTOCOL) == (0, 1, 2, 3, 4)
    assert [code for code, _ in _args.EXIT_CODES] == [0, 1, 2, 3, 4, 130]
    assert _table._EPILOG == (
        "exit status: 0 success, 1 CNC error (EW code), 2 usage error, "
        "3 connection error or timeout, 4 protocol violation, 130 interrupted (Ctrl-C)"
    )


def test_print_error(capsys: pytest.CaptureFixture[str]) -> None:
    _args.print_error("EW_BUSY (-1): busy, retry")
    _args.print_error("cannot listen on 127.0.0.1:1: denied", "focas-net serve: error")
    assert capsys.readouterr().err == (
        "focas-net: EW_BUSY (-1): busy, retry\n"
        "focas-net serve: error: cannot listen on 127.0.0.1:1: denied\n"
    )


# -- the command table ----------------------------------------------------------------------


def _leaves(rows: tuple[_table.Cmd | _table.Group, ...]) -> list[tuple[str, _table.Cmd]]:
    out: list[tuple[str, _table.Cmd]] = []
    for row in rows:
        if isinstance(row, _table.Group):
            out += [(f"{row.name} {cmd.name}", cmd) for cmd in row.commands]
        else:
            out.append((row.name, row))
    return out


def test_the_table_names_every_client_command_once() -> None:
    names = [name for name, _ in _leaves(_table.COMMANDS)]
    assert names == [
        "status", "sysinfo", "program", "position", "param get", "param set", "macro get",
        "macro set", "macro clear", "diag", "pmc read", "pmc write", "pmc bit", "alarms",
        "watch", "unlock", "versamax", "sim panel", "sim alarm", "sim clear", "sim cycle",
        "sim override", "sim fault", "sim faults",
    ]  # fmt: skip
    writes = [name for name, cmd in _leaves(_table.COMMANDS) if cmd.writes]
    assert writes == ["param set", "macro set", "pmc write", "pmc bit"]


def test_a_table_row_becomes_a_parser(capsys: pytest.CaptureFixture[str]) -> None:
    parser = _args.Parser(prog="focas-net")
    sub = parser.add_subparsers(dest="command")
    rows = (
        _table.Cmd(
            "echo",
            "say it again",
            lambda args: _never,
            (_table.arg("word", metavar="WORD", help="what to say"),),
            writes=True,
        ),
        _table.Group("two", "a group", (_table.Cmd("one", "the only one", lambda a: _never),)),
    )
    _table.register(sub, rows)
    args = parser.parse_args(["echo", "hi", "--port", "0x10", "--password", "pw"])
    assert (args.word, args.port, args.password, args.host, args.timeout) == (
        "hi",
        16,
        "pw",
        "127.0.0.1",
        3.0,
    )
    assert callable(args.func)
    args = parser.parse_args(["two", "one", "--json"])
    assert args.two_command == "one" and args.json and not hasattr(args, "password")
    with pytest.raises(SystemExit):
        parser.parse_args(["echo", "--help"])
    text = capsys.readouterr().out
    assert "Say it again." in text and "connection:" in text and "--password TEXT" in text
    assert text.rstrip().endswith("130 interrupted (Ctrl-C)")


async def _never(cnc: object) -> Output:  # pragma: no cover - never connected
    raise AssertionError("not connected")


@pytest.mark.parametrize("value", ["-0x10", "-0b101", "-1e3", "-inf", "-.5", "-7"])
def test_a_negative_value_is_a_value_not_an_option(value: str) -> None:
    args = build_parser().parse_args(["param", "set", "1320", value, "--axis", "1"])
    assert args.value == value  # read by the parameter's type when the command runs
