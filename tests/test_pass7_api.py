"""The Python API as a new user meets it, a seventh pass: wrong types and values given to the
clients, the simulator's controls, the machine and its manual clock are refused with the
right exception, naming the argument and the value given, before anything is sent or
changed."""

from __future__ import annotations

import math
from decimal import Decimal
from pathlib import Path
from typing import Any

import pytest

from focas_net import (
    EW,
    AlarmProjection,
    AutMode,
    CncError,
    FocasClient,
    FocasServer,
    MachineError,
    NativeClient,
    PositionKind,
    ProjectionMode,
    ReconnectPolicy,
    default_machine,
    load_machine,
    read_dynamic_all,
    read_status_all,
    read_status_paths_all,
)
from focas_net.gateway import (
    ConfigError,
    Gateway,
    GatewayConfig,
    MachineConfig,
    OpcUaSettings,
    OpcUaUser,
)
from focas_net.sim import Machine
from focas_net.sim.nc import ManualClock


# -- the clients -----------------------------------------------------------------------------
@pytest.mark.parametrize("kind", [True, None, 1.5, b"0", Decimal(1)])
async def test_a_position_kind_of_another_type_is_a_type_error_naming_kind(
    both_clients: tuple[Machine, FocasClient, NativeClient], kind: Any
) -> None:
    _, cnc, native = both_clients
    for client in (cnc, native):
        with pytest.raises(TypeError, match="position kind must be") as caught:
            await client.read_positions(kind)
        assert repr(kind) in str(caught.value)


@pytest.mark.parametrize("kind", [4, -1, 70000])
async def test_a_position_kind_number_out_of_range_names_the_kinds(
    both_clients: tuple[Machine, FocasClient, NativeClient], kind: int
) -> None:
    _, cnc, native = both_clients
    for client in (cnc, native):
        with pytest.raises(ValueError, match=rf"unknown position kind {kind} \(absolute"):
            await client.read_positions(kind)


def test_labelled_values_refuse_a_bool_or_another_type() -> None:
    with pytest.raises(TypeError, match=r"mode must be .* got True"):
        AutMode.parse_panel(True)
    with pytest.raises(TypeError, match=r"got 1.5"):
        AutMode.parse(1.5)  # type: ignore[arg-type]
    with pytest.raises(TypeError, match=r"position kind must be .* got None"):
        PositionKind.parse(None)  # type: ignore[arg-type]
    assert AutMode.parse_panel("7") is AutMode.THND  # digits as text stay a number


@pytest.mark.parametrize("mode", [True, False, 1.5, b"MEM", [1]])
async def test_set_panel_mode_of_another_type_is_refused_and_nothing_changes(
    both_clients: tuple[Machine, FocasClient, NativeClient], mode: Any
) -> None:
    machine, cnc, _ = both_clients
    before = machine.state_digest()
    with pytest.raises(TypeError, match="mode"):
        await cnc.sim.set_panel(mode)
    assert machine.state_digest() == before


@pytest.mark.parametrize("switch", ["pwe", "emergency"])
@pytest.mark.parametrize("value", ["on", 1.0, b"1", [True]])
async def test_a_panel_switch_of_another_type_is_a_type_error(
    both_clients: tuple[Machine, FocasClient, NativeClient], switch: str, value: Any
) -> None:
    _, cnc, _ = both_clients
    with pytest.raises(TypeError, match=rf"{switch} must be True, False or None"):
        await cnc.sim.set_panel(**{switch: value})
    with pytest.raises(ValueError, match=rf"{switch} must be True, False or None .* got 2"):
        two: dict[str, Any] = {switch: 2}
        await cnc.sim.set_panel(**two)


