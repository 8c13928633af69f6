"""The Python API as a new user meets it, an eighth pass: the simulated machine, the packed
and the native client and the simulator's controls given wrong types and the edges of their
ranges, refused alike wherever the same rule applies, naming what was given."""

from __future__ import annotations

from collections.abc import AsyncIterator
from pathlib import Path
from typing import Any

import pytest

from focas_net import (
    EW,
    CncError,
    FocasClient,
    FocasServer,
    MachineError,
    NativeClient,
    default_machine,
    load_machine,
)
from focas_net.sim import Machine, machine_from_dict
from focas_net.sim.nc import ManualClock

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"


@pytest.fixture
async def served() -> AsyncIterator[tuple[Machine, FocasClient, NativeClient]]:
    machine = default_machine(sim_clock=ManualClock())
    async with FocasServer(machine, port=0) as server:
        host, port = server.addresses[0]
        async with (
            FocasClient(host, port, timeout=5) as cnc,
            NativeClient(host, port, timeout=5) as native,
        ):
            yield machine, cnc, native


def _ew(exc: BaseException) -> int:
    assert isinstance(exc, MachineError | CncError)
    return exc.ew


# -- the rapid override's F0 -------------------------------------------------------------------
@pytest.mark.parametrize(("typed", "percent"), [("F0", 0), (" f0 ", 0), ("f0", 0)])
async def test_the_rapid_override_takes_f0_from_python_as_the_command_line_does(
    served: tuple[Machine, FocasClient, NativeClient], typed: str, percent: int
) -> None:
    machine, cnc, _ = served
    machine.set_overrides(rapid=25)
    machine.set_overrides(rapid=typed)
    assert machine.overrides()[1] == percent
    machine.set_overrides(rapid=25)
    await cnc.sim.set_overrides(rapid=typed)
    assert machine.overrides()[1] == percent


@pytest.mark.parametrize("typed", ["F25", "F", "f 0", "F00"])
async def test_other_rapid_override_text_is_refused_alike_naming_it(
    served: tuple[Machine, FocasClient, NativeClient], typed: str
) -> None:
    machine, cnc, _ = served
    with pytest.raises(ValueError) as by_machine:
        machine.set_overrides(feed=50, rapid=typed)
    with pytest.raises(ValueError) as by_client:
        await cnc.sim.set_overrides(feed=50, rapid=typed)
    assert str(by_machine.value) == str(by_client.value)
    assert repr(typed) in str(by_client.value)
    assert machine.overrides() == (100, 100, 100)  # nothing changed, not even the feed


@pytest.mark.parametrize(
    ("kwargs", "words"),
    [
        ({"feed": "50"}, "feed override must be a whole number, got '50'"),
        ({"rapid": "50"}, "rapid override must be a whole number or the text F0, got '50'"),
        ({"rapid": ""}, "rapid override must be a whole number or the text F0, got ''"),
        ({"spindle": "F0"}, "spindle override must be a whole number, got 'F0'"),
        ({"rapid": 50.0}, "rapid override must be a whole number or the text F0, got 50.0"),
        ({"rapid": True}, "rapid override must be a whole number or the text F0, got True"),
        ({"rapid": b"F0"}, "rapid override must be a whole number or the text F0, got b'F0'"),
    ],
)
async def test_an_override_of_another_type_is_one_type_error_on_machine_and_client(
    served: tuple[Machine, FocasClient, NativeClient], kwargs: dict[str, Any], words: str
) -> None:
    machine, cnc, _ = served
    with pytest.raises(TypeError, match=words):
        machine.set_overrides(**kwargs)
    with pytest.raises(TypeError, match=words):
        await cnc.sim.set_overrides(**kwargs)
    assert machine.overrides() == (100, 100, 100)


# -- a PMC range of no bytes -------------------------------------------------------------------
@pytest.mark.parametrize("area", ["R", "G", "X"])
def test_the_machine_refuses_a_pmc_range_of_no_bytes_as_the_clients_do(area: str) -> None:
    machine = default_machine()
    version = machine.version
    for op in (
        lambda: machine.write_pmc(area, 0, b""),
        lambda: machine.write_pmc(area, 0, bytearray(), force=True),
        lambda: machine.read_pmc(area, 0, 0),
        lambda: machine.read_pmc(area, 0, -1),
    ):
        with pytest.raises(MachineError) as refused:
            op()
        assert refused.value.ew == EW.LENGTH
        assert "PMC byte count" in str(refused.value) and "one byte at least" in str(refused.value)
    assert machine.version == version  # nothing was written


async def test_a_pmc_range_of_no_bytes_is_refused_by_every_front_end(
    served: tuple[Machine, FocasClient, NativeClient],
) -> None:
    _, cnc, native = served
    for call in (
        lambda: cnc.write_pmc("R", 0, b""),
        lambda: cnc.read_pmc("R", 0, 0),
        lambda: cnc.sim.set_pmc("R", 0, b""),
        lambda: native.write_pmc("R", 0, b""),
        lambda: native.read_pmc("R", 0, 0),
    ):
        with pytest.raises(ValueError, match=r"PMC byte count 0 is outside 1\.\.65536"):
            await call()


# -- an alarm of an axis the path has not ------------------------------------------------------
async def test_an_alarm_of_an_axis_beyond_the_path_names_the_axis_and_the_count(
    served: tuple[Machine, FocasClient, NativeClient],
) -> None:
    machine, cnc, _ = served
    words = "axis_no 9 outside 0..3: the path has 3 axes (0: an alarm of no axis)"
    with pytest.raises(MachineError) as by_machine:
        machine.raise_alarm(9, 6, 411, "SERVO")
    assert by_machine.value.ew == EW.ATTRIB and by_machine.value.detail == words
    with pytest.raises(CncError) as by_client:
        await cnc.sim.raise_alarm("SV", 411, "SERVO", axis_no=9)
    assert by_client.value.ew == EW.ATTRIB
    assert by_client.value.detail == f"sim_raise_alarm: {words}"
    await cnc.sim.raise_alarm("SV", 411, "SERVO", axis_no=3)  # the last axis is one
    assert [(a.axis_no, a.alm_no) for a in await cnc.read_alarms()] == [(3, 411)]


def test_an_alarm_axis_on_a_machine_of_one_axis_says_axis() -> None:
    machine = machine_from_dict({"machine": {"name": "one", "axes": ["X"]}})
    with pytest.raises(MachineError, match=r"axis_no 2 outside 0\.\.1: the path has 1 axis \("):
        machine.raise_alarm(2, 6, 411)


async def test_an_alarm_axis_is_named_with_the_count_of_the_path_it_was_raised_on() -> None:
    machine = load_machine(EXAMPLES / "lathe_2path.toml")
    async with FocasServer(machine, port=0) as server:
        host, port = server.addresses[0]
        async with FocasClient(host, port, timeout=5) as cnc:
            with pytest.raises(CncError) as refused:
                await cnc.sim.raise_alarm("SV", 411, axis_no=3, path=2)
            await cnc.sim.raise_alarm("SV", 411, axis_no=2, path=2)
    assert refused.value.detail.endswith(
        "axis_no 3 outside 0..2: the path has 2 axes (0: an alarm of no axis)"
    )
    assert [a.axis_no for a in machine.active_alarms(path=2)] == [2]
