"""``focas-net watch``: the frame as a pure function of a state, and the command against a
real server whose machine runs a program on a clock that moves with every read."""

from __future__ import annotations

import asyncio
import json
import os
import pty
import signal
import sys
from collections.abc import AsyncIterator
from decimal import Decimal
from pathlib import Path
from typing import Any

import pytest
from cli_support import SUBPROCESS_TIMEOUT, Cli
from support import IO_TIMEOUT, serving

from focas_net.cli import main
from focas_net.cli._args import EXIT_CONNECTION, EXIT_OK, EXIT_USAGE
from focas_net.cli.watch_cmds import (
    CLEAR_TO_END,
    CURSOR_HOME,
    HIDE_CURSOR,
    SHOW_CURSOR,
    Frame,
    WatchState,
    duration_text,
    frame_dict,
    poll,
    render_frame,
    screen_text,
)
from focas_net.client import FocasClient, Positions
from focas_net.protocol import (
    ActiveAlarm,
    LoadMeters,
    PositionKind,
    ProgramNumbers,
    RunInfo,
    StatusInfo,
)
from focas_net.server import FocasServer
from focas_net.sim import Machine, default_machine, load_machine

# -- the frame, without a server ------------------------------------------------------------


def _positions(kind: PositionKind, x: str, z: str) -> Positions:
    values = {"X": Decimal(x), "Z": Decimal(z)}
    return Positions(kind, 3, values, {n: int(v * 1000) for n, v in values.items()})


STATE = WatchState(
    status=StatusInfo(
        hdck=0, tmmode=0, aut=1, run=3, motion=1, mstb=0, emergency=0, alarm=1, edit=0
    ),
    numbers=ProgramNumbers(running=300, main=300),
    program_name="FACE",
    sequence=20,
    positions=(
        _positions(PositionKind.ABSOLUTE, "12.500", "-1.000"),
        _positions(PositionKind.MACHINE, "112.500", "-101.000"),
        _positions(PositionKind.RELATIVE, "2.500", "0.000"),
        _positions(PositionKind.DISTANCE, "7.500", "0.000"),
    ),
    feed=1200,
    spindle=800,
    run_info=RunInfo(
        feed=50,
        rapid=25,
        spindle=110,
        parts_count=3,
        parts_total=120,
        power_on_ms=3_723_400,
        operating_ms=61_050,
        cutting_ms=3_000,
        cycle_ms=12_599,
    ),
    parts_required=10,
    alarms=(ActiveAlarm(axis_no=1, alm_type=4, alm_no=500, msg="OVER TRAVEL ( +1 )"),),
)


def test_a_frame_shows_every_figure() -> None:
    assert render_frame(Frame(7, "127.0.0.1:8193", STATE)) == [
        "127.0.0.1:8193  frame 7",
        "run STRT  mode MEM  motion MTN  mstb ***  emergency ****  alarm ALM",
        "program O0300 (FACE)  main O0300  sequence N20",
        "axis  absolute   machine  relative  distance",
        "X       12.500   112.500     2.500     7.500",
        "Z       -1.000  -101.000     0.000     0.000",
        "feed 1200 mm/min  spindle 800 min^-1",
        "override feed 50 %  rapid 25 %  spindle 110 %",
        "parts 3  total 120  required 10",
        "time cycle 0:00:12.5  cutting 0:00:03.0  operating 0:01:01.0  power on 1:02:03.4",
        "alarms 1",
        "  OT0500 (axis 1) OVER TRAVEL ( +1 )",
    ]


def test_a_field_the_cnc_refused_is_a_dash_and_loads_show_when_read() -> None:
    state = WatchState(
        numbers=ProgramNumbers(running=0, main=0),
        positions=(_positions(PositionKind.ABSOLUTE, "1.000", "2.000"), None, None, None),
        loads=LoadMeters(spindle=(42,), servo=(7, 0, 3)),
        alarms=(),
    )
    assert render_frame(Frame(1, "[::1]:8193", state)) == [
        "[::1]:8193  frame 1",
        "run -",
        "program none  main none  sequence -",
        "axis  absolute  machine  relative  distance",
        "X        1.000        -         -         -",
        "Z        2.000        -         -         -",
        "feed - mm/min  spindle - min^-1",
        "override -",
        "parts -  required -",
        "time -",
        "load spindle 42 %  servo X 7 %  Z 0 %  3 3 %",
        "alarms none",
    ]
    assert frame_dict(Frame(1, "[::1]:8193", state))["state"]["loads"] == {
        "spindle": [42],
        "servo": [7, 0, 3],
    }
    assert frame_dict(Frame(1, "h:1", STATE))["state"]["loads"] is None  # not read