@pytest.mark.parametrize("what", ["count", "arg"])
@pytest.mark.parametrize("value", [True, "5", 1.5, None, b"1"])
async def test_inject_fault_count_and_arg_of_another_type_are_type_errors(
    both_clients: tuple[Machine, FocasClient, NativeClient], what: str, value: Any
) -> None:
    _, cnc, _ = both_clients
    with pytest.raises(TypeError, match=rf"{what} must be an integer, got {value!r}"):
        await cnc.sim.inject_fault("delay", **{what: value})
    assert await cnc.sim.list_faults() == ()


@pytest.mark.parametrize("msg", [None, 5, 1.5, b"OIL LOW", True])
async def test_raise_alarm_message_of_another_type_is_a_type_error(
    both_clients: tuple[Machine, FocasClient, NativeClient], msg: Any
) -> None:
    _, cnc, _ = both_clients
    with pytest.raises(TypeError, match=r"alarm message must be text \(str\), got"):
        await cnc.sim.raise_alarm("PS", 100, msg)
    assert await cnc.read_alarms() == ()


@pytest.mark.parametrize("width", [True, "4", 4.0, b"4"])
async def test_write_param_width_of_another_type_is_a_type_error_before_sending(
    both_clients: tuple[Machine, FocasClient, NativeClient], width: Any
) -> None:
    machine, cnc, native = both_clients
    before = machine.state_digest()
    for client in (cnc, native):
        with pytest.raises(TypeError, match=r"parameter width must be 1, 2, 4 or 8 .*got"):
            await client.write_param(6711, 5, width=width)
    assert machine.state_digest() == before


async def test_native_figure_kind_and_address_of_another_type_are_type_errors(
    both_clients: tuple[Machine, FocasClient, NativeClient],
) -> None:
    _, _, native = both_clients
    with pytest.raises(TypeError, match="servo figure must be"):
        await native.read_servo_figures(None)  # type: ignore[arg-type]
    with pytest.raises(ValueError, match="servo figure 3 is not"):
        await native.read_servo_figures(3)  # type: ignore[arg-type]
    with pytest.raises(TypeError, match="kind must be an integer, got '0'"):
        await native.read_spindle_meters("0")  # type: ignore[arg-type]
    with pytest.raises(TypeError, match="address must be a letter"):
        await native.read_modal_values(b"F")  # type: ignore[arg-type]


@pytest.mark.parametrize("given", ["1", -1, 0, math.nan, True])
async def test_native_calls_that_send_nothing_still_check_their_timeout(
    both_clients: tuple[Machine, FocasClient, NativeClient], given: Any
) -> None:
    _, _, native = both_clients
    error = (
        ValueError if isinstance(given, int | float) and not isinstance(given, bool) else TypeError
    )
    with pytest.raises(error, match="timeout"):
        await native.read_sysinfo(timeout=given)
    with pytest.raises(error, match="timeout"):
        await native.read_paths(timeout=given)


# -- the machine and its clock -----------------------------------------------------------------
@pytest.mark.parametrize("start", ["1", b"1", True, None, math.nan, math.inf, -math.inf])
def test_manual_clock_refuses_a_start_that_is_no_finite_number(start: Any) -> None:
    error = TypeError if not isinstance(start, float) else ValueError
    with pytest.raises(error, match=r"start"):
        ManualClock(start)


@pytest.mark.parametrize("seconds", ["1", b"1", True, None])
def test_manual_clock_steps_of_another_type_name_the_argument(seconds: Any) -> None:
    clock = ManualClock()
    with pytest.raises(TypeError, match=r"seconds must be a number of seconds, got"):
        clock.advance(seconds)
    with pytest.raises(TypeError, match=r"when must be a number of seconds, got"):
        clock.set(seconds)
    assert clock.now() == 0.0


@pytest.mark.parametrize("when", [math.nan, math.inf])
def test_manual_clock_set_to_no_finite_time_says_so(when: float) -> None:
    clock = ManualClock(5)
    with pytest.raises(ValueError, match=rf"a clock is set to a finite time, got {when}"):
        clock.set(when)
    with pytest.raises(ValueError, match=r"cannot go back from 5.0 to 1"):
        clock.set(1)


