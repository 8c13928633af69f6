"""The benchmark suite's own logic, on a tiny scale: the floor's frame handling, the worker's
helpers, the ratio / target / table arithmetic, and one real server + client process pair.

Nothing here asserts a speed; the figures themselves come from ``python -m benchmarks``.
"""

from __future__ import annotations

import asyncio
import json
import math
import os
import struct
import subprocess
import sys
from collections.abc import AsyncIterator
from pathlib import Path
from subprocess import PIPE
from typing import Any

import pytest
from peers import WriteLog
from support import IO_TIMEOUT

from benchmarks import plant, run, worker
from benchmarks.floor import (
    HEADER,
    STATUS,
    STATUS_PAYLOAD,
    VARIANTS,
    WRITE_CHUNK,
    FloorClient,
    Variant,
    serve,
)
from benchmarks.report import (
    FLOOR,
    FOCAS,
    PEER,
    Check,
    Results,
    Row,
    Summary,
    evaluate,
    pairwise_ratios,
    render_checks,
    render_table,
)
from focas_net.server import FocasServer
from focas_net.sim import default_machine

HOST = "127.0.0.1"


@pytest.fixture(params=VARIANTS)
async def floor_port(request: pytest.FixtureRequest) -> AsyncIterator[int]:
    """A floor server of each variant (``BufferedProtocol`` and plain ``Protocol``)."""
    variant: Variant = request.param
    server = await serve(HOST, 0, variant)
    try:
        yield server.sockets[0].getsockname()[1]
    finally:
        server.close()
        await server.wait_closed()


async def _exchange(port: int, data: bytes, expect: int, chunk: int | None = None) -> bytes:
    """Send ``data`` (in ``chunk``-byte pieces if given) and read ``expect`` bytes back."""
    reader, writer = await asyncio.open_connection(HOST, port)
    try:
        step = chunk or len(data)
        for i in range(0, len(data), step):
            writer.write(data[i : i + step])
            await writer.drain()
        return await asyncio.wait_for(reader.readexactly(expect), 5)
    finally:
        writer.close()
        await writer.wait_closed()


def _status_answer(request_id: int) -> bytes:
    return HEADER.pack(4 + len(STATUS_PAYLOAD), STATUS, request_id) + STATUS_PAYLOAD


async def test_floor_answers_status_with_the_fixed_payload(floor_port: int) -> None:
    client = await FloorClient.connect(HOST, floor_port)
    try:
        assert await client.read_status() == STATUS_PAYLOAD
        assert len(STATUS_PAYLOAD) == 20
    finally:
        await client.close()


async def test_floor_client_matches_pipelined_answers(floor_port: int) -> None:
    client = await FloorClient.connect(HOST, floor_port)
    try:
        answers = await asyncio.gather(*(client.read_status() for _ in range(200)))
        assert answers == [STATUS_PAYLOAD] * 200
        assert await client.request(0x7777) == struct.pack("<h", 1)  # unknown: EW_FUNC
    finally:
        await client.close()


class LoggedFloorClient(FloorClient):
    """The floor client, its transport a :class:`WriteLog` (``log``)."""

    log: WriteLog

    def connection_made(self, transport: asyncio.BaseTransport) -> None:
        self.log = WriteLog(transport)
        super().connection_made(self.log)


async def test_floor_client_writes_a_turns_frames_in_chunks(floor_port: int) -> None:
    client = await LoggedFloorClient.connect(HOST, floor_port)
    assert isinstance(client, LoggedFloorClient)
    sizes = client.log.sizes
    try:
        futures = [client.send(STATUS) for _ in range(2 * WRITE_CHUNK + 3)]  # one loop turn
        answers = await asyncio.gather(*futures)
        assert answers == [STATUS_PAYLOAD] * (2 * WRITE_CHUNK + 3)
        assert sizes == [8 * WRITE_CHUNK, 8 * WRITE_CHUNK, 8 * 3]  # 8-byte request frames
    finally:
        await client.close()


async def test_floor_server_handles_split_and_merged_frames(floor_port: int) -> None:
    requests = b"".join(HEADER.pack(4, STATUS, rid) for rid in (5, 6, 7))
    expected = b"".join(_status_answer(rid) for rid in (5, 6, 7))
    assert await _exchange(floor_port, requests, len(expected), chunk=1) == expected
    assert await _exchange(floor_port, requests, len(expected)) == expected