def test_a_lost_connection_keeps_the_last_state_under_its_line() -> None:
    lines = render_frame(Frame(4, "h:1", STATE, "connection to h:1 lost: refused; reconnecting"))
    assert lines[:3] == [
        "h:1  frame 4",
        "! connection to h:1 lost: refused; reconnecting",
        "run STRT  mode MEM  motion MTN  mstb ***  emergency ****  alarm ALM",
    ]
    assert render_frame(Frame(1, "h:1", None, "lost")) == [
        "h:1  frame 1",
        "! lost",
        "no state read yet",
    ]
    assert frame_dict(Frame(1, "h:1", None, "lost")) == {
        "frame": 1,
        "address": "h:1",
        "problem": "lost",
        "state": None,
    }


def test_frame_json_carries_the_figures() -> None:
    data = frame_dict(Frame(2, "h:1", STATE))
    state = data["state"]
    assert state["status"]["run"] == {
        "value": 3,
        "name": "STRT",
        "meaning": "cycle start (running)",
    }
    assert state["positions"]["machine"] == {"X": "112.500", "Z": "-101.000"}
    assert state["parts"] == {"count": 3, "total": 120, "required": 10}
    assert state["times_ms"]["cycle"] == 12_599
    assert state["overrides"] == {"feed": 50, "rapid": 25, "spindle": 110}
    assert (state["program_running"], state["program_name"], state["sequence"]) == (300, "FACE", 20)
    assert [a["code"] for a in state["alarms"]] == ["OT0500"]
    json.dumps(data)  # JSON-ready throughout


def test_screen_text_refreshes_in_place_only_on_a_terminal() -> None:
    assert screen_text(["a", "b"], tty=False, first=True) == "a\nb\n"
    assert screen_text(["a", "b"], tty=False, first=False) == "\na\nb\n"
    drawn = screen_text(["a", "b"], tty=True, first=False)
    assert drawn.startswith(CURSOR_HOME) and drawn.endswith(CLEAR_TO_END)
    assert drawn == f"{CURSOR_HOME}a\x1b[K\nb\x1b[K\n{CLEAR_TO_END}"


@pytest.mark.parametrize(
    ("ms", "text"),
    [
        (0, "0:00:00.0"),
        (99, "0:00:00.0"),
        (100, "0:00:00.1"),
        (59_999, "0:00:59.9"),
        (3_600_000, "1:00:00.0"),
        (360_000_000, "100:00:00.0"),
        (None, "-"),
    ],
)
def test_duration_text(ms: int | None, text: str) -> None:
    assert duration_text(ms) == text


# -- against a server -----------------------------------------------------------------------

PROGRAM = "O0500 (WATCH)\nN10 G90 G21 G1 X600. F1200 S900 M3\nN20 M30\n"


class SteppingClock:
    """Machine time that moves by ``step`` seconds at every read of it: each frame of the
    watch sees a later machine time, and no figure depends on wall time."""

    def __init__(self, step: float) -> None:
        self.step = step
        self._now = 0.0

    def now(self) -> float:
        self._now += self.step
        return self._now

    def advance(self, seconds: float) -> None:
        self._now += seconds


def running_machine() -> Machine:
    """A machine 1 s into ``PROGRAM``: past the spindle start (M3), X on its way to 600."""
    clock = SteppingClock(0.01)
    machine = default_machine(sim_clock=clock)
    machine.store_program(PROGRAM)
    machine.select_program(500)
    machine.cycle_start()
    clock.advance(1.0)
    return machine


@pytest.fixture
async def cli(capsys: pytest.CaptureFixture[str]) -> AsyncIterator[Cli]:
    async with serving(running_machine()) as served:
        yield Cli(served, capsys)