@pytest.mark.parametrize("clock", ["fast", None, 5, ManualClock])
def test_set_clock_of_no_clock_is_a_type_error(clock: Any) -> None:
    machine = default_machine(sim_clock=ManualClock())
    with pytest.raises(TypeError, match=r"clock must be a clock with now\(\)"):
        machine.set_clock(clock)


@pytest.mark.parametrize(
    ("field", "named"),
    [("axis_no", "axis"), ("alm_type", "alarm type"), ("alm_no", "alarm number")],
)
@pytest.mark.parametrize("value", [1.5, True, "3", None])
def test_machine_raise_alarm_refuses_a_number_of_another_type(
    field: str, named: str, value: Any
) -> None:
    """Named as the clients and the command line name the field."""
    machine = default_machine(sim_clock=ManualClock())
    args: dict[str, Any] = {"axis_no": 0, "alm_type": 3, "alm_no": 100}
    args[field] = value
    before = machine.state_digest()
    with pytest.raises(TypeError, match=rf"{named} must be an integer, got {value!r}"):
        machine.raise_alarm(args["axis_no"], args["alm_type"], args["alm_no"], "X")
    assert machine.state_digest() == before
    assert machine.active_alarms() == []


@pytest.mark.parametrize("number", [500.0, True, "500", None])
def test_machine_macro_number_of_another_type_is_a_type_error(number: Any) -> None:
    machine = default_machine(sim_clock=ManualClock())
    before = machine.state_digest()
    with pytest.raises(TypeError, match=r"macro variable number must be an integer, got"):
        machine.write_macro(number, Decimal(1))
    with pytest.raises(TypeError, match=r"macro variable number must be an integer, got"):
        machine.read_macro(number)
    assert machine.state_digest() == before


@pytest.mark.parametrize("letter", [None, 5, b"R", 1.5])
def test_machine_pmc_letter_of_another_type_is_a_type_error(letter: Any) -> None:
    machine = default_machine(sim_clock=ManualClock())
    with pytest.raises(TypeError, match=r"PMC area must be a letter"):
        machine.write_pmc(letter, 0, b"\x01")
    with pytest.raises(TypeError, match=r"PMC area must be a letter"):
        machine.read_pmc(letter, 0, 1)


@pytest.mark.parametrize("text", [None, 5, b"O1\nM30\n"])
def test_machine_program_text_of_another_type_is_a_type_error(text: Any) -> None:
    machine = default_machine(sim_clock=ManualClock())
    with pytest.raises(TypeError, match=r"a program must be text \(str\), got"):
        machine.store_program(text)


@pytest.mark.parametrize(
    ("call", "args"),
    [
        ("set_cnc_date", (2026, 2**70, 1)),
        ("set_cnc_date", (2026, 1, True)),
        ("set_cnc_time", (1.5, 0, 0)),
    ],
)
def test_machine_clock_setting_refuses_huge_and_other_types(
    call: str, args: tuple[Any, ...]
) -> None:
    machine = default_machine(sim_clock=ManualClock())
    with pytest.raises((TypeError, MachineError)):
        getattr(machine, call)(*args)


@pytest.mark.parametrize("value", [1.5, True, "7", None])
def test_machine_set_diag_refuses_a_value_of_another_type(value: Any) -> None:
    machine = default_machine(sim_clock=ManualClock())
    with pytest.raises(TypeError, match=r"diagnostic value must be an integer, got"):
        machine.set_diag(300, 1, value)


