"""The Python API as a new user meets it, a confirming ninth pass: points left arguable are
decided (one machine served twice is refused, naming it; the history options of an alarm
projection that reads no history are documented as changing nothing), and the packed and
native clients asked the same thing answer the same."""

from __future__ import annotations

from typing import Any

import pytest

from focas_net import (
    EW,
    CncError,
    FocasClient,
    FocasServer,
    NativeClient,
    NativeServer,
    default_machine,
    start_native,
)
from focas_net.client import AlarmProjection, AlarmRaised, ProjectionMode
from focas_net.sim import Machine, MachineError, PathSpec
from focas_net.sim.nc.scenario import DEFAULT_SCENARIO


# -- one Machine object given twice to FocasServer --------------------------------------------
@pytest.mark.parametrize("where", [(0, 1), (0, 2), (1, 2)])
def test_the_same_machine_given_twice_is_refused_naming_both_places(
    where: tuple[int, int],
) -> None:
    machines = [default_machine(), default_machine(), default_machine()]
    first, second = where
    machines[second] = machines[first]
    with pytest.raises(ValueError) as refused:
        FocasServer(machines, port=0)
    text = str(refused.value)
    assert f"machines[{second}]" in text
    assert f"machines[{first}]" in text
    assert repr(machines[first]) in text


def test_two_machines_alike_but_not_the_same_object_are_served() -> None:
    one, other = default_machine(), default_machine()
    server = FocasServer([one, other], port=0)
    assert [listener.machine for listener in server.listeners] == [one, other]


def test_a_machine_given_twice_through_a_generator_is_refused_as_well() -> None:
    machine = default_machine()
    with pytest.raises(ValueError, match=r"machines\[1\] is machines\[0\]"):
        FocasServer((machine for _ in range(2)), port=0)


# -- AlarmProjection's history options in ACTIVE mode ----------------------------------------
@pytest.mark.parametrize("replay", [True, False])
@pytest.mark.parametrize("native", [False, True])
async def test_active_mode_reads_no_history_whatever_replay_history_says(
    both_clients: tuple[Machine, FocasClient, NativeClient],
    monkeypatch: pytest.MonkeyPatch,
    replay: bool,
    native: bool,
) -> None:
    machine, cnc, through_native = both_clients
    client: FocasClient | NativeClient = through_native if native else cnc
    machine.raise_alarm(0, 4, 100, "a test alarm")

    async def no_history(*args: object, **kwargs: object) -> object:
        raise AssertionError("ACTIVE mode reads no history")

    monkeypatch.setattr(client, "read_alarm_history", no_history)
    projection = AlarmProjection(client, mode="active", replay_history=replay, depth=7)
    assert projection.mode is ProjectionMode.ACTIVE
    events = await projection.poll()
    assert [type(e) for e in events] == [AlarmRaised]


def test_the_docs_say_what_replay_history_does_in_active_mode() -> None:
    from pathlib import Path

    docs = (Path(__file__).parents[1] / "docs" / "client.md").read_text(encoding="utf-8")
    assert "in `ACTIVE` mode they change nothing" in docs
    assert "in ACTIVE mode they change nothing" in (AlarmProjection.__doc__ or "")


# -- alarm history depth: the clients read more than 250 as 250 ------------------------------
@pytest.mark.parametrize("native", [False, True])
@pytest.mark.parametrize("depth", [0, -1, -250])
async def test_a_depth_below_one_is_refused_without_a_bound_the_client_does_not_keep(
    both_clients: tuple[Machine, FocasClient, NativeClient], native: bool, depth: int
) -> None:
    _, cnc, through_native = both_clients
    client: FocasClient | NativeClient = through_native if native else cnc
    assert (await client.read_alarm_history(251)).ew == 0  # taken, read as 250
    with pytest.raises(ValueError) as refused:
        await client.read_alarm_history(depth)
    assert str(refused.value) == (
        f"history depth {depth} is below 1 (the latest entries to read; more than 250 "
        "reads the 250 the history holds)"
    )


