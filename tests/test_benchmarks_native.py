"""The native FOCAS/2 benchmark's own logic on a tiny scale: its worker ops against a served
machine, and its targets' arithmetic. Nothing here asserts a speed."""

from __future__ import annotations

import asyncio
import os
from collections.abc import Callable
from typing import Any, TypeVar

import pytest
from support import serving

from benchmarks import native
from benchmarks.report import Results, Row, pairwise_ratios
from benchmarks.worker import Worker

T = TypeVar("T")


def _results(rows: list[Row]) -> Results:
    return Results({"nproc": "2"}, "python -m benchmarks", {}, rows=rows)


def _vs_fwlib(scenario: str, subject: str, samples: list[float], fwlib: list[float]) -> Row:
    return Row(scenario, subject, "calls/s", samples, native.FWLIB, pairwise_ratios(samples, fwlib))


def test_checks_pass_and_fail_each_target() -> None:
    lib = [100.0, 100.0, 100.0]
    rows = [
        Row("native_pipe64", native.FWLIB, "calls/s", lib),
        _vs_fwlib("native_pipe64", native.NATIVE, [1100.0, 900.0, 1200.0], lib),  # 11 x
        _vs_fwlib("native_pipe64", native.PYFOCAS, [50.0, 50.0, 50.0], lib),
        Row("native_seq_macro", native.FWLIB, "calls/s", lib),
        _vs_fwlib("native_seq_macro", native.NATIVE, [60.0, 65.0, 90.0], lib),  # 0.65 x
        _vs_fwlib("native_seq_macro", native.PYFOCAS, [70.0, 70.0, 70.0], lib),  # ahead of us
        Row("native_poll100", native.NATIVE, "us/poll", [500.0, 600.0]),  # not pyfocas's call
        Row("native_poll100_status", native.NATIVE, "us/poll", [50.0, 60.0]),
        Row("native_poll100_status", native.PYFOCAS, "us/poll", [100.0, 90.0]),
    ]
    checks = native.checks(_results(rows))
    verdicts = {c.name: c.verdict for c in checks}
    assert all("floor" not in c.detail for c in checks)  # no floor measured, none named
    assert verdicts == {
        "native_pipe64 read_macro >= 10 x FANUC's library on one handle": "PASS",
        "native_seq read_macro >= 0.7 x FANUC's library": "FAIL",
        "native_seq read_status >= 0.7 x FANUC's library": "SKIP",
        "native_seq_macro: ahead of pyfocas": "FAIL",
        "native_seq_status: ahead of pyfocas": "SKIP",
        "native_pipe64: ahead of pyfocas": "PASS",
        "native_poll100_status: ahead of pyfocas": "PASS",  # less CPU per poll
    }


def test_checks_say_where_the_asyncio_floor_stood() -> None:
    lib = [100.0, 100.0]
    rows = [
        Row("native_pipe64", native.FWLIB, "calls/s", lib),
        _vs_fwlib("native_pipe64", native.NATIVE, [600.0, 700.0], lib),
        _vs_fwlib("native_pipe64", native.FLOOR, [800.0, 900.0], lib),
        Row("native_seq_status", native.FWLIB, "calls/s", lib),
        _vs_fwlib("native_seq_status", native.NATIVE, [60.0, 60.0], lib),
        _vs_fwlib("native_seq_status", native.FLOOR, [70.0, 80.0], lib),
        _vs_fwlib("native_seq_status", native.PYFOCAS, [80.0, 80.0], lib),
    ]
    details = {c.name: (c.verdict, c.detail) for c in native.checks(_results(rows))}
    assert details["native_pipe64 read_macro >= 10 x FANUC's library on one handle"] == (
        "FAIL",
        "median 6.50 x FANUC's library (the asyncio floor: 8.50 x)",
    )
    assert details["native_seq read_status >= 0.7 x FANUC's library"] == (
        "FAIL",
        "median 0.60 x FANUC's library (the asyncio floor: 0.75 x)",
    )
    assert details["native_seq_status: ahead of pyfocas"] == (
        "FAIL",
        "0.75 x pyfocas (the asyncio floor: 0.94 x)",
    )