# -- constructors and helpers ------------------------------------------------------------------
@pytest.mark.parametrize(
    ("kwargs", "error", "words"),
    [
        ({"max_in_flight": "64"}, TypeError, "max_in_flight must be an integer, got '64'"),
        ({"max_in_flight": 1.5}, TypeError, "max_in_flight must be an integer, got 1.5"),
        ({"max_in_flight": True}, TypeError, "max_in_flight must be an integer, got True"),
        ({"max_frame": math.nan}, TypeError, "max_frame must be an integer, got nan"),
        ({"max_frame": 2**70}, ValueError, "max_frame 1180591620717411303424 is outside"),
        ({"ssl": "tls"}, TypeError, "ssl must be an ssl.SSLContext or None, got 'tls'"),
        ({"ssl": True}, TypeError, "ssl must be an ssl.SSLContext or None, got True"),
        ({"server_hostname": 5}, TypeError, "server_hostname must be a str or None, got 5"),
        ({"on_state_change": "print"}, TypeError, "on_state_change must be callable"),
    ],
)
def test_focas_client_constructor_refuses_wrong_types(
    kwargs: dict[str, Any], error: type[Exception], words: str
) -> None:
    with pytest.raises(error) as caught:
        FocasClient("127.0.0.1", 8193, **kwargs)
    assert words in str(caught.value)


@pytest.mark.parametrize("max_blocks", ["10", 10.0, True, None])
def test_native_client_max_blocks_of_another_type(max_blocks: Any) -> None:
    with pytest.raises(TypeError, match=rf"max_blocks must be an integer, got {max_blocks!r}"):
        NativeClient("127.0.0.1", 8193, max_blocks=max_blocks)
    with pytest.raises(TypeError, match="on_state_change must be callable"):
        NativeClient("127.0.0.1", 8193, on_state_change=5)  # type: ignore[arg-type]


def test_state_callbacks_are_checked_when_added_and_named_when_removed() -> None:
    cnc = FocasClient("127.0.0.1", 8193)
    with pytest.raises(TypeError, match=r"callback must be callable .* got None"):
        cnc.add_state_callback(None)  # type: ignore[arg-type]
    with pytest.raises(ValueError, match="is not a state callback of this client"):
        cnc.remove_state_callback(print)


@pytest.mark.parametrize(
    ("kwargs", "error", "words"),
    [
        ({"initial_delay": "1"}, TypeError, "initial_delay must be a number, got '1'"),
        ({"max_delay": None}, TypeError, "max_delay must be a number, got None"),
        ({"factor": True}, TypeError, "factor must be a number, got True"),
        ({"jitter": math.nan}, ValueError, "jitter must be a number, got nan (not a number)"),
        (
            {"stable_after": math.nan},
            ValueError,
            "stable_after must be a number, got nan (not a number)",
        ),
        ({"initial_delay": math.inf}, ValueError, "initial_delay must be finite, got inf"),
        ({"factor": math.inf}, ValueError, "factor must be finite, got inf"),
        ({"initial_delay": -1}, ValueError, "must not be negative: initial_delay -1"),
        ({"max_attempts": 2.5}, TypeError, "max_attempts must be an integer or None, got 2.5"),
        ({"max_attempts": 0}, ValueError, "max_attempts must be at least 1 (or None), got 0"),
    ],
)
def test_reconnect_policy_names_what_it_refuses(
    kwargs: dict[str, Any], error: type[Exception], words: str
) -> None:
    with pytest.raises(error) as caught:
        ReconnectPolicy(**kwargs)
    assert words in str(caught.value)


@pytest.mark.parametrize(
    ("kwargs", "error", "words"),
    [
        ({"mode": "history"}, ValueError, "unknown projection mode 'history' (one of 'active'"),
        ({"mode": 1}, TypeError, "mode must be a ProjectionMode, got 1"),
        ({"interval": "1"}, TypeError, "interval must be a number of seconds, got '1'"),
        ({"depth": 5.0}, TypeError, "depth must be an integer, got 5.0"),
        ({"max_failures": "3"}, TypeError, "max_failures must be an integer or None, got '3'"),
        ({"replay_history": "no"}, TypeError, "replay_history must be True or False, got 'no'"),
        ({"timeout": -1}, ValueError, "timeout must be positive, got -1"),
    ],
)
def test_alarm_projection_names_what_it_refuses(
    kwargs: dict[str, Any], error: type[Exception], words: str
) -> None:
    with pytest.raises(error) as caught:
        AlarmProjection(FocasClient("127.0.0.1", 8193), **kwargs)
    assert words in str(caught.value)
    assert AlarmProjection(FocasClient("127.0.0.1", 8193), "active+history").mode is (
        ProjectionMode.ACTIVE_PLUS_HISTORY
    )


