"""The Python API as a new user meets it, a confirming pass after the eighth: a parameter value
with decimals refused in one wording whether it is text or a Decimal, on both clients; a
sequence of clients that is no list named without a Python repr; and a call on a client that
is not connected telling why, in every state, on both clients."""

from __future__ import annotations

from collections.abc import Callable
from decimal import Decimal
from typing import Any

import pytest
from support import free_port

from focas_net import (
    EW,
    AlarmProjection,
    CncError,
    FaultKind,
    FocasClient,
    FocasConnectionError,
    FocasServer,
    NativeClient,
    default_machine,
    read_dynamic_all,
    read_status_all,
    read_status_paths_all,
)
from focas_net.client import alarm_changes
from focas_net.client._values import param_int
from focas_net.sim import Machine
from focas_net.sim.nc import ManualClock
from focas_net.web import ActionError, Station, perform

_CLIENTS = [FocasClient, NativeClient]


# -- a parameter value with decimals -----------------------------------------------------------
@pytest.mark.parametrize("value", ["1.5", Decimal("1.5"), " 1.5 ", "+1.50"])
async def test_decimals_for_an_integer_parameter_are_refused_in_one_wording(
    both_clients: tuple[Machine, FocasClient, NativeClient], value: str | Decimal
) -> None:
    machine, cnc, native = both_clients
    shown = str(Decimal(str(value).strip()))
    for client in (cnc, native):
        with pytest.raises(ValueError) as caught:
            await client.write_param(1410, value)
        assert str(caught.value) == (
            f"parameter 1410 is not a real parameter: {shown} is no integer"
        )
    assert machine.read_param(1410, 0) == 5000


@pytest.mark.parametrize(("value", "written"), [("1.0", 1), (" 12.00 ", 12), (Decimal("7.0"), 7)])
async def test_text_with_zero_decimals_is_written_as_a_decimal_is(
    both_clients: tuple[Machine, FocasClient, NativeClient], value: str | Decimal, written: int
) -> None:
    machine, cnc, native = both_clients
    machine.set_panel(0, 1, 0)  # MDI, PWE on
    session = machine.new_session()
    for client in (cnc, native):
        machine.write_param(session, 1410, 0, 5000)
        await client.write_param(1410, value)
        assert machine.read_param(1410, 0) == written


@pytest.mark.parametrize("value", [Decimal("NaN"), Decimal("-Infinity"), Decimal("sNaN")])
async def test_a_decimal_that_is_no_number_is_refused_alike_without_a_repr(
    both_clients: tuple[Machine, FocasClient, NativeClient], value: Decimal
) -> None:
    _, cnc, native = both_clients
    texts = set()
    for client in (cnc, native):
        with pytest.raises(ValueError) as caught:
            await client.write_param(1410, value)
        texts.add(str(caught.value))
    assert texts == {f"parameter 1410: not a number: {value} (no NaN or infinity)"}


async def test_a_decimal_fitting_no_parameter_type_is_named_as_typed(
    both_clients: tuple[Machine, FocasClient, NativeClient],
) -> None:
    _, cnc, native = both_clients
    for client in (cnc, native):
        with pytest.raises(ValueError) as caught:
            await client.write_param(1410, Decimal("0.00000000001"))
        assert "Decimal(" not in str(caught.value)
        assert "0.00000000001" in str(caught.value)


@pytest.mark.parametrize(
    ("typed", "words"),
    [
        ("1e3", "parameter 6711: not a number: '1e3' (no exponent: write the digits)"),
        ("inf", "parameter 6711: not a number: 'inf' (no NaN or infinity: write the digits)"),
        ("1_000", "parameter 6711: not a number: '1_000'"),
        ("", "parameter 6711: not a number: '' (nothing typed)"),
        ("12.5", "parameter 6711 is not a real parameter: 12.5 is no integer"),
    ],
)
def test_parameter_text_is_read_as_param_set_reads_it(typed: str, words: str) -> None:
    with pytest.raises(ValueError) as caught:
        param_int(6711, typed)
    assert str(caught.value) == words
    assert param_int(6711, "12.0") == 12