def test_rows_take_their_ratio_to_the_library_pair_by_pair() -> None:
    rows = native._ratio_rows(
        "native_seq_macro",
        "calls/s",
        {native.NATIVE: [4.0, 9.0], native.FWLIB: [2.0, 3.0], native.PYFOCAS: [1.0, 6.0]},
        {native.NATIVE: "n"},
    )
    by_subject = {r.subject: r for r in rows}
    assert by_subject[native.FWLIB].ratios is None
    assert by_subject[native.NATIVE].ratios == [2.0, 3.0]
    assert by_subject[native.PYFOCAS].ratios == [0.5, 2.0]
    assert by_subject[native.NATIVE].note == "n"
    alone = native._ratio_rows("native_pipe64", "calls/s", {native.NATIVE: [1.0]}, {})
    assert alone[0].ratios is None and alone[0].ratio_to is None


@pytest.mark.parametrize("callers", [1, 4])
async def test_the_native_client_worker_ops(callers: int) -> None:
    w = Worker(native.NATIVE)
    async with serving() as served:
        host, port = served.host, served.port
        assert await w.handle({"op": "native_prepare", "host": host, "port": port}) == {}
        assert str(served.machine.read_macro(native.MACRO)) == native.MACRO_VALUE
        cmd = {"host": host, "port": port, "call": "read_macro", "callers": callers}
        result = await w.handle({"op": "native_run", "duration": 0.02, **cmd})
        assert result["ops"] >= callers and result["elapsed"] > 0
        assert 1 <= result["frames"] <= result["ops"]
        polls = [
            await w.handle(
                {
                    "op": "native_poll",
                    "targets": [[host, port]] * 3,
                    "call": call,
                    "interval": 0.01,
                    "duration": 0.03,
                }
            )
            for call in ("read_dynamic", "read_status")
        ]
    for poll in polls:
        assert poll["due"] == 9 and poll["errors"] == 0
        assert 0 < poll["polls"] <= poll["due"]


@pytest.mark.parametrize("call", ["read_macro", "read_status"])
async def test_the_asyncio_floor_worker_op(call: str) -> None:
    w = Worker(native.FLOOR)
    async with serving() as served:
        served.machine.write_macro(native.MACRO, 5)
        cmd = {"op": "native_run", "host": served.host, "port": served.port, "call": call}
        result = await w.handle({**cmd, "callers": 1, "duration": 0.02})
        assert result["ops"] >= 1 and result["elapsed"] > 0 and result["cpu"] >= 0
        if call == "read_macro":
            result = await w.handle({**cmd, "callers": 64, "duration": 0.02})
            assert result["ops"] >= 64 and result["elapsed"] > 0 and result["cpu"] >= 0
        else:  # cnc_statinfo is three blocks: the pipelined floor queues calls of one
            with pytest.raises(RuntimeError, match="cnc_statinfo is not one block"):
                await w.handle({**cmd, "callers": 64, "duration": 0.02})


class _Written:
    """A transport that keeps what is written."""

    def __init__(self) -> None:
        self.frames: list[bytes] = []

    def write(self, data: bytes) -> None:
        self.frames.append(data)


async def test_the_pipelined_floor_sends_ten_blocks_a_frame_one_frame_at_a_time() -> None:
    proto = native.PipeFloorProtocol()
    written = _Written()
    proto.connection_made(written)  # type: ignore[arg-type]
    proto.version = 1
    blocks = [bytes([0, 6, i, i, i, i]) for i in range(25)]
    futures = [proto.block(b) for b in blocks]
    await asyncio.sleep(0)  # the end of the loop turn: the first frame leaves
    answered: list[bytes] = []
    for expected in (10, 10, 5):
        assert len(written.frames) == 1, "one frame in flight"
        frame = written.frames.pop()
        assert int.from_bytes(frame[10:12]) == expected
        sent = frame[12:]
        assert len(sent) == 6 * expected
        # each block answered by one echoing it (6 bytes, its length word first)
        proto.data_received(
            bytes.fromhex("a0a0a0a0 0001 2102")
            + (2 + len(sent)).to_bytes(2)
            + expected.to_bytes(2)
            + sent
        )
        answered += [sent[i : i + 6] for i in range(0, len(sent), 6)]
    assert not written.frames and not proto.queue and proto.inflight is None
    assert [f.result() for f in futures] == blocks == answered