async def test_reading_many_names_what_is_no_client(
    both_clients: tuple[Machine, FocasClient, NativeClient],
) -> None:
    _, cnc, native = both_clients
    with pytest.raises(TypeError, match=r"clients\[1\] must be a NativeClient, got <FocasClient"):
        await read_dynamic_all([native, cnc])  # type: ignore[list-item]
    with pytest.raises(TypeError, match=r"clients\[0\] must be a FocasClient or a NativeClient"):
        await read_status_all(["127.0.0.1"])  # type: ignore[list-item]
    with pytest.raises(TypeError, match="clients must be a list of clients, got 5"):
        await read_status_paths_all(5)  # type: ignore[arg-type]
    with pytest.raises(ValueError, match="timeout must be positive"):
        await read_status_all([cnc], timeout=0)
    assert len(await read_status_all([cnc, native])) == 2


@pytest.mark.parametrize(
    ("users", "words"),
    [
        ("admin", "opcua.users: got 'admin'; expected a tuple of OpcUaUser"),
        (None, "opcua.users: got None; expected a tuple of OpcUaUser"),
        (("admin",), "opcua.users[1]: got 'admin'; expected an OpcUaUser(name, password)"),
        ((OpcUaUser(5, "pw"),), "opcua.users[1].name: got 5; expected a user name"),  # type: ignore[arg-type]
        (
            (OpcUaUser("a", "x"), OpcUaUser("a", "y")),
            "opcua.users[2].name: user 'a' is given twice",
        ),
    ],
)
def test_opcua_settings_built_in_python_check_their_users(users: Any, words: str) -> None:
    with pytest.raises(ConfigError) as caught:
        OpcUaSettings(users=users).check()
    assert str(caught.value) == words


@pytest.mark.parametrize(
    ("text", "words"),
    [
        ("", "parameter 6711: not a number: '' (nothing typed)"),
        ("1e3", "parameter 6711: not a number: '1e3' (no exponent: write the digits)"),
        ("abc", "parameter 6711: not a number: 'abc'"),
    ],
)
async def test_write_param_text_no_number_is_refused_in_one_wording_on_both_clients(
    both_clients: tuple[Machine, FocasClient, NativeClient], text: str, words: str
) -> None:
    machine, cnc, native = both_clients
    machine.set_panel(mode=0, pwe=1)
    before = machine.state_digest()
    for client in (cnc, native):
        with pytest.raises(ValueError) as caught:
            await client.write_param(6711, text)
        assert str(caught.value) == words
    assert machine.state_digest() == before


@pytest.mark.parametrize(
    ("call", "args", "words"),
    [
        ("clear_alarms", (1.5,), "alm_type must be an integer, got 1.5"),
        ("clear_alarms", (-1, "100"), "alm_no must be an integer, got '100'"),
        ("read_param", (1320, "1"), "axis must be an integer, got '1'"),
        ("read_diag", ("300", 1), "number must be an integer, got '300'"),
        ("read_pmc", ("R", "0", 1), "PMC start address must be an integer, got '0'"),
        ("read_pmc", ("R", 0, 2.0), "PMC byte count must be an integer, got 2.0"),
        ("write_pmc", ("R", "0", b"\x01"), "PMC start address must be an integer, got '0'"),
        ("write_pmc", ("R", 0, "\x01"), "PMC data must be bytes, got '\\x01'"),
        ("active_alarms", (-1, "5"), "limit must be an integer, got '5'"),
        ("alarm_history", (2.0,), "depth must be an integer, got 2.0"),
    ],
)
def test_machine_numbers_of_another_type_are_named(
    call: str, args: tuple[Any, ...], words: str
) -> None:
    machine = default_machine(sim_clock=ManualClock())
    before = machine.state_digest()
    with pytest.raises(TypeError) as caught:
        getattr(machine, call)(*args)
    assert str(caught.value) == words
    assert machine.state_digest() == before