# -- many clients at once ------------------------------------------------------------------------
@pytest.mark.parametrize("call", [read_status_all, read_status_paths_all, read_dynamic_all])
async def test_clients_given_as_a_generator_are_named_without_a_repr(call: Any) -> None:
    clients = (c for c in [NativeClient("127.0.0.1", 1)])
    with pytest.raises(TypeError) as caught:
        await call(clients)
    text = str(caught.value)
    assert " at 0x" not in text and "<" not in text
    assert text == "clients must be a list of clients, got a generator (make it a list: list(...))"


@pytest.mark.parametrize(
    ("clients", "kind"), [({NativeClient("127.0.0.1", 1)}, "a set"), (iter([]), "a list_iterator")]
)
async def test_clients_in_a_set_or_an_iterator_are_named_by_kind(clients: Any, kind: str) -> None:
    with pytest.raises(TypeError) as caught:
        await read_status_all(clients)
    assert str(caught.value) == (
        f"clients must be a list of clients, got {kind} (make it a list: list(...))"
    )


async def test_clients_in_a_dict_are_named_without_a_hint_to_list_its_keys() -> None:
    with pytest.raises(TypeError) as caught:
        clients: Any = {"m1": NativeClient("127.0.0.1", 1)}
        await read_status_all(clients)
    assert str(caught.value) == "clients must be a list of clients, got a dict"


# -- a call on a client that is not connected -----------------------------------------------------
@pytest.mark.parametrize("kind", _CLIENTS)
async def test_a_call_after_a_refused_connect_tells_why(kind: Any) -> None:
    port = free_port()
    client = kind("127.0.0.1", port, timeout=5)
    with pytest.raises(FocasConnectionError) as refused:
        await client.connect()
    with pytest.raises(FocasConnectionError) as caught:
        await client.read_status()
    assert str(caught.value) == (
        f"not connected to 127.0.0.1:{port} (connect() failed: {refused.value})"
    )


@pytest.mark.parametrize("kind", _CLIENTS)
async def test_a_call_on_a_closed_client_names_it_and_why(kind: Any) -> None:
    async with FocasServer(default_machine(sim_clock=ManualClock()), port=0) as server:
        host, port = server.addresses[0]
        client = kind(host, port, timeout=5)
        async with client:
            pass
        words = f"not connected to {host}:{port}: the client is closed (a closed client "
        for call in (client.read_status(), client.connect()):
            with pytest.raises(FocasConnectionError) as caught:
                await call
            assert str(caught.value).startswith(words)


# -- a fault the server refuses --------------------------------------------------------------------
@pytest.mark.parametrize(
    ("kind", "options", "why"),
    [
        ("error", {}, "an error fault's EW code is a nonzero -32768..32767, got 0"),
        (FaultKind.DELAY, {"arg": -5}, "a delay is 0..60000 ms, got -5"),
        ("drop", {"count": 0}, "a fault's count is 1..10000, got 0"),
        (99, {}, "no fault kind 99 (one of 1 DELAY, 2 ERROR, 3 DROP, 4 SPLIT)"),
        ("drop", {"scope": 7}, "no fault scope 7 (one of 0 CONNECTION, 1 MACHINE)"),
    ],
)
async def test_a_fault_the_server_refuses_says_why_as_the_command_line_does(
    both_clients: tuple[Machine, FocasClient, NativeClient], kind: Any, options: Any, why: str
) -> None:
    _, cnc, _ = both_clients
    with pytest.raises(CncError) as caught:
        await cnc.sim.inject_fault(kind, **options)
    assert caught.value.ew == EW.DATA
    assert str(caught.value) == f"EW_DATA (5): data error: sim_inject_fault: {why}"
    assert await cnc.sim.list_faults() == ()


# -- an alarm projection of something that is no client ---------------------------------------
@pytest.mark.parametrize("client", ["cnc", None, 5, default_machine()])
def test_a_projection_of_no_client_is_refused_naming_what_was_given(client: Any) -> None:
    with pytest.raises(TypeError) as caught:
        AlarmProjection(client)
    assert str(caught.value) == (f"client must be a FocasClient or a NativeClient, got {client!r}")


async def test_a_server_s_repr_counts_one_machine_as_one() -> None:
    server = FocasServer(default_machine(), port=0)
    assert repr(server) == "<FocasServer new 1 machine>"
    async with server:
        assert repr(server) == "<FocasServer serving 1 machine>"
    assert repr(FocasServer([default_machine(), default_machine()])) == (
        "<FocasServer new 2 machines>"
    )


