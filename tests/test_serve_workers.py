"""``focas-net serve --workers N``: a fleet served by N worker processes under one parent."""

from __future__ import annotations

import argparse
import asyncio
import hashlib
import os
import re
import signal
import socket
import struct
import sys
from contextlib import AbstractAsyncContextManager
from pathlib import Path

import pytest
from support import IO_TIMEOUT, SERVE_READY, killed_at_exit, serve_process, wait_until

from focas_net.cli import _fleet, _workers, serve
from focas_net.client import NativeClient

READY = SERVE_READY
START_TIMEOUT = 60.0
Proc = asyncio.subprocess.Process


def workers(
    *args: str, lines: int
) -> AbstractAsyncContextManager[tuple[Proc, list[re.Match[str]]]]:
    """``python -m focas_net serve --port 0 ARGS`` until its ``lines`` ready lines came."""
    return serve_process(*args, lines=lines, start_timeout=START_TIMEOUT)


def children(pid: int) -> list[int]:
    """The child processes of ``pid``, from /proc."""
    found: list[int] = []
    for task in Path(f"/proc/{pid}/task").iterdir():
        found += [int(c) for c in (task / "children").read_text().split()]
    return found


def alive(pid: int) -> bool:
    try:
        stat = Path(f"/proc/{pid}/stat").read_text()
    except OSError:
        return False
    return stat.rsplit(")", 1)[1].split()[0] != "Z"


def cnc_id(name: str) -> tuple[int, ...]:
    """The CNC ID the simulator derives from a machine's name (the first 16 bytes of its
    SHA-256, as four big-endian words)."""
    return struct.unpack(">4I", hashlib.sha256(name.encode()).digest()[:16])


async def stopped(proc: Proc) -> tuple[int, str]:
    assert proc.stderr is not None
    async with asyncio.timeout(START_TIMEOUT):
        code = await proc.wait()
        return code, (await proc.stderr.read()).decode()


def test_slices_are_contiguous_and_cover_the_fleet() -> None:
    assert _fleet.fleet_slices(6, 3) == [range(0, 2), range(2, 4), range(4, 6)]
    assert _fleet.fleet_slices(7, 3) == [range(0, 2), range(2, 4), range(4, 7)]
    assert _fleet.fleet_slices(1, 1) == [range(0, 1)]
    with pytest.raises(ValueError, match="4 workers for 3 machines"):
        _fleet.fleet_slices(3, 4)


def test_worker_options_shift_the_ports_of_its_slice() -> None:
    args = argparse.Namespace(port=9000, native_port=19000, workers=3, fleet=6)
    mine = _workers.worker_args(args, range(2, 4))
    assert (mine.port, mine.native_port, mine.workers, mine.fleet) == (9002, 19002, 1, 6)
    assert _fleet.fleet_indices(mine) == range(2, 4)
    assert _fleet.machines_per_process(mine) == 2
    assert _fleet.machines_per_process(args) == 2
    assert args.port == 9000  # the parent's options are left alone
    ephemeral = _workers.worker_args(argparse.Namespace(port=0, native_port=None), range(4, 6))
    assert (ephemeral.port, ephemeral.native_port) == (0, None)


def _options(*argv: str) -> argparse.Namespace:
    parser = argparse.ArgumentParser()
    serve.register(parser.add_subparsers())
    return parser.parse_args(["serve", *argv])


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (
            ("--fleet", "2", "--workers", "3"),
            "argument --workers: at most 64, and no more than the 2 machines of --fleet, got 3",
        ),
        (("--workers", "2"), "the fleet is 1 machine (without --fleet): give --fleet N"),
        (
            ("--fleet", "4", "--workers", "2", "--web", "0"),
            "argument --web: the dashboard shows the machines of one process, not of --workers 2",
        ),
    ],
)
def test_too_many_workers_is_refused_naming_it(argv: tuple[str, ...], message: str) -> None:
    with pytest.raises(_fleet.ConfigError, match=re.escape(message)):
        serve.check_options(_options(*argv))


async def test_six_machines_over_three_workers_each_port_its_machine() -> None:
    async with workers("--fleet", "6", "--workers", "3", lines=6) as (proc, ready):
        names = [m["name"] for m in ready]
        assert names == [f"focas-sim-0i-{i}" for i in range(1, 7)]
        assert len(children(proc.pid)) == 3
        for match in ready:
            async with NativeClient("127.0.0.1", int(match["port"]), timeout=IO_TIMEOUT) as c:
                assert await c.read_cnc_id() == cnc_id(match["name"])
        kids = children(proc.pid)
        proc.send_signal(signal.SIGTERM)
        code, err = await stopped(proc)
        assert (code, err) == (0, "")
        await wait_until(lambda: not any(alive(k) for k in kids), within=START_TIMEOUT)