def test_machine_alarm_reads_take_any_bound_from_zero() -> None:
    machine = default_machine(sim_clock=ManualClock())
    machine.raise_alarm(0, 3, 100, "X")
    assert len(machine.active_alarms(limit=2**70)) == 1
    assert len(machine.alarm_history(2**70)) == 1
    with pytest.raises(ValueError, match="limit must be at least 0"):
        machine.active_alarms(limit=-1)
    with pytest.raises(ValueError, match="depth must be at least 0"):
        machine.alarm_history(-1)


@pytest.mark.parametrize(
    ("kwargs", "error", "words"),
    [
        ({"host": None}, TypeError, "host must be a str (an address or a name), got None"),
        ({"port": 1.5}, TypeError, "port must be an integer or None, got 1.5"),
        ({"port": True}, TypeError, "port must be an integer or None, got True"),
        ({"ports": b"\x07"}, TypeError, "ports must be a list of port numbers or None"),
        ({"ports": [0.0]}, TypeError, "ports[0] must be an integer, got 0.0"),
        ({"ssl": "tls"}, TypeError, "ssl must be an ssl.SSLContext or None, got 'tls'"),
        ({"max_frame": math.nan}, TypeError, "max_frame must be an integer, got nan"),
        ({"max_connections": math.inf}, TypeError, "max_connections must be an integer"),
        ({"grace_period": math.nan}, ValueError, "grace_period must be a number of seconds"),
        ({"idle_timeout": "300"}, TypeError, "idle_timeout must be a number of seconds"),
        ({"backlog": 2**70}, ValueError, "backlog 1180591620717411303424 is outside 0.."),
        ({"native_port": -1}, ValueError, "native_port -1 is outside 0..65535"),
        ({"native_max_body": None}, TypeError, "native_max_body must be an integer, got None"),
        ({"read_only": "yes"}, TypeError, "read_only must be True, False or None, got 'yes'"),
        ({"durable": 5}, TypeError, "durable must be callable or None, got 5"),
    ],
)
def test_focas_server_names_a_wrong_argument_before_touching_the_machine(
    kwargs: dict[str, Any], error: type[Exception], words: str
) -> None:
    machine = default_machine(sim_clock=ManualClock())
    before = machine.state_digest()
    kwargs.setdefault("port", 0)
    with pytest.raises(error) as caught:
        FocasServer(machine, **kwargs)
    assert words in str(caught.value)
    assert machine.state_digest() == before and not machine.read_only


@pytest.mark.parametrize("machines", ["m", [default_machine(), "m"], 5])
def test_focas_server_names_what_is_no_machine(machines: Any) -> None:
    with pytest.raises(TypeError, match=r"machines(\[1\])? must be a Machine"):
        FocasServer(machines, port=0)


@pytest.mark.parametrize(
    ("kwargs", "words"),
    [
        ({"name": None}, "a machine's name must be text (str), got None"),
        ({"name": b"m"}, "a machine's name must be text (str), got b'm'"),
        ({"param_password": 1234}, "a parameter password is text or bytes, got 1234"),
    ],
)
def test_default_machine_names_a_wrong_type(kwargs: dict[str, Any], words: str) -> None:
    with pytest.raises(TypeError) as caught:
        default_machine(**kwargs)
    assert str(caught.value) == words