async def test_floor_server_takes_a_frame_larger_than_its_buffer(floor_port: int) -> None:
    big = HEADER.pack(4 + 60_000, 0x0104, 9) + bytes(60_000)
    answer = await _exchange(floor_port, big + HEADER.pack(4, STATUS, 10), 10 + 28)
    assert answer[:10] == HEADER.pack(6, 0x0104, 9) + struct.pack("<h", 1)
    assert answer[10:] == _status_answer(10)


async def test_floor_server_closes_on_a_bad_length(floor_port: int) -> None:
    reader, writer = await asyncio.open_connection(HOST, floor_port)
    try:
        writer.write(struct.pack("<IHH", 3, STATUS, 1))
        await writer.drain()
        assert await asyncio.wait_for(reader.read(), 5) == b""
    finally:
        writer.close()
        await writer.wait_closed()


async def test_worker_throughput_and_idle_connections_against_the_floor(floor_port: int) -> None:
    result = await worker.throughput(FLOOR, HOST, floor_port, conns=3, callers=2, duration=0.02)
    assert result["ops"] >= 6  # every caller completes at least one call
    assert result["elapsed"] > 0 and result["cpu"] >= 0
    w = worker.Worker(FLOOR)
    opened = await w.handle({"op": "idle_open", "host": HOST, "port": floor_port, "count": 7})
    assert opened == {"open": 7}
    assert await w.handle({"op": "idle_close"}) == {"open": 0}


async def test_worker_burst_pair_against_the_floor(floor_port: int) -> None:
    result = await worker.burst_pair(FLOOR, HOST, floor_port, burst=8, duration=0.01)
    assert set(result) == {"big", "small"}
    assert result["big"] > 0 and result["small"] > 0


def test_subjects_alternate_their_turns() -> None:
    suite = run.Suite(run.Config(), [], _results([]))
    suite.subjects = [FLOOR, FOCAS, PEER]
    assert suite.turns(0) == [FLOOR, FOCAS, PEER]
    assert suite.turns(1) == [PEER, FOCAS, FLOOR]


def test_storm_plan_covers_every_bit_evenly() -> None:
    plan = worker.storm_plan(1000, 8)
    assert len(plan) == 1000
    hits: dict[tuple[int, int], int] = {}
    for offset, bit in plan:
        assert 0 <= offset < 8 and 0 <= bit < 8
        hits[offset, bit] = hits.get((offset, bit), 0) + 1
    assert len(hits) == 64
    assert set(hits.values()) == {15, 16}


def test_count_wrong() -> None:
    assert worker.count_wrong(b"\xff" * 8, True) == 0
    assert worker.count_wrong(b"\xff\x7f", True) == 1
    assert worker.count_wrong(b"\x00\x00", False) == 0
    assert worker.count_wrong(b"\x01\x81", False) == 3


def test_pairwise_ratios_and_summary() -> None:
    assert pairwise_ratios([2.0, 9.0, 4.0], [1.0, 3.0, 8.0]) == [2.0, 3.0, 0.5]
    assert pairwise_ratios([1.0], [0.0]) == [math.inf]
    with pytest.raises(ValueError):
        pairwise_ratios([1.0, 2.0], [1.0])
    assert Summary.of([3.0, 1.0, 2.0, 10.0, 4.0]) == Summary(3.0, 1.0, 10.0)
    with pytest.raises(ValueError):
        Summary.of([])


def _results(rows: list[Row]) -> Results:
    return Results({"nproc": "2"}, "python -m benchmarks", {}, rows=rows)


def _tp(mode: str, subject: str, samples: list[float], floor: list[float]) -> Row:
    return Row(mode, subject, "req/s", samples, "floor", pairwise_ratios(samples, floor))


