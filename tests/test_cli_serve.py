"""``focas-net serve`` as a subprocess: ready lines, SIGTERM, bad files, options."""

from __future__ import annotations

import argparse
import asyncio
import gc
import re
import signal
import sys
from contextlib import AbstractAsyncContextManager
from pathlib import Path
from typing import Any

import pytest
from cli_support import run_focas_net
from support import SERVE_READY, Wire, serve_process

from focas_net.cli import _fleet, serve
from focas_net.errors import EW
from focas_net.protocol import COMMANDS, Command, InjectFault, MacroRequest, MacroValue, SetPanel
from focas_net.sim import default_machine

READY = SERVE_READY
STATUS = (Command.RDCNCSTAT, b"")
START_TIMEOUT = 30.0


def running(
    *args: str,
) -> AbstractAsyncContextManager[tuple[asyncio.subprocess.Process, list[re.Match[str]]]]:
    """``python -m focas_net serve --port 0 ARGS``, until its ready lines are printed."""
    fleet = int(args[args.index("--fleet") + 1]) if "--fleet" in args else 1
    return serve_process(*args, lines=fleet, start_timeout=START_TIMEOUT)


async def stop(proc: asyncio.subprocess.Process) -> int:
    proc.send_signal(signal.SIGTERM)
    async with asyncio.timeout(START_TIMEOUT):
        return await proc.wait()


async def test_serve_ready_line_and_sigterm() -> None:
    async with running() as (proc, ready):
        (match,) = ready
        assert match["name"] == "focas-sim-0i"
        assert match["host"] == "127.0.0.1"
        async with await Wire.open("127.0.0.1", int(match["port"])) as w:
            assert await w.ew(*STATUS) == 0
        assert await stop(proc) == 0


async def test_serve_sigterm_answers_delayed_request_in_flight() -> None:
    async with running("--grace-period", "10") as (proc, ready):
        w = await Wire.open("127.0.0.1", int(ready[0]["port"]))
        async with w:
            fault = InjectFault(1, 0, 1, 500).encode()
            assert await w.ew(Command.SIM_INJECT_FAULT, fault) == 0
            rid = w.send(*STATUS)
            await w.writer.drain()
            proc.send_signal(signal.SIGTERM)
            frame = await w.recv(within=START_TIMEOUT)
            assert (frame.command, frame.request_id) == (Command.RDCNCSTAT, rid)
            assert await w.closed_by_peer()
        async with asyncio.timeout(START_TIMEOUT):
            assert await proc.wait() == 0


async def test_serve_sigint_exits_zero() -> None:
    async with running() as (proc, _ready):
        proc.send_signal(signal.SIGINT)
        async with asyncio.timeout(START_TIMEOUT):
            assert await proc.wait() == 0


async def test_serve_fleet_no_control_read_only() -> None:
    async with running("--fleet", "3", "--no-control") as (proc, ready):
        assert [m["name"] for m in ready] == [f"focas-sim-0i-{i}" for i in (1, 2, 3)]
        assert [m["modes"] for m in ready] == [None, None, None]
        assert len({m["port"] for m in ready}) == 3
        async with await Wire.open("127.0.0.1", int(ready[1]["port"])) as w:
            assert await w.ew(Command.SIM_SET_PANEL, SetPanel(0, 1, 0).encode()) == EW.FUNC
            assert await w.ew(Command.WRMACRO, MacroValue(100, 8, 1, 0).encode()) == 0
        assert await stop(proc) == 0
    async with running("--read-only") as (proc, ready):
        assert ready[0]["modes"] == "read-only"
        async with await Wire.open("127.0.0.1", int(ready[0]["port"])) as w:
            assert await w.ew(Command.WRMACRO, MacroValue(100, 8, 1, 0).encode()) == EW.PROT
            assert (await w.request(Command.RDMACRO, MacroRequest(100))).vacant
        assert await stop(proc) == 0


async def test_serve_param_password() -> None:
    async with running("--param-password", "SECR") as (proc, ready):
        async with await Wire.open("127.0.0.1", int(ready[0]["port"])) as w:
            assert await w.ew(Command.WRUNLOCKPARAM, b"NOPE") == EW.PASSWD
            assert await w.ew(Command.WRUNLOCKPARAM, b"SECR") == 0
        assert await stop(proc) == 0
        assert proc.stderr is not None
        assert b"SECR" not in await proc.stderr.read()


