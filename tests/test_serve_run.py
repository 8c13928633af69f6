"""``serve --speed`` and ``serve --run``, and production (``cycle_start(repeat=True)``)."""

from __future__ import annotations

import argparse

import pytest

from focas_net.cli import _fleet, serve
from focas_net.sim import default_machine
from focas_net.sim.nc import CycleState, ManualClock, RealTimeClock

PART = "O0010\nN10 G1 X10. F600\nN20 G0 X0\nN30 M30\n"  # 1 s of cutting, a rapid back


def _parse(*argv: str) -> argparse.Namespace:
    parser = argparse.ArgumentParser()
    serve.register(parser.add_subparsers())
    return parser.parse_args(["serve", *argv])


def test_production_repeats_the_main_program_and_counts_every_part() -> None:
    clock = ManualClock()
    machine = default_machine(sim_clock=clock, programs=(PART,))
    machine.cycle_start(repeat=True)
    one_part = 1.0 + 10.0 / 24000.0 * 60.0  # G1 10 mm at F600, G0 back at 24 m/min
    clock.advance(one_part * 3 + 0.1)
    assert machine.read_param(6711, 0) == 3
    assert machine.status().run == 3  # still running: the fourth part
    assert machine.timer(2) == pytest.approx(3.0 + 0.1)  # cutting: three parts and a bit
    machine.reset()
    assert machine.engine.state is CycleState.RESET


def test_serve_run_and_speed_build_running_machines_on_one_clock() -> None:
    machines = _fleet.build_machines(_parse("--fleet", "3", "--run", "--speed", "10"))
    assert all(m.engine.state is CycleState.START for m in machines)
    clocks = {id(m.sim_clock) for m in machines}
    assert len(clocks) == 1
    clock = machines[0].sim_clock
    assert isinstance(clock, RealTimeClock) and clock.speed == 10.0


@pytest.mark.parametrize("speed", ["0", "-1", "x", "1e9", "nan"])
def test_bad_speed(speed: str, capsys: pytest.CaptureFixture[str]) -> None:
    with pytest.raises(SystemExit) as exc:
        _parse("--speed", speed)
    assert exc.value.code == 2
    assert "--speed" in capsys.readouterr().err