def test_evaluate_passes_and_fails_each_target() -> None:
    floor = [100.0, 100.0, 100.0]
    rows = [
        Row("seq", FLOOR, "req/s", floor),
        _tp("seq", FOCAS, [105.0, 101.0, 99.0], floor),  # median 1.01 >= 1.0
        _tp("seq", PEER, [50.0, 50.0, 50.0], floor),
        Row("pipe64", FLOOR, "req/s", floor),
        _tp("pipe64", FOCAS, [70.0, 85.0, 95.0], floor),  # median 0.85 < 0.9
        _tp("pipe64", PEER, [90.0, 90.0, 90.0], floor),  # ahead of focas_net
        Row("pmc4k", FOCAS, "ms", [3.0, 2.0], "floor speed", [0.9, 0.85]),
        Row("bitstorm", FOCAS, "calls/s", [1.0], extra={"lost": 0, "errors": 0, "calls": 2000}),
        Row("memory", FOCAS, "KiB/conn", [2.0, 30.0, 3.5]),
        Row("fleet_rate", FOCAS, "polls/s", [2000.0], "nominal", [1.0]),
        Row("fleet_cpu", FOCAS, "cores", [0.6]),
    ]
    checks = {c.name: c for c in evaluate(_results(rows), fleet_size=200, fleet_hz=10)}
    verdicts = {name: c.verdict for name, c in checks.items()}
    assert verdicts == {
        "seq >= 1.0 x floor": "PASS",
        "pipe64 >= 0.9 x floor": "FAIL",
        "conc100 >= 0.9 x floor": "SKIP",
        "pmc4k >= 0.8 x the floor's speed on as many frames": "PASS",
        "bitstorm: zero lost": "PASS",
        "memory <= 4 KiB per idle connection": "PASS",
        "fleet: 200 machines at 10 Hz, client CPU < 0.5 core": "FAIL",
        "seq: ahead of pymodbus": "PASS",
        "pipe64: ahead of pymodbus": "FAIL",
        "conc100: ahead of pymodbus": "SKIP",
    }


def test_evaluate_counts_a_lost_bit() -> None:
    rows = [Row("bitstorm", FOCAS, "calls/s", [1.0], extra={"lost": 1, "errors": 0})]
    (storm,) = [
        c for c in evaluate(_results(rows), fleet_size=1, fleet_hz=1) if "bitstorm" in c.name
    ]
    assert storm.passed is False


def test_table_and_json_render_every_row() -> None:
    floor = [1000.0, 3000.0, 2000.0]
    rows = [Row("seq", FLOOR, "req/s", floor), _tp("seq", FOCAS, [900.0, 2400.0, 2000.0], floor)]
    table = render_table(rows).splitlines()
    assert len(table) == 4
    assert table[2].split()[:5] == ["seq", "floor", "2,000", "1,000", "3,000"]
    assert "0.90 [0.80..1.00]" in table[3]
    results = _results(rows)
    results.checks = [Check("x", True, "fine"), Check("y", None, "not measured")]
    assert render_checks(results.checks).splitlines() == [
        "PASS  x: fine",
        "SKIP  y: not measured",
    ]
    data = json.loads(json.dumps(results.to_json()))
    assert data["rows"][1]["ratio"] == {"median": 0.9, "min": 0.8, "max": 1.0}
    assert [c["verdict"] for c in data["checks"]] == ["PASS", "SKIP"]


def test_cli_rejects_an_unknown_scenario(capsys: pytest.CaptureFixture[str]) -> None:
    assert run.main(["--only", "nonesuch"]) == 2
    assert "nonesuch" in capsys.readouterr().err


def test_floor_server_and_client_processes(tmp_path: Path) -> None:
    cfg = run.Config(reps=1, duration=0.05, warmup=0.01)
    server = run.start_server(FLOOR, cfg)
    client = run.WorkerProcess(FLOOR, cfg)
    try:
        host, port = server.endpoint
        result = client.call("throughput", host=host, port=port, conns=2, callers=2, duration=0.05)
        assert result["ops"] >= 4
        assert server.rss_kib() > 0
        with pytest.raises(RuntimeError, match="unknown op"):
            client.call("nonesuch")
    finally:
        client.stop()
        server.stop()
    assert server.proc.returncode is not None
    assert client.proc.returncode == 0


def test_process_tree_cpu_and_rss_count_the_children() -> None:
    child = subprocess.Popen([sys.executable, "-c", "import sys; sys.stdin.read()"], stdin=PIPE)
    try:
        me = os.getpid()
        assert child.pid in plant.process_tree(me)
        assert plant.tree_rss_kib(me) > plant.tree_rss_kib(child.pid) > 0
        assert plant.tree_cpu_seconds(me) >= plant.tree_cpu_seconds(child.pid) >= 0.0
    finally:
        assert child.stdin is not None
        child.stdin.close()
        child.wait(IO_TIMEOUT)
    assert child.pid not in plant.process_tree(os.getpid())
    waited = plant.cpu_pressure()
    assert waited is None or 0.0 <= waited <= 1.0