async def test_a_16i_real_parameter_write_is_ew_length_in_plain_words() -> None:
    machine = load_machine(Path(__file__).parent / "data" / "fwlib_16i_machine.toml")
    machine.set_panel(mode=0, pwe=1)
    async with FocasServer(machine, port=0) as server:
        host, port = server.addresses[0]
        async with NativeClient(host, port) as native:
            with pytest.raises(CncError) as caught:
                await native.write_param(1420, Decimal("1.5"), axis=1)
    assert caught.value.ew == EW.LENGTH
    assert "1420 is 1 byte wide, not 8 (a value with decimals)" in str(caught.value)


async def test_an_unknown_pmc_area_is_named_with_the_areas_in_one_wording(
    both_clients: tuple[Machine, FocasClient, NativeClient],
) -> None:
    machine, cnc, native = both_clients
    words = "unknown PMC area 'Q' (one of X, Y, F, G, R, T, C, D, K, A, E)"
    for client in (cnc, native):
        with pytest.raises(ValueError) as caught:
            await client.read_pmc("Q", 0, 1)
        assert str(caught.value) == words
    with pytest.raises(ValueError) as from_machine:
        machine.pmc_area("Q")
    assert str(from_machine.value) == words


@pytest.mark.parametrize(
    ("kwargs", "words"),
    [
        ({"mode": True}, "mode must be an AutMode, its name or its number, got True"),
        ({"mode": 1.5}, "mode must be an AutMode, its name or its number, got 1.5"),
        ({"pwe": "on"}, "pwe must be True, False or None (unchanged), got 'on'"),
        ({"emergency": 1.0}, "emergency must be True, False or None (unchanged), got 1.0"),
    ],
)
def test_machine_set_panel_names_a_wrong_type(kwargs: dict[str, Any], words: str) -> None:
    machine = default_machine(sim_clock=ManualClock())
    before = machine.state_digest()
    with pytest.raises(TypeError) as caught:
        machine.set_panel(**kwargs)
    assert str(caught.value) == words
    assert machine.state_digest() == before
    machine.set_panel(mode=0, pwe=True, emergency=False)  # bools are switches
    assert machine.status().aut == 0


@pytest.mark.parametrize(
    ("kwargs", "error", "words"),
    [
        ({"config": "plant.toml"}, TypeError, "config must be a GatewayConfig (load_config(path)"),
        ({"sinks": 5}, TypeError, "sinks must be a list of sinks, got 5"),
        ({"sinks": [print]}, TypeError, "sinks[0] must be a sink (with described, online"),
        ({"policy": True}, TypeError, "policy must be a ReconnectPolicy, got True"),
        ({"clock": 5}, TypeError, "clock must be callable (time.time), got 5"),
        ({"config": GatewayConfig(machines=())}, ValueError, "needs at least one machine"),
    ],
)
def test_gateway_names_a_wrong_argument(
    kwargs: dict[str, Any], error: type[Exception], words: str
) -> None:
    kwargs.setdefault("config", GatewayConfig(machines=(MachineConfig("m", "127.0.0.1"),)))
    with pytest.raises(error) as caught:
        Gateway(**kwargs)
    assert words in str(caught.value)
    gateway = Gateway(GatewayConfig(machines=(MachineConfig("m", "127.0.0.1"),)))
    with pytest.raises(TypeError, match=r"sink must be a sink .* it has no described\(\)"):
        gateway.add_sink(5)  # type: ignore[arg-type]


async def test_started_call_on_done_refuses_what_is_not_callable(
    both_clients: tuple[Machine, FocasClient, NativeClient],
) -> None:
    _, cnc, native = both_clients
    for started in (cnc.start_read_status(), native.start_read_macro(500)):
        with pytest.raises(TypeError, match="on_done takes a callable with no arguments, got 5"):
            started.on_done(5)  # type: ignore[arg-type]
        await started.result()