async def test_watch_json_frames_show_a_running_program_move(cli: Cli) -> None:
    code, out, err = await cli.run("watch", "--count", "3", "--interval", "0.05", "--json")
    assert (code, err) == (EXIT_OK, "")
    frames = [json.loads(line) for line in out.splitlines()]
    assert [f["frame"] for f in frames] == [1, 2, 3]
    states = [f["state"] for f in frames]
    assert all(f["problem"] is None for f in frames)
    assert {s["status"]["run"]["name"] for s in states} == {"STRT"}
    assert {(s["program_running"], s["program_name"], s["sequence"]) for s in states} == {
        (500, "WATCH", 10)
    }
    assert {(s["feed"], s["spindle_speed"]) for s in states} == {(1200, 900)}
    xs = [Decimal(s["positions"]["absolute"]["X"]) for s in states]
    assert 0 < xs[0] < xs[1] < xs[2] < 600
    to_go = [Decimal(s["positions"]["distance"]["X"]) for s in states]
    assert to_go[0] > to_go[1] > to_go[2] > 0
    cutting = [s["times_ms"]["cutting"] for s in states]
    assert 0 < cutting[0] < cutting[1] < cutting[2]


async def test_watch_text_frames_are_separated_by_a_blank_line(cli: Cli) -> None:
    out = await cli.ok("watch", "--count", "2", "--interval", "0.05")
    assert "\x1b" not in out  # not a terminal: no control sequences
    first, second = out.rstrip("\n").split("\n\n")
    assert first.splitlines()[0] == f"{cli.served.host}:{cli.served.port}  frame 1"
    assert second.splitlines()[0] == f"{cli.served.host}:{cli.served.port}  frame 2"
    assert "program O0500 (WATCH)  main O0500  sequence N10" in first.splitlines()
    assert first.splitlines()[1].startswith("run STRT  mode MEM  motion MTN")
    assert first != second  # the axis moved between the frames


@pytest.mark.parametrize(
    ("argv", "reason"),
    [
        (("--interval", "0"), "argument --interval: must be 0.05..3600 seconds, got 0"),
        (("--interval", "0.01"), "argument --interval: must be 0.05..3600 seconds, got 0.01"),
        (("--interval", "soon"), "argument --interval: not a number: 'soon'"),
        (("--count", "0"), "argument --count: must be at least 1, got 0"),
    ],
)
def test_a_bad_interval_or_count_is_a_usage_error_naming_it(
    argv: tuple[str, ...], reason: str, capsys: pytest.CaptureFixture[str]
) -> None:
    with pytest.raises(SystemExit) as info:
        main(["watch", *argv])
    out, err = capsys.readouterr()
    assert (info.value.code, out) == (EXIT_USAGE, "")
    assert err == f"focas-net watch: error: {reason}; see focas-net watch --help\n"


async def test_an_unreachable_machine_is_one_line() -> None:
    async with serving() as gone:
        host, port = gone.host, gone.port
    code = await asyncio.to_thread(
        main, ["watch", "--host", host, "--port", str(port), "--count", "1"]
    )
    assert code == EXIT_CONNECTION


async def test_poll_reads_the_loads_and_names_the_program() -> None:
    async with serving(running_machine()) as served:
        async with FocasClient(served.host, served.port, timeout=IO_TIMEOUT) as cnc:
            names: dict[int, str] = {}
            first = await poll(cnc, names, directory=True)
            again = await poll(cnc, {}, directory=False)
    assert names == {1: "DEMO CONTOUR", 500: "WATCH"}
    assert first.program_name == "WATCH"
    assert again.program_name is None  # no directory read, no cached name
    loads = first.loads
    assert loads is not None
    assert (len(loads.spindle), len(loads.servo)) == (1, 3)
    assert loads.spindle[0] > 0  # the spindle turns (M3) while X cuts
    servo = "  ".join(f"{axis} {v} %" for axis, v in zip("XYZ", loads.servo, strict=True))
    assert f"load spindle {loads.spindle[0]} %  servo {servo}" in render_frame(
        Frame(1, "h:1", first)
    )


# -- as a process: a lost connection, then Ctrl-C --------------------------------------------


async def _frames(proc: asyncio.subprocess.Process) -> AsyncIterator[dict[str, Any]]:
    assert proc.stdout is not None
    while True:
        line = await asyncio.wait_for(proc.stdout.readline(), SUBPROCESS_TIMEOUT)
        if not line:
            return
        yield json.loads(line)