def _plant_rows(achieved: float, worst_ms: float, client: float, server: float) -> list[Row]:
    rows = []
    for name in ("plant", "plant_run"):
        rows += [
            Row(f"{name}_rate", FOCAS, "polls/s", [10_000 * achieved], "nominal", [achieved],
                extra={"worst_ms": worst_ms}),
            Row(f"{name}_client", FOCAS, "cores", [client]),
            Row(f"{name}_server", FOCAS, "cores", [server]),
        ]  # fmt: skip
    return rows


@pytest.mark.parametrize(
    ("achieved", "worst_ms", "client", "server", "verdicts"),
    [
        (1.0, 10.0, 0.3, 0.3, ("PASS", "PASS")),
        (0.98, 10.0, 0.3, 0.3, ("FAIL", "FAIL")),  # polls missed
        (1.0, 60.0, 0.3, 0.3, ("FAIL", "FAIL")),  # a poll slower than 50 ms
        (1.0, 10.0, 0.6, 0.3, ("FAIL", "FAIL")),  # the client over half a core
        (1.0, 10.0, 0.3, 0.7, ("FAIL", "PASS")),  # the idle server over half a core
    ],
)
def test_evaluate_plant_holds_every_target(
    achieved: float, worst_ms: float, client: float, server: float, verdicts: tuple[str, str]
) -> None:
    rows = _plant_rows(achieved, worst_ms, client, server)
    checks = plant.evaluate_plant(_results(rows), size=1000, ready_size=5000)
    got = {c.name.split(":")[0]: c.verdict for c in checks}
    assert (got["plant"], got["plant_run"]) == verdicts
    assert got["plant_ready"] == "SKIP"
    assert got["native seq"] == got["native conc64"] == "SKIP"
    assert "native pipe64" not in got  # reported, not held to the target


def test_evaluate_plant_start_and_native() -> None:
    rows = [
        Row("plant_ready", FOCAS, "s", [9.0, 16.0]),  # the slowest start counts
        Row("plant_rss", FOCAS, "MiB", [300.0]),
        Row("native_seq_server", FOCAS, "us/req", [60.0], "packed", [1.4]),
        Row("native_conc64_server", FOCAS, "us/req", [60.0], "packed", [1.6]),
        Row("native_pipe64_server", FOCAS, "us/req", [60.0], "packed", [8.0]),
    ]
    checks = {
        c.name.split(":")[0]: c for c in plant.evaluate_plant(_results(rows), size=1, ready_size=2)
    }
    assert checks["plant_ready"].verdict == "FAIL"
    assert "slowest start 16.0 s" in checks["plant_ready"].detail
    assert checks["native seq"].verdict == "PASS"
    assert checks["native conc64"].verdict == "FAIL"
    assert "median ratio 1.60" in checks["native conc64"].detail
    assert "native pipe64" not in checks
    assert checks["plant"].verdict == "SKIP"


async def test_worker_polls_a_fleet_over_connections_opened_once() -> None:
    async with FocasServer([default_machine(), default_machine()], host=HOST, port=0) as server:
        targets: list[list[Any]] = [[HOST, port] for _, port in server.addresses]
        conns = await worker.open_fleet(targets)
        floors = await worker.open_fleet(targets, FloorClient.connect)
        try:
            staggered = await worker.poll_fleet(conns, interval=0.05, duration=0.2)
            together = await worker.poll_fleet(conns, interval=0.05, duration=0.2, slots=1)
            floor_slot = await worker.poll_fleet(floors, interval=0.05, duration=0.2, slots=1)
        finally:
            await worker.close_conns(conns + floors)
    for r in (staggered, together, floor_slot):
        assert r["due"] == 2 * 4  # 2 machines, 4 ticks each
        assert 0 < r["polls"] <= r["due"]  # a tick that went by under load is skipped
        assert r["errors"] == 0
        assert r["worst_latency"] > 0.0


async def test_worker_native_throughput_over_many_connection_pairs() -> None:
    async with FocasServer([default_machine()], host=HOST, port=0) as server:
        ((_, port),) = server.addresses
        r = await worker.native_throughput(HOST, port, conns=3, callers=2, duration=0.1)
    assert r["ops"] >= 3 * 2  # every caller finished at least one statinfo after the deadline
    assert r["elapsed"] > 0.0
    assert r["cpu"] > 0.0