@pytest.mark.parametrize("depth", [251, 1000])
async def test_a_projection_takes_the_depths_its_client_takes(
    both_clients: tuple[Machine, FocasClient, NativeClient], depth: int
) -> None:
    machine, cnc, _ = both_clients
    machine.raise_alarm(0, 4, 100, "a test alarm")
    projection = AlarmProjection(cnc, "active+history", depth=depth)
    events = await projection.poll()
    assert [type(e).__name__ for e in events] == ["AlarmRaised", "AlarmHistoryEvent"]


@pytest.mark.parametrize("depth", [0, -3])
def test_a_projection_refuses_a_depth_below_one_as_its_client_does(depth: int) -> None:
    client = FocasClient("127.0.0.1", 8193)
    with pytest.raises(ValueError) as refused:
        AlarmProjection(client, "active+history", depth=depth)
    assert str(refused.value) == (
        f"history depth {depth} is below 1 (the latest entries to read; more than 250 "
        "reads the 250 the history holds)"
    )


# -- a scenario of another type ----------------------------------------------------------------
@pytest.mark.parametrize("scenario", ["nope", 5, {"parts": 3}, True])
def test_start_scenario_names_a_scenario_of_another_type(scenario: Any) -> None:
    machine = default_machine()
    with pytest.raises(TypeError) as refused:
        machine.start_scenario(scenario)
    assert str(refused.value) == (
        f"scenario must be a Scenario (focas_net.sim.nc.scenario) or None, got {scenario!r}"
    )
    assert not machine.scenario_running


@pytest.mark.parametrize("scenario", ["nope", 5, ["a"]])
def test_a_machine_is_not_built_with_a_scenario_of_another_type(scenario: Any) -> None:
    with pytest.raises(TypeError) as refused:
        Machine("m", scenario=scenario)
    assert str(refused.value) == (
        f"scenario must be a Scenario (focas_net.sim.nc.scenario) or None, got {scenario!r}"
    )


def test_a_scenario_of_its_own_type_still_starts() -> None:
    machine = default_machine()
    machine.start_scenario(DEFAULT_SCENARIO)
    assert machine.scenario_running


def test_a_scenario_attribute_set_to_another_type_is_named_when_started() -> None:
    machine = default_machine()
    machine.scenario = "nope"  # type: ignore[assignment]
    with pytest.raises(TypeError, match=r"scenario must be a Scenario .* got 'nope'"):
        machine.start_scenario()


# -- the native client's arguments, as its guide gives them -----------------------------------
def test_the_native_guide_gives_the_native_clients_arguments_and_their_defaults() -> None:
    import inspect
    import re
    from pathlib import Path

    text = (Path(__file__).parents[1] / "docs" / "native-client.md").read_text(encoding="utf-8")
    (block,) = re.findall(r"```python\n(NativeClient\(host.*?)```", text, flags=re.S)
    written = dict(
        (name, value) for name, value in re.findall(r"(\w+)=([^,)\s]+)", " ".join(block.split()))
    )
    signature = inspect.signature(NativeClient)
    defaults = {
        name: repr(p.default)
        for name, p in signature.parameters.items()
        if p.default is not inspect.Parameter.empty
    }
    assert written == defaults
    packed = set(inspect.signature(FocasClient).parameters)
    lacking = sorted(packed - set(signature.parameters))
    assert lacking == ["max_frame", "max_in_flight", "password", "server_hostname", "ssl"]
    for name in lacking:
        assert f"`{name}`" in text
        with pytest.raises(TypeError, match=f"unexpected keyword argument '{name}'"):
            NativeClient("127.0.0.1", **{name: None})  # type: ignore[arg-type]


# -- machines in a dict or a set ---------------------------------------------------------------
def test_machines_in_a_dict_are_refused_naming_the_dict_not_its_first_key() -> None:
    machines = {"lathe": default_machine(), "mill": default_machine()}
    with pytest.raises(TypeError) as refused:
        FocasServer(machines, port=0)  # type: ignore[arg-type]
    assert str(refused.value) == (
        "machines must be a Machine or a list of them, got a dict (its machines in order: "
        "list(machines.values()))"
    )