async def test_watch_survives_a_lost_connection_and_ends_on_ctrl_c() -> None:
    machine = running_machine()
    server = FocasServer(machine, host="127.0.0.1", port=0, grace_period=1.0)
    await server.start()
    host, port = server.listeners[0].address
    proc = await asyncio.create_subprocess_exec(
        sys.executable,
        "-m",
        "focas_net",
        "watch",
        "--host",
        host,
        "--port",
        str(port),
        "--interval",
        "0.05",
        "--timeout",
        "0.5",
        "--json",
        stdout=asyncio.subprocess.PIPE,
        stderr=asyncio.subprocess.PIPE,
    )
    restarted: FocasServer | None = None
    seen: list[str] = []
    try:
        frames = _frames(proc)
        async for frame in frames:  # bounded: each line within SUBPROCESS_TIMEOUT
            if frame["problem"] is None and not seen:
                seen.append("up")
                await server.aclose()
            elif frame["problem"] is not None and seen == ["up"]:
                assert "lost" in frame["problem"] and "reconnecting" in frame["problem"]
                assert frame["state"]["program_name"] == "WATCH"  # the last state read
                seen.append("lost")
                restarted = FocasServer(machine, host=host, port=port, grace_period=1.0)
                await restarted.start()
            elif frame["problem"] is None and seen == ["up", "lost"]:
                seen.append("back")
                break
        assert seen == ["up", "lost", "back"]
        proc.send_signal(signal.SIGINT)
        async with asyncio.timeout(SUBPROCESS_TIMEOUT):
            _rest, err = await proc.communicate()
        assert proc.returncode == EXIT_OK
        assert b"Traceback" not in err and b"KeyboardInterrupt" not in err
    finally:
        if proc.returncode is None:
            proc.kill()
            await proc.wait()
        await server.aclose()
        if restarted is not None:
            await restarted.aclose()


def _read_all(fd: int) -> bytes:
    """Everything written to a pseudo-terminal until its last writer closed it."""
    chunks = []
    while True:
        try:
            chunk = os.read(fd, 65536)
        except OSError:  # EIO: the other side is closed
            break
        if not chunk:
            break
        chunks.append(chunk)
    return b"".join(chunks)


async def test_on_a_terminal_frames_are_drawn_in_place_and_the_cursor_comes_back() -> None:
    async with serving(running_machine()) as served:
        main_fd, child_fd = pty.openpty()
        try:
            proc = await asyncio.create_subprocess_exec(
                sys.executable,
                "-m",
                "focas_net",
                "watch",
                "--host",
                served.host,
                "--port",
                str(served.port),
                "--interval",
                "0.05",
                "--count",
                "2",
                stdout=child_fd,
                stderr=asyncio.subprocess.PIPE,
            )
            os.close(child_fd)
            child_fd = -1
            reading = asyncio.create_task(asyncio.to_thread(_read_all, main_fd))
            async with asyncio.timeout(SUBPROCESS_TIMEOUT):
                _, err = await proc.communicate()
                shown = (await reading).decode()
        finally:
            if child_fd >= 0:
                os.close(child_fd)
            os.close(main_fd)
    assert (proc.returncode, err) == (EXIT_OK, b"")
    assert shown.startswith(HIDE_CURSOR + CURSOR_HOME)
    assert shown.endswith(CLEAR_TO_END + SHOW_CURSOR)
    assert shown.count(CURSOR_HOME) == 2  # two frames, each drawn from the top
    assert "frame 2" in shown.split(CURSOR_HOME)[2]


async def test_a_read_the_cnc_refuses_leaves_only_its_field_out(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    path = tmp_path / "bare.toml"
    path.write_text('[machine]\nname = "bare"\naxes = ["X", "Z"]\n')  # no parameter 6713
    async with serving(load_machine(path)) as served:
        cli = Cli(served, capsys)
        frame = json.loads(await cli.ok("watch", "--count", "1", "--json"))
        text = await cli.ok("watch", "--count", "1")
    state = frame["state"]
    assert frame["problem"] is None
    assert state["parts"]["required"] is None
    assert state["status"]["run"]["name"] == "****"
    assert set(state["positions"]["absolute"]) == {"X", "Z"}
    assert "parts 0  total 0  required -" in text.splitlines()