EXAMPLE = Path(__file__).resolve().parent.parent / "examples" / "machine.toml"


@pytest.mark.skipif(not EXAMPLE.exists(), reason="examples/machine.toml not present")
async def test_serve_machine_file() -> None:
    async with running("--machine", str(EXAMPLE)) as (proc, ready):
        async with await Wire.open("127.0.0.1", int(ready[0]["port"])) as w:
            assert await w.ew(*STATUS) == 0
        assert await stop(proc) == 0


async def _run_to_exit(*args: str) -> tuple[int, str, str]:
    return await run_focas_net("serve", "--port", "0", *args, seconds=START_TIMEOUT)


async def test_bad_machine_file_is_one_line_exit_2(tmp_path: Path) -> None:
    bad = tmp_path / "bad.toml"
    bad.write_text("[machine]\nname = 5\n")
    code, out, err = await _run_to_exit("--machine", str(bad))
    assert code == 2
    assert out == ""
    lines = err.strip().splitlines()
    assert len(lines) == 1
    assert str(bad) in lines[0] and "name" in lines[0]


async def test_missing_machine_file_exit_2(tmp_path: Path) -> None:
    missing = tmp_path / "nope.toml"
    code, _out, err = await _run_to_exit("--machine", str(missing))
    assert code == 2
    assert len(err.strip().splitlines()) == 1 and str(missing) in err


async def test_bad_tls_files_exit_2(tmp_path: Path) -> None:
    code, _out, err = await _run_to_exit("--tls-key", str(tmp_path / "k.pem"))
    assert code == 2 and "--tls-cert" in err
    code, _out, err = await _run_to_exit("--tls-cert", str(tmp_path / "c.pem"))
    assert code == 2 and f"--tls-cert {tmp_path / 'c.pem'}: no such file or directory" in err


async def test_tls_files_that_cannot_serve_say_which_and_why(
    certificate: tuple[Path, Path],
) -> None:
    """Not OpenSSL's ``[SSL] PEM lib (_ssl.c:3926)``: the option, the file and what it lacks."""
    cert, key = certificate
    cases = [
        (("--tls-cert", str(cert)), f"--tls-cert {cert} holds no private key: give --tls-key FILE"),
        (("--tls-cert", str(key), "--tls-key", str(key)), f"--tls-cert {key}: no PEM certificate"),
        (
            ("--tls-cert", str(cert), "--tls-key", str(cert)),
            f"--tls-key {cert}: no PEM private key",
        ),
    ]
    results = await asyncio.gather(*(_run_to_exit(*argv) for argv, _ in cases))
    for (argv, reason), (code, out, err) in zip(cases, results, strict=True):
        assert (code, out) == (2, ""), (argv, err)
        assert err.startswith(f"focas-net serve: error: {reason}") and err.count("\n") == 1, err
        assert "_ssl.c" not in err and "PEM lib" not in err


async def test_port_in_use_exit_1() -> None:
    blocker = await asyncio.start_server(lambda r, w: None, "127.0.0.1", 0)
    try:
        port = blocker.sockets[0].getsockname()[1]
        proc = await asyncio.create_subprocess_exec(
            sys.executable, "-m", "focas_net", "serve", "--port", str(port),
            stdout=asyncio.subprocess.PIPE, stderr=asyncio.subprocess.PIPE,
        )  # fmt: skip
        async with asyncio.timeout(START_TIMEOUT):
            _out, err = await proc.communicate()
        assert proc.returncode == 1
        assert "cannot listen" in err.decode()
    finally:
        blocker.close()
        await blocker.wait_closed()


def _parse(*argv: str) -> argparse.Namespace:
    parser = argparse.ArgumentParser()
    serve.register(parser.add_subparsers())
    return parser.parse_args(["serve", *argv])


def test_defaults() -> None:
    args = _parse()
    assert (args.host, args.port, args.fleet) == ("127.0.0.1", 8193, 1)
    assert (args.max_connections, args.idle_timeout, args.max_frame) == (256, 300.0, 65_536)
    assert not args.no_control and not args.read_only
    assert args.func is serve.run


