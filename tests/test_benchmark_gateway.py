"""The gateway's scale benchmark on a tiny scale: its targets' arithmetic, and one run of three
machines for a few seconds that reports every field. Nothing here asserts a speed."""

from __future__ import annotations

import json
import os
from pathlib import Path

import pytest

from benchmarks import gateway
from benchmarks.gateway import GATEWAY, Window, checks, rows
from benchmarks.gateway_poll import FLOOR, FWLIB_POOL, FWLIB_THREADS, ticks


def _window(subject: str, cpu: float, *, fast: int = 100, skipped: int = 0) -> Window:
    return Window(
        subject, wall=10.0, cpu=cpu, fleet_cpu=2.0, fast=fast, fast_errors=0, slow=10,
        slow_errors=0, skipped=skipped, fast_due=100.0, slow_due=10.0, load=(0.5, 0.7),
        pressure=0.1,
    )  # fmt: skip


def test_checks_hold_the_gateway_to_half_a_core_and_three_times_the_library() -> None:
    windows = {
        GATEWAY: [_window(GATEWAY, 2.0)],  # 0.2 core
        FLOOR: [_window(FLOOR, 1.0)],
        FWLIB_THREADS: [_window(FWLIB_THREADS, 8.0)],
        FWLIB_POOL: [_window(FWLIB_POOL, 5.0, fast=90, skipped=10)],  # the cheaper, late
    }
    verdicts = {c.name: (c.verdict, c.detail) for c in checks(windows)}
    assert verdicts["gateway <= 0.5 core, at 99% of its polls"] == ("PASS", "0.200 core")
    name = "gateway >= 3 x less CPU than FANUC's library (its cheaper way)"
    assert verdicts[name] == ("FAIL", "2.50 x (fwlib-pool)")
    polls = "fwlib-pool: >= 99% of the polls due, no cycle overrun, no error"
    assert verdicts[polls] == ("FAIL", "fast 90.0%, slow 100.0%, 10 skipped, 0 errors")
    assert verdicts[polls.replace("fwlib-pool", GATEWAY)][0] == "PASS"


def test_rows_give_each_subject_its_cores_and_the_gateway_its_floor() -> None:
    windows = {
        GATEWAY: [_window(GATEWAY, 2.0)],
        FLOOR: [_window(FLOOR, 1.0)],
        FWLIB_THREADS: [_window(FWLIB_THREADS, 4.0)],
    }
    table = {
        row.subject if row.scenario == "gateway" else row.scenario: row for row in rows(windows)
    }
    gw = table["focas_net"]
    assert gw.summary.median == pytest.approx(0.2)
    assert gw.ratio is not None and gw.ratio.median == pytest.approx(0.5)
    assert gw.ratio_to == FWLIB_THREADS
    assert gw.note.startswith("2.00 x the client floor; 20,000 us per machine and fast cycle; ")
    assert "fast 100/100 (100.0%)" in gw.note
    assert table["gateway_fwlib_threads"].ratio is None
    assert table["gateway_floor"].extra["fleet_cores"] == pytest.approx(0.2)


def test_a_gateway_behind_its_polls_does_not_pass_on_its_cpu() -> None:
    windows = {GATEWAY: [_window(GATEWAY, 2.0, fast=30)]}
    verdicts = {c.name: (c.verdict, c.detail) for c in checks(windows)}
    assert verdicts["gateway <= 0.5 core, at 99% of its polls"] == (
        "FAIL",
        "0.200 core at 30.0% of its polls",
    )


def test_checks_skip_what_was_not_measured() -> None:
    verdicts = {c.name: c.verdict for c in checks({FLOOR: [_window(FLOOR, 1.0)]})}
    assert verdicts["gateway <= 0.5 core, at 99% of its polls"] == "SKIP"
    assert verdicts["gateway >= 3 x less CPU than FANUC's library (its cheaper way)"] == "SKIP"


def test_ticks_count_from_zero_one_interval_apart() -> None:
    schedule = ticks(1000.0, offset=500.0)
    tick, due, skipped = next(schedule)
    assert (tick, skipped) == (0, 0)
    assert next(schedule) == (1, due + 1000.0, 0)


def test_three_machines_for_a_few_seconds(tmp_path: Path) -> None:
    subjects = [FLOOR]
    if os.environ.get("FOCAS_NET_FWLIB"):
        subjects += [FWLIB_THREADS, FWLIB_POOL]
    if gateway.gateway_available() is None and os.path.exists(gateway.MOSQUITTO):
        subjects.append(GATEWAY)
    out = tmp_path / "gateway.json"
    argv = ["--machines", "3", "--seconds", "2", "--warmup", "1", "--pool", "2"]
    argv += ["--only", ",".join(subjects), "--json", str(out)]
    assert gateway.main(argv) == 0
    results = json.loads(out.read_text(encoding="utf-8"))
    assert results["config"]["machines"] == 3
    measured = {row["scenario"] for row in results["rows"]}
    for subject in subjects:
        assert ("gateway" if subject == GATEWAY else f"gateway_{subject.replace('-', '_')}") in (
            measured
        ), results["skipped"]
    for row in results["rows"]:
        assert row["unit"] == "cores"
        extra = row["extra"]
        assert extra["errors"] == 0, row["note"]
        assert extra["fast"] > 0 and extra["fast_due"] > 0
        assert {"slow", "slow_due", "skipped", "fleet_cores", "load_max"} <= set(extra)
    verdicts = {c["name"]: c["verdict"] for c in results["checks"]}
    assert any(name.startswith(f"{FLOOR}: ") for name in verdicts)