def test_the_asyncio_floor_runs_on_uvloop() -> None:
    # uvloop's transports are not subclasses of asyncio.Transport
    uvloop = pytest.importorskip("uvloop")

    async def main() -> float:
        async with serving() as served:
            served.machine.write_macro(native.MACRO, 5)
            result = await native.floor_run(served.host, served.port, "read_macro", 0.02)
            piped = await native.floor_pipe_run(served.host, served.port, "read_macro", 4, 0.02)
            return min(result["ops"], piped["ops"] / 4)

    assert uvloop.run(main()) >= 1


async def test_the_asyncio_floor_refuses_an_error_answer(monkeypatch: pytest.MonkeyPatch) -> None:
    # a variable number the machine has not is answered with EW_NUMBER: the floor must not
    # time calls that fail
    monkeypatch.setattr(native, "MACRO", 99_999_999)
    async with serving() as served:
        with pytest.raises(RuntimeError, match="cnc_rdmacro answered"):
            await native.floor_run(served.host, served.port, "read_macro", 0.02)


def test_the_floor_protocol_takes_frames_whole_or_in_pieces() -> None:
    loop = asyncio.new_event_loop()
    try:
        proto = native.FloorProtocol()
        first = bytes.fromhex("a0a0a0a0 0002 2102 0002") + b"xy"
        second = bytes.fromhex("a0a0a0a0 0002 2102 0000")
        answers = []
        for data in (first, first[:5], first[5:], second + first[:11], first[11:]):
            if proto.waiter is None:
                proto.waiter = loop.create_future()
                answers.append(proto.waiter)
            proto.data_received(data)
        # whole, in two pieces, then a frame and the start of the next in one read
        assert [a.result() for a in answers] == [first, first, second, first]
        assert proto.waiter is None and not proto.buffer
        waiter = proto.waiter = loop.create_future()
        proto.connection_lost(None)
        with pytest.raises(ConnectionError, match="connection lost"):
            waiter.result()
    finally:
        loop.close()


@pytest.mark.skipif(native.pyfocas_missing() is not None, reason="pyfocas is not installed")
@pytest.mark.parametrize("callers", [1, 3])
async def test_the_pyfocas_worker_ops(callers: int) -> None:
    async with serving() as served:
        served.machine.write_macro(native.MACRO, 5)
        host, port = served.host, served.port
        result = await _in_thread(
            native.blocking_run, native.PYFOCAS, host, port, "read_macro", callers, 0.02
        )
        assert result["ops"] >= callers
        poll = await _in_thread(
            native.blocking_poll, native.PYFOCAS, [[host, port]] * 2, "read_status", 0.01, 0.02
        )
    assert poll["due"] == 4 and poll["errors"] == 0


@pytest.mark.skipif(native.fwlib_missing() is not None, reason="set FOCAS_NET_FWLIB")
async def test_the_fwlib_worker_ops() -> None:
    async with serving() as served:
        served.machine.write_macro(native.MACRO, 5)
        host, port = served.host, served.port

        def both() -> tuple[dict[str, float], dict[str, float]]:
            run = native.blocking_run(native.FWLIB, host, port, "read_status", 64, 0.02)
            poll = native.blocking_poll(
                native.FWLIB, [[host, port]] * 2, "read_dynamic", 0.01, 0.02
            )
            status = native.blocking_poll(
                native.FWLIB, [[host, port]] * 2, "read_status", 0.01, 0.02
            )
            assert status["due"] == 4 and status["errors"] == 0
            return run, poll

        run, poll = await _in_thread(both)
    assert run["ops"] >= 1  # 64 callers on one handle: its one thread, in turn
    assert poll["due"] == 4 and poll["errors"] == 0


def test_missing_subjects_say_why(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.delenv("FOCAS_NET_FWLIB", raising=False)
    assert native.fwlib_missing() == "FOCAS_NET_FWLIB is not set (the path of FANUC's libfwlib32)"
    monkeypatch.setenv("FOCAS_NET_FWLIB", os.path.join("/nonexistent", "libfwlib32.so"))
    assert "no such file" in (native.fwlib_missing() or "")


async def _in_thread(fn: Callable[..., T], *args: Any) -> T:
    """A blocking subject's op off the loop (the served machine answers on the loop)."""
    return await asyncio.wait_for(asyncio.to_thread(fn, *args), 30)