@pytest.mark.parametrize(
    "argv",
    [
        ("--port", "70000"),
        ("--port", "x"),
        ("--fleet", "0"),
        ("--max-connections", "0"),
        ("--idle-timeout", "-1"),
        ("--idle-timeout", "nan"),
        ("--max-frame", "3"),
        ("--max-frame", "0xA0A0A0A0"),
        ("--max-frame", "4294967296"),
        ("--log-level", "LOUD"),
        ("--param-password", "\u20acuro"),
        ("--param-password", ""),
        ("--param-password", "12345"),
    ],
)
def test_bad_options(argv: tuple[str, ...], capsys: pytest.CaptureFixture[str]) -> None:
    with pytest.raises(SystemExit) as exc:
        _parse(*argv)
    assert exc.value.code == 2
    capsys.readouterr()


def test_build_machines_fleet_names_and_flags() -> None:
    machines = _fleet.build_machines(_parse("--fleet", "3", "--no-control", "--read-only"))
    assert [m.name for m in machines] == ["focas-sim-0i-1", "focas-sim-0i-2", "focas-sim-0i-3"]
    assert len({id(m) for m in machines}) == 3
    assert all(not m.control_enabled and m.read_only for m in machines)
    (single,) = _fleet.build_machines(_parse())
    assert single.name == "focas-sim-0i" and single.control_enabled and not single.read_only


NATIVE_READY = re.compile(
    r"^focas-net: (?P<name>\S+) \(native FOCAS/2\) listening on (?P<host>[\d.]+):(?P<port>\d+)$"
)


async def test_serve_native_port_speaks_both_front_ends() -> None:
    from pyfocas.protocol.protocol import FOCAS

    async with running("--native-port", "0") as (proc, ready):
        assert proc.stdout is not None
        async with asyncio.timeout(START_TIMEOUT):
            line = (await proc.stdout.readline()).decode().rstrip("\n")
        native = NATIVE_READY.match(line)
        assert native is not None, f"unexpected output: {line!r}"
        assert native["name"] == ready[0]["name"]
        packed_port, native_port = int(ready[0]["port"]), int(native["port"])
        assert packed_port != native_port

        def native_macro() -> Any:
            client = FOCAS("127.0.0.1", native_port)
            client.connect()
            try:
                client.write_macro_double(510, 42.5)
                return client.read_macro(510)
            finally:
                client.socket.close()

        assert await asyncio.to_thread(native_macro) == {510: 42.5}
        async with await Wire.open("127.0.0.1", packed_port) as w:
            answer = await w.call(Command.RDMACRO, MacroRequest(510).encode())
        assert COMMANDS[Command.RDMACRO].response.decode(answer) == MacroValue(510, 8, 425, 1)
        assert await stop(proc) == 0


async def test_serve_port_answers_pyfocas_and_the_packed_protocol_alike() -> None:
    from pyfocas.protocol.protocol import FOCAS

    async with running() as (proc, ready):
        port = int(ready[0]["port"])

        def native_macro() -> Any:
            client = FOCAS("127.0.0.1", port)
            client.connect()
            try:
                client.write_macro_double(511, -3.5)
                return client.read_macro(511)
            finally:
                client.socket.close()

        async with asyncio.timeout(START_TIMEOUT):
            assert await asyncio.to_thread(native_macro) == {511: -3.5}
        async with await Wire.open("127.0.0.1", port) as w:
            answer = await w.call(Command.RDMACRO, MacroRequest(511).encode())
        assert COMMANDS[Command.RDMACRO].response.decode(answer) == MacroValue(511, 8, -35, 1)
        assert await stop(proc) == 0


def test_serving_freezes_what_was_built_and_still_collects_new_garbage() -> None:
    built = [default_machine() for _ in range(3)]
    try:
        serve._freeze_what_was_built()
        assert gc.get_freeze_count() > 0
        frozen = gc.get_freeze_count()

        class Node:
            other: Any = None

        a, b = Node(), Node()
        a.other, b.other = b, a  # a cycle made after the freeze
        del a, b
        assert gc.collect() >= 2  # still collected
        assert gc.get_freeze_count() == frozen  # and the built machines stay out of reach
        assert all(m.status() is not None for m in built)
    finally:
        gc.unfreeze()