def free_block(n: int) -> int:
    """The first of ``n`` consecutive ports that could all be bound just now."""
    for base in range(40_000, 60_000, 997):  # bounded: 20 tries
        socks: list[socket.socket] = []
        try:
            for port in range(base, base + n):
                s = socket.socket()
                socks.append(s)
                s.bind(("127.0.0.1", port))
            return base
        except OSError:
            continue
        finally:
            for s in socks:
                s.close()
    raise RuntimeError(f"no {n} consecutive free ports")


async def test_fixed_ports_follow_the_slices() -> None:
    first = free_block(4)
    argv = ("--fleet", "4", "--workers", "2", "--port", str(first))
    async with workers(*argv, lines=4) as (proc, ready):
        assert [int(m["port"]) for m in ready] == [first + i for i in range(4)]
        proc.send_signal(signal.SIGINT)
        assert (await stopped(proc))[0] == 0


async def test_native_lines_come_after_every_machine_line() -> None:
    argv = ("--fleet", "3", "--workers", "3", "--native-port", "0")
    async with workers(*argv, lines=6) as (proc, ready):
        modes = [m["modes"] for m in ready]
        assert modes == [None] * 3 + ["native FOCAS/2"] * 3
        assert [m["name"] for m in ready] == [f"focas-sim-0i-{i}" for i in (1, 2, 3)] * 2
        proc.send_signal(signal.SIGTERM)
        assert (await stopped(proc))[0] == 0


async def test_a_killed_worker_stops_the_parent_and_the_others() -> None:
    async with workers("--fleet", "6", "--workers", "3", lines=6) as (proc, _ready):
        kids = children(proc.pid)
        assert len(kids) == 3
        os.kill(kids[1], signal.SIGKILL)
        code, err = await stopped(proc)
        assert code == 1
        assert "was killed by SIGKILL while serving; stopping the other workers" in err
        await wait_until(lambda: not any(alive(k) for k in kids), within=START_TIMEOUT)


async def test_a_killed_parent_leaves_no_worker() -> None:
    async with workers("--fleet", "2", "--workers", "2", lines=2) as (proc, _ready):
        kids = children(proc.pid)
        proc.kill()
        await proc.wait()
        await wait_until(lambda: not any(alive(k) for k in kids), within=START_TIMEOUT)


async def test_a_bad_machine_file_is_reported_once_before_any_worker(tmp_path: Path) -> None:
    bad = tmp_path / "bad.toml"
    bad.write_text("this is not toml =\n")
    proc = await asyncio.create_subprocess_exec(
        sys.executable, "-m", "focas_net", "serve", "--port", "0", "--fleet", "2",
        "--workers", "2", "--machine", str(bad),
        stdout=asyncio.subprocess.PIPE, stderr=asyncio.subprocess.PIPE,
    )  # fmt: skip
    code, err = await stopped(proc)
    assert code == 2
    assert err.count(str(bad)) == 1
    assert "worker" not in err


async def test_a_worker_failing_at_start_stops_the_others_with_its_code() -> None:
    first = free_block(2)
    with socket.socket() as taken:  # the second worker's port is taken
        taken.bind(("127.0.0.1", first + 1))
        taken.listen()
        proc = await asyncio.create_subprocess_exec(
            sys.executable, "-m", "focas_net", "serve", "--host", "127.0.0.1",
            "--port", str(first), "--fleet", "2", "--workers", "2",
            stdout=asyncio.subprocess.PIPE, stderr=asyncio.subprocess.PIPE,
        )  # fmt: skip
        code, err = await stopped(proc)
    assert code == 1  # the worker's own: a port that cannot be bound
    assert f"cannot listen on 127.0.0.1:{first + 1}" in err
    assert "worker 2 (machine 2, pid " in err
    assert "exited with code 1 before it was ready; stopping the other workers" in err


async def test_sigint_to_the_whole_group_stops_every_worker_once() -> None:
    """A terminal's Ctrl-C: SIGINT to the parent's process group."""
    proc = await asyncio.create_subprocess_exec(
        sys.executable, "-m", "focas_net", "serve", "--host", "127.0.0.1", "--port", "0",
        "--fleet", "4", "--workers", "2",
        stdout=asyncio.subprocess.PIPE, stderr=asyncio.subprocess.PIPE,
        start_new_session=True,
    )  # fmt: skip
    assert proc.stdout is not None
    async with killed_at_exit(proc):
        async with asyncio.timeout(START_TIMEOUT):
            for _ in range(4):
                assert READY.match((await proc.stdout.readline()).decode().rstrip("\n"))
        kids = children(proc.pid)
        os.killpg(proc.pid, signal.SIGINT)
        assert await stopped(proc) == (0, "")
        await wait_until(lambda: not any(alive(k) for k in kids), within=START_TIMEOUT)