@pytest.mark.parametrize("kind", [set, frozenset])
def test_machines_in_a_set_are_refused_as_a_set_has_no_order(kind: Any) -> None:
    machines = kind([default_machine(), default_machine()])
    with pytest.raises(TypeError) as refused:
        FocasServer(machines, port=8193)
    assert str(refused.value) == (
        f"machines must be a Machine or a list of them, got a {kind.__name__}, which has no "
        "order (machine i listens on port + i): make it a list"
    )


# -- simulator controls refused by the server say why ------------------------------------------
@pytest.mark.parametrize("call", ["list_faults", "clear_faults"])
async def test_a_fault_scope_the_server_does_not_know_is_named_as_inject_fault_names_it(
    both_clients: tuple[Machine, FocasClient, NativeClient], call: str
) -> None:
    _, cnc, _ = both_clients
    with pytest.raises(CncError) as armed:
        await cnc.sim.inject_fault("delay", scope=5)
    with pytest.raises(CncError) as refused:
        await getattr(cnc.sim, call)(5)
    assert refused.value.ew == EW.DATA
    why = "no fault scope 5 (one of 0 CONNECTION, 1 MACHINE)"
    assert str(armed.value).endswith(why)
    assert str(refused.value).endswith(f"sim_{call}: {why}")


@pytest.mark.parametrize("number", [3901, 3902])
async def test_vacating_a_parts_count_says_why_it_is_refused(
    both_clients: tuple[Machine, FocasClient, NativeClient], number: int
) -> None:
    machine, cnc, _ = both_clients
    before = machine.read_macro(number)
    with pytest.raises(CncError) as refused:
        await cnc.sim.vacate_macro(number)
    assert refused.value.ew == EW.DATA
    assert str(refused.value).endswith(
        f"sim_vacate_macro: #{number} is a parts count, which always holds a number "
        "(write 0 to reset it)"
    )
    assert machine.read_macro(number) == before


def test_the_machine_refuses_a_vacant_parts_count_in_the_clients_words() -> None:
    machine = default_machine()
    with pytest.raises(MachineError) as refused:
        machine.write_macro(3902, None)
    assert str(refused.value) == (
        "EW_DATA: #3902 is a parts count, which always holds a number (write 0 to reset it)"
    )


# -- a main program number of another type ----------------------------------------------------
@pytest.mark.parametrize("number", ["1", 1.0, True, "O0001"])
def test_a_main_program_of_another_type_is_a_type_error_naming_it(number: Any) -> None:
    with pytest.raises(TypeError) as refused:
        Machine("m", programs=["O0001\nM30\n"], main_program=number)
    assert str(refused.value) == f"main_program must be an integer, got {number!r}"
    with pytest.raises(TypeError) as by_path:
        Machine("m", paths=[PathSpec(("X",), programs=("O0001\nM30\n",), main_program=number)])
    assert str(by_path.value) == str(refused.value)


# -- a native-only server's port is named as the argument typed ------------------------------
@pytest.mark.parametrize(
    ("port", "kind", "words"),
    [
        (-1, ValueError, "port -1 is outside 0..65535 (0: any free port)"),
        (65536, ValueError, "port 65536 is outside 0..65535 (0: any free port)"),
        ("8193", TypeError, "port must be an integer, got '8193'"),
        (None, TypeError, "port must be an integer, got None"),
        (True, TypeError, "port must be an integer, got True"),
    ],
)
async def test_a_native_server_names_its_port_as_given(port: Any, kind: Any, words: str) -> None:
    with pytest.raises(kind) as refused:
        NativeServer(default_machine(), "127.0.0.1", port)
    assert str(refused.value) == words
    with pytest.raises(kind) as started:
        await start_native(default_machine(), port=port)
    assert str(started.value) == words