@pytest.mark.parametrize(("typed", "shown"), [("1.5", "1.5"), (1.5, "1.5"), (" 1.50 ", "1.50")])
def test_the_page_refuses_decimals_for_an_integer_parameter_in_the_clients_words(
    typed: Any, shown: str
) -> None:
    machine = default_machine()
    with pytest.raises(ActionError) as caught:
        perform(Station(0, machine), "write_param", {"number": 1410, "value": typed})
    assert str(caught.value) == (
        f"value: parameter 1410 is not a real parameter: {shown} is no integer"
    )
    with pytest.raises(ValueError) as client:
        param_int(1410, typed if isinstance(typed, str) else Decimal(str(typed)))
    assert f"value: {client.value}" == str(caught.value)


# -- the machine's tools given a number of another type ---------------------------------------
@pytest.mark.parametrize("typed", ["1", 1.5, True])
def test_the_machine_s_tool_calls_refuse_a_number_of_another_type_as_a_type(typed: Any) -> None:
    machine = default_machine()
    calls: list[tuple[Callable[[], object], str]] = [
        (lambda: machine.tool_group(typed), "tool group"),
        (lambda: machine.tool_offsets(typed, 2, 0), "tool offset number"),
        (lambda: machine.tool_offsets(1, 2, typed), "tool offset type"),
        (lambda: machine.write_tool_offset(1, 0, typed), "tool offset 1 "),
        (lambda: machine.work_offsets(0, 1, typed), "axis"),
        (lambda: machine.write_work_offset(typed, None, [1, 2, 3]), "work offset number"),
        (lambda: machine.set_tool_life_count(1, typed), "tool group 1 count"),
    ]
    before = machine.state_digest()
    for call, what in calls:
        with pytest.raises(TypeError) as caught:
            call()
        assert str(caught.value).startswith(what)
        assert str(caught.value).endswith(f" must be an integer, got {typed!r}")
    assert machine.state_digest() == before


# -- reprs -------------------------------------------------------------------------------------
async def test_a_started_call_and_the_sim_control_show_what_they_are(
    both_clients: tuple[Machine, FocasClient, NativeClient],
) -> None:
    _, cnc, native = both_clients
    assert repr(cnc.sim) == f"<SimControl of {cnc!r}>"
    for client in (cnc, native):
        call = client.start_read_status()
        assert repr(call) in ("<StartedCall waiting>", "<StartedCall answered>")
        await call.result()
        assert repr(call) == "<StartedCall ended>"
        given_up = client.start_read_status()
        given_up.cancel()
        assert repr(given_up) == "<StartedCall ended>"
    for kind in _CLIENTS:
        failed = kind("127.0.0.1", 1).start_read_status()  # read by a task of its own
        assert repr(failed) in ("<StartedCall waiting>", "<StartedCall answered>")
        with pytest.raises(FocasConnectionError):
            await failed.result()
        assert repr(failed) == "<StartedCall ended>"


@pytest.mark.parametrize(
    ("before", "active", "words"),
    [
        ([], [], r"^before must be the alarms by key a previous call returned \(\{\} at first\)"),
        (None, [], r"^before must be .*, got None$"),
        ({}, "y", r"^active must be a list of ActiveAlarm, got 'y'$"),
        ({}, None, r"^active must be a list of ActiveAlarm, got None$"),
        ({}, [1], r"^active must be a list of ActiveAlarm, it holds 1$"),
    ],
)
def test_alarm_changes_names_what_is_no_alarm_list(before: Any, active: Any, words: str) -> None:
    with pytest.raises(TypeError, match=words):
        alarm_changes(before, active)


# -- a fleet past the last port ------------------------------------------------------------------
@pytest.mark.parametrize("option", ["port", "native_port"])
def test_a_fleet_past_the_last_port_is_named_as_the_command_line_names_it(option: str) -> None:
    machines = [Machine(f"m{i}") for i in range(3)]
    options: dict[str, Any] = {option: 65534}
    with pytest.raises(ValueError) as caught:
        FocasServer(machines, **options)
    assert str(caught.value) == (
        f"3 machines from {option}=65534 run past 65535 (the last machine would get port 65536)"
    )
