"""The Python API as a new user meets it, an eighth pass: the simulated machine, the packed
and the native client and the simulator's controls given wrong types and the edges of their
ranges, refused alike wherever the same rule applies, naming what was given."""

from __future__ import annotations

import asyncio
import re
from collections.abc import Awaitable, Callable
from decimal import Decimal
from pathlib import Path
from typing import Any

import pytest

from focas_net import (
    EW,
    AlarmProjection,
    CncError,
    FocasClient,
    FocasServer,
    FocasTimeoutError,
    MachineError,
    NativeClient,
    NativeServer,
    default_machine,
    load_machine,
)
from focas_net._refusals import axis_past
from focas_net.client._locks import KeyedLocks
from focas_net.protocol import alarm_code, alarm_type_of, encode_ew, ew_of_text
from focas_net.server import ListenError
from focas_net.sim import MAX_HISTORY_CAPACITY, Machine, machine_from_dict
from focas_net.sim.nc import ManualClock
from focas_net.web import Dashboard, stations_of

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"


def _ew(exc: BaseException) -> int:
    assert isinstance(exc, MachineError | CncError)
    return exc.ew


# -- the rapid override's F0 -------------------------------------------------------------------
@pytest.mark.parametrize(("typed", "percent"), [("F0", 0), (" f0 ", 0), ("f0", 0)])
async def test_the_rapid_override_takes_f0_from_python_as_the_command_line_does(
    both_clients: tuple[Machine, FocasClient, NativeClient], typed: str, percent: int
) -> None:
    machine, cnc, _ = both_clients
    machine.set_overrides(rapid=25)
    machine.set_overrides(rapid=typed)
    assert machine.overrides()[1] == percent
    machine.set_overrides(rapid=25)
    await cnc.sim.set_overrides(rapid=typed)
    assert machine.overrides()[1] == percent


@pytest.mark.parametrize("typed", ["F25", "F", "f 0", "F00"])
async def test_other_rapid_override_text_is_refused_alike_naming_it(
    both_clients: tuple[Machine, FocasClient, NativeClient], typed: str
) -> None:
    machine, cnc, _ = both_clients
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
    both_clients: tuple[Machine, FocasClient, NativeClient], kwargs: dict[str, Any], words: str
) -> None:
    machine, cnc, _ = both_clients
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
        lambda: machine.write_pmc(area, 0, b"", force=True),
        lambda: machine.read_pmc(area, 0, 0),
        lambda: machine.read_pmc(area, 0, -1),
    ):
        with pytest.raises(MachineError) as refused:
            op()
        assert refused.value.ew == EW.LENGTH
        assert "PMC byte count" in str(refused.value) and "one byte at least" in str(refused.value)
    assert machine.version == version  # nothing was written


async def test_a_pmc_range_of_no_bytes_is_refused_by_every_front_end(
    both_clients: tuple[Machine, FocasClient, NativeClient],
) -> None:
    _, cnc, native = both_clients
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
    both_clients: tuple[Machine, FocasClient, NativeClient],
) -> None:
    machine, cnc, _ = both_clients
    words = "axis 9 is outside 0..3: the path has 3 axes"
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
    with pytest.raises(MachineError, match=r"axis 2 is outside 0\.\.1: the path has 1 axis$"):
        machine.raise_alarm(2, 6, 411)


async def test_an_alarm_axis_is_named_with_the_count_of_the_path_it_was_raised_on() -> None:
    machine = load_machine(EXAMPLES / "lathe_2path.toml")
    async with FocasServer(machine, port=0) as server:
        host, port = server.addresses[0]
        async with FocasClient(host, port, timeout=5) as cnc:
            with pytest.raises(CncError) as refused:
                await cnc.sim.raise_alarm("SV", 411, axis_no=3, path=2)
            await cnc.sim.raise_alarm("SV", 411, axis_no=2, path=2)
    assert refused.value.detail.endswith("axis 3 is outside 0..2: the path has 2 axes")
    assert [a.axis_no for a in machine.active_alarms(path=2)] == [2]


# -- the machine's other numbers, switches and sequences ---------------------------------------
def _machine_calls(m: Machine, bad: Any) -> dict[str, Any]:
    """Calls of the machine with ``bad`` where a whole number goes, by the argument's name."""
    return {
        "program number": lambda: m.select_program(bad),
        "program number ": lambda: m.delete_program(bad),
        "program number  ": lambda: m.program_text(bad),
        "timer kind": lambda: m.timer(bad),
        "timer kind ": lambda: m.timer_ms(bad),
        "parameter number": lambda: m.param_item(bad),
        "diagnostic number": lambda: m.diag_item(bad),
        "macro number": lambda: m.macro_writable(bad),
        "rack": lambda: m.module_record(bad, 1),
        "slot": lambda: m.config_record(0, bad),
        "offset": lambda: m.read_config(0, 1, bad, 2),
        "length": lambda: m.read_config(0, 1, 0, bad),
        "number": lambda: m.read_diag(bad, 0),
        "axis": lambda: m.read_diag(410, bad),
    }


@pytest.mark.parametrize("bad", [1.5, "1", b"x", [], True, Decimal("1"), "\u0661"])
def test_a_machine_number_of_another_type_is_a_type_error_naming_it(bad: Any) -> None:
    m = default_machine()
    for what, call in _machine_calls(m, bad).items():
        with pytest.raises(TypeError) as refused:
            call()
        assert str(refused.value) == f"{what.strip()} must be an integer, got {bad!r}", what


@pytest.mark.parametrize("bad", [1.5, "yes", 1, 0, b"", None])
def test_a_machine_switch_is_true_or_false_not_anything_truthy(bad: Any) -> None:
    m = default_machine()
    version = m.version
    with pytest.raises(TypeError, match=rf"force must be True or False, got {bad!r}"):
        m.write_pmc("R", 0, b"\x01", force=bad)
    with pytest.raises(TypeError, match=rf"replace must be True or False, got {bad!r}"):
        m.store_program("O1234\nM30\n%", replace=bad)
    assert m.version == version and 1234 not in [p.number for p in m.program_directory()]
    if bad is not None:  # None leaves the repeat setting as it is
        with pytest.raises(TypeError, match=r"repeat must be True, False or None, got"):
            m.cycle_start(repeat=bad)


@pytest.mark.parametrize("kind", [True, False])
def test_a_current_folder_kind_is_no_bool(kind: bool) -> None:
    """A bool is no kind: a TypeError, as every number of another type given to the machine."""
    m = default_machine()
    for call in (lambda: m.current_folder(kind), lambda: m.set_current_folder("//CNC_MEM/", kind)):
        with pytest.raises(TypeError, match=rf"current folder kind must be an integer, got {kind}"):
            call()


@pytest.mark.parametrize("bad", [1.5, "1", b"x", None])
def test_tool_and_work_offset_writes_name_a_first_number_of_another_type(bad: Any) -> None:
    m = default_machine()
    # (a TypeError, as the machine refuses every number of another type: tests/test_confirm8_api.py)
    words = rf" must be an integer, got {re.escape(repr(bad))}"
    with pytest.raises(TypeError, match=rf"^tool offset number{words}"):
        m.write_tool_offsets(bad, 0, [1])
    with pytest.raises(TypeError, match=rf"^work offset number{words}"):
        m.write_work_offsets(bad, None, [[0, 0, 0]])


@pytest.mark.parametrize("bad", [5, 1.5, "123", b"\x01", None])
def test_offset_values_that_are_no_list_are_a_type_error(bad: Any) -> None:
    m = default_machine()
    with pytest.raises(TypeError, match=r"tool offset values must be a list or tuple"):
        m.write_tool_offsets(1, 0, bad)
    with pytest.raises(TypeError, match=r"work offset values must be a list or tuple"):
        m.write_work_offset(1, None, bad)
    with pytest.raises(TypeError, match=r"work offset rows must be a list or tuple"):
        m.write_work_offsets(1, None, bad)


def test_an_offset_write_of_no_values_is_refused_as_a_pmc_write_of_no_bytes() -> None:
    m = default_machine()
    version = m.version
    calls: tuple[Callable[[], object], ...] = (
        lambda: m.write_tool_offsets(1, 0, []),
        lambda: m.write_work_offsets(1, None, []),
        lambda: m.write_work_offset(1, None, ()),
    )
    for call in calls:
        with pytest.raises(MachineError) as refused:
            call()
        assert refused.value.ew == EW.LENGTH and "a write of no" in str(refused.value)
    assert m.version == version


async def test_the_packed_client_takes_replace_as_true_or_false(
    both_clients: tuple[Machine, FocasClient, NativeClient],
) -> None:
    machine, cnc, _ = both_clients
    with pytest.raises(TypeError, match="replace must be True or False, got 'no'"):
        await cnc.write_program("O1234\nM30\n%", replace="no")  # type: ignore[arg-type]
    assert 1234 not in [p.number for p in machine.program_directory()]


# -- building machines and servers -------------------------------------------------------------
@pytest.mark.parametrize(
    ("kwargs", "error", "words"),
    [
        ({"history_capacity": "250"}, TypeError, "history_capacity must be an integer, got '250'"),
        ({"history_capacity": 2.5}, TypeError, "history_capacity must be an integer, got 2.5"),
        ({"history_capacity": True}, TypeError, "history_capacity must be an integer, got True"),
        (
            {"history_capacity": 2**63},
            ValueError,
            f"history_capacity {2**63} is outside 1..100000 (entries)",
        ),
        ({"history_capacity": 0}, ValueError, "history_capacity 0 is outside 1..100000 (entries)"),
        ({"clock": 5}, TypeError, "clock must be callable (it returns the time), got 5"),
        ({"read_only": "no"}, TypeError, "read_only must be True or False, got 'no'"),
        ({"read_only": 1}, TypeError, "read_only must be True or False, got 1"),
        ({"control_enabled": 0}, TypeError, "control_enabled must be True or False, got 0"),
        ({"programs": b"O1"}, TypeError, "programs must be a list of program texts, got b'O1'"),
        ({"programs": 3}, TypeError, "programs must be a list of program texts, got 3"),
        ({"programs": [b"O1"]}, TypeError, "programs[0] must be a program's text (str), got b'O1'"),
        (
            {"programs": {"O1\nM30\n": 1}},
            TypeError,
            "programs must be a list of program texts, got {'O1\\nM30\\n': 1}",
        ),
        (
            {"programs": "O1000\nM30\n"},
            TypeError,
            "programs must be a list of program texts, got one text 'O1000\\nM30\\n': give it in "
            "a list",
        ),
    ],
)
def test_default_machine_names_an_argument_of_another_type(
    kwargs: dict[str, Any], error: type[Exception], words: str
) -> None:
    with pytest.raises(error) as refused:
        default_machine(**kwargs)
    assert str(refused.value) == words


def test_the_history_capacity_is_the_machine_files_range() -> None:
    assert MAX_HISTORY_CAPACITY == 100_000
    assert default_machine(history_capacity=MAX_HISTORY_CAPACITY).alarm_history() == ()
    machine = machine_from_dict({"machine": {"name": "m", "axes": ["X"], "history_capacity": 1}})
    assert machine.alarm_history() == ()


@pytest.mark.parametrize("path", [True, b"examples/machine.toml", 5, None])
def test_load_machine_names_a_path_of_another_type(path: Any) -> None:
    with pytest.raises(TypeError, match=r"a machine file's path must be a str or a Path, got "):
        load_machine(path)


@pytest.mark.parametrize(
    ("host", "words"),
    [
        ("localhost\n", "not a host name: 'localhost\\n'"),
        ("bad host!", "not a host name: 'bad host!'"),
        ("127.0.0.1:8193", "is a host and a port: give the host '127.0.0.1' and the port 8193"),
        ("\u0661", "holds a digit beyond ASCII"),
        ("", "empty host ''"),
    ],
)
async def test_a_server_checks_its_host_as_the_clients_and_the_command_line_do(
    host: str, words: str
) -> None:
    machine = default_machine()
    with pytest.raises(ValueError, match=re.escape(words)):
        FocasServer(machine, host=host, port=0)
    with pytest.raises(ValueError, match=re.escape(words)):
        NativeServer(machine, host)


async def test_a_server_takes_an_ipv6_address_in_brackets() -> None:
    try:
        async with FocasServer(default_machine(), host="[::1]", port=0) as server:
            assert server.addresses[0][0] == "::1"
    except ListenError as exc:  # a box without IPv6
        assert str(exc).startswith("cannot listen on [::1]:0: ")


async def test_a_port_that_cannot_be_bound_names_the_address_and_the_reason() -> None:
    async with FocasServer(default_machine(), port=0) as first:
        host, port = first.addresses[0]
        with pytest.raises(ListenError) as refused:
            async with FocasServer(default_machine(), port=port):
                pass
    assert str(refused.value) == f"cannot listen on {host}:{port}: address already in use"
    assert refused.value.where == f"{host}:{port}" and refused.value.errno is not None


@pytest.mark.parametrize(
    ("args", "kwargs", "words"),
    [
        ((None,), {}, "machine must be a Machine, got None"),
        (("m",), {}, "machine must be a Machine, got 'm'"),
        ((), {"version": "1"}, "version must be an integer, got '1'"),
        ((), {"version": 1.0}, "version must be an integer, got 1.0"),
        ((), {"max_body": "4096"}, "max_body must be an integer, got '4096'"),
        ((), {"max_body": None}, "max_body must be an integer, got None"),
    ],
)
def test_a_native_server_names_an_argument_of_another_type(
    args: tuple[Any, ...], kwargs: dict[str, Any], words: str
) -> None:
    with pytest.raises(TypeError) as refused:
        NativeServer(*(args or (default_machine(),)), **kwargs)
    assert str(refused.value) == words


# -- FOCAS/2 requests whose text does not fit ---------------------------------------------------
@pytest.mark.parametrize(
    ("call", "words"),
    [
        (
            lambda n: n.read_drive_usage("//CNC_MEM/USER/"),
            "cnc_rdpdf_inf: name '//CNC_MEM/USER/': printable ASCII of at most 11 characters",
        ),
        (
            lambda n: n.read_file_info("O\u00e9"),
            "cnc_rdpdf_prginf: name 'O\u00e9': printable ASCII of at most 243 characters",
        ),
        (
            lambda n: n.select_main_file("//CNC_MEM/" + "A" * 300),
            "cnc_pdf_slctmain: name '//CNC_MEM/AAAAAAAAAAAAAAAAAAAAAAAAAAAAAA': printable ASCII "
            "of at most 255 characters",
        ),
    ],
)
async def test_a_native_request_that_does_not_fit_names_the_function_not_its_repr(
    both_clients: tuple[Machine, FocasClient, NativeClient],
    call: Callable[[NativeClient], Awaitable[object]],
    words: str,
) -> None:
    _, _, native = both_clients
    with pytest.raises(ValueError) as refused:
        await call(native)
    assert str(refused.value) == words
    assert "Request(" not in str(refused.value)


# -- an axis beyond the path, on both clients ---------------------------------------------------
@pytest.mark.parametrize(
    ("call", "function"),
    [
        (lambda c: c.read_param(1420, axis=9), "cnc_rdparam"),
        (lambda c: c.read_param_real(1420, axis=9), "cnc_rdparam"),
        (lambda c: c.read_diag(300, axis=9), "cnc_diagnoss"),
        (lambda c: c.read_positions(axis=9), "cnc_rdposition"),
        (lambda c: c.write_param_bit(1005, 1, True, axis=9), "cnc_rdparam"),
    ],
)
async def test_an_axis_beyond_the_path_is_named_with_the_count_on_both_clients(
    both_clients: tuple[Machine, FocasClient, NativeClient],
    call: Callable[[Any], Awaitable[object]],
    function: str,
) -> None:
    machine, cnc, native = both_clients
    machine.set_panel(0, 1, 0)  # MDI, PWE on: a write is refused for its axis only
    details = []
    for client in (cnc, native):
        with pytest.raises(CncError) as refused:
            await call(client)
        assert refused.value.ew == EW.ATTRIB
        details.append(refused.value.detail)
    assert all(d.endswith(f": {axis_past(9, 3)}") for d in details), details
    # (both name FANUC's function: the packed cnc_rddiag's refusal is cnc_diagnoss's too)
    assert details[0] == details[1] == f"{function}: {axis_past(9, 3)}"


async def test_an_axis_given_to_an_item_of_no_axis_stays_as_the_cnc_answered(
    both_clients: tuple[Machine, FocasClient, NativeClient],
) -> None:
    _, cnc, native = both_clients
    for client in (cnc, native):
        with pytest.raises(CncError) as refused:
            await client.read_param(6711, axis=1)
        assert (refused.value.ew, refused.value.detail) == (EW.ATTRIB, "cnc_rdparam")


async def test_a_path_of_two_axes_counts_its_own(tmp_path: Path) -> None:
    machine = load_machine(EXAMPLES / "lathe_2path.toml")
    async with FocasServer(machine, port=0) as server:
        host, port = server.addresses[0]
        async with FocasClient(host, port, timeout=5) as cnc:
            with pytest.raises(CncError) as refused:
                await cnc.read_positions(axis=3, path=2)
            assert len((await cnc.read_positions(axis=2, path=2)).values) == 1
    assert refused.value.detail == f"cnc_rdposition: {axis_past(3, 2)}"


# -- the machine's sessions, messages, positions and macro words -------------------------------
@pytest.mark.parametrize("session", [None, "s", 1])
def test_a_session_of_another_type_is_named_before_the_lock_is_asked(session: Any) -> None:
    machine = default_machine(param_password="1234")
    machine.set_panel(0, 1, 0)  # MDI, PWE on: the write would reach the password
    words = (
        rf"session must be a Session \(machine.new_session\(\)\), got {re.escape(repr(session))}"
    )
    calls: tuple[Callable[[], object], ...] = (
        lambda: machine.unlock(session, "1234"),
        lambda: machine.write_param(session, 1420, 1, 5),
        lambda: machine.param_gate_closed(session),
    )
    for call in calls:
        with pytest.raises(TypeError, match=words):
            call()


@pytest.mark.parametrize("password", [1234, None, 12.5])
def test_an_unlock_with_a_password_of_another_type_is_a_type_error(password: Any) -> None:
    for machine in (default_machine(), default_machine(param_password="1234")):
        session = machine.new_session()
        with pytest.raises(TypeError, match="a parameter password is text or bytes, got "):
            machine.unlock(session, password)
        assert not session.unlocked


@pytest.mark.parametrize("messages", ["2001 HELLO", 5, [("A", 0, 0, 2001, "HELLO")]])
def test_external_messages_of_another_type_are_named(messages: Any) -> None:
    machine = default_machine()
    with pytest.raises(TypeError, match=r"messages(\[0\])? must be a(n| list of) ExternalMessage"):
        machine.set_external_messages(messages)


@pytest.mark.parametrize("kind", ["foo", "abs"])
def test_a_position_kind_the_machine_has_not_lists_the_kinds(kind: Any) -> None:
    with pytest.raises(MachineError, match=r"\(absolute, machine, relative, distance\)"):
        default_machine().positions(kind)
    with pytest.raises(TypeError, match="position kind must be text \\(str\\), got 0"):
        default_machine().positions(0)  # type: ignore[arg-type]
    with pytest.raises(TypeError, match="axis must be an integer, got '1'"):
        default_machine().positions("absolute", "1")  # type: ignore[arg-type]


@pytest.mark.parametrize(
    "value", [Decimal("NaN"), Decimal("Infinity"), Decimal("1E+12"), 10**12, Decimal("1E-10")]
)
async def test_a_macro_value_no_variable_holds_is_refused_in_one_wording(
    both_clients: tuple[Machine, FocasClient, NativeClient], value: Decimal | int
) -> None:
    machine, cnc, native = both_clients
    with pytest.raises(MachineError) as by_machine:
        machine.write_macro(500, value)
    for client in (cnc, native):
        with pytest.raises(ValueError) as by_client:
            await client.write_macro(500, value)
        assert str(by_client.value) == by_machine.value.detail
    # a finite Decimal in plain decimals, as it was typed (0.0000000001, not 1E-10)
    typed = format(value, "f") if isinstance(value, Decimal) and value.is_finite() else value
    assert by_machine.value.detail.startswith(f"#500: macro value {typed} ")


# -- reprs ---------------------------------------------------------------------------------------
def test_a_machines_repr_keeps_its_axis_names_apart() -> None:
    assert repr(default_machine()) == "Machine('focas-sim-0i', axes=('X', 'Y', 'Z'))"
    lathe = load_machine(EXAMPLES / "lathe_2path.toml")
    assert repr(lathe) == "Machine('twin-turret-lathe', paths=[('X1', 'Z1'), ('X2', 'Z2')])"


@pytest.mark.parametrize(
    ("mode", "shown"),
    [
        ("active_plus_history", "active+history"),
        ("ACTIVE_PLUS_HISTORY", "active+history"),
        (" Active+History ", "active+history"),
        ("active", "active"),
    ],
)
async def test_a_projection_takes_its_mode_by_value_or_name_and_says_what_it_follows(
    both_clients: tuple[Machine, FocasClient, NativeClient], mode: str, shown: str
) -> None:
    _, cnc, _ = both_clients
    projection = AlarmProjection(cnc, mode, interval=0.5)
    assert repr(projection) == f"<AlarmProjection {shown} every 0.5 s of {cnc!r}>"


async def test_a_dashboards_repr_is_its_address_and_its_machines() -> None:
    async with FocasServer([default_machine(), default_machine()], port=0) as server:
        dashboard = Dashboard(stations_of(server), port=0)
        assert repr(dashboard) == "<Dashboard http://127.0.0.1:0/ 2 machines>"
        async with dashboard:
            assert repr(dashboard) == f"<Dashboard {dashboard.url} 2 machines>"
            assert dashboard.address[1] != 0


# -- the protocol's helpers ------------------------------------------------------------------------
def given(value: object) -> Any:
    """``value`` as any type: the calls a type checker refuses, made as a user may make them."""
    return value


@pytest.mark.parametrize(
    ("call", "error", "words"),
    [
        (
            lambda: alarm_type_of(given(6)),
            TypeError,
            "an alarm type's name must be text (str), got 6",
        ),
        (lambda: ew_of_text(given(5)), TypeError, "an EW code as typed must be text (str), got 5"),
        (lambda: alarm_code(given("SV"), 1), TypeError, "alm_type must be an integer, got 'SV'"),
        (lambda: alarm_code(6, given(1.5)), TypeError, "alm_no must be an integer, got 1.5"),
        (lambda: encode_ew(2**20), ValueError, "EW code 1048576 is outside -32768..32767 (an i16)"),
        (lambda: encode_ew(given("5")), TypeError, "an EW code must be an integer, got '5'"),
        (
            lambda: machine_from_dict(given(None)),
            TypeError,
            "a machine file's data must be a mapping (parsed TOML), got None",
        ),
    ],
)
def test_the_protocols_helpers_name_an_argument_of_another_type(
    call: Callable[[], object], error: type[Exception], words: str
) -> None:
    with pytest.raises(error) as refused:
        call()
    assert str(refused.value) == words
    assert alarm_code(6, 411) == "SV0411" and encode_ew(-1) == b"\xff\xff"


def test_a_manual_clocks_repr_is_where_it_stands() -> None:
    clock = ManualClock(10)
    clock.advance(2.5)
    assert repr(clock) == "ManualClock(12.5)"


# -- a bit write that waited for another past its deadline ---------------------------------------
async def test_a_lock_not_freed_in_time_names_the_address_not_its_key() -> None:
    locks: KeyedLocks[tuple[int, int]] = KeyedLocks()
    passed = asyncio.get_running_loop().time() - 1.0  # a deadline already gone
    async with locks.hold((4, 100)):
        with pytest.raises(FocasTimeoutError) as waited:
            async with locks.hold((4, 100), passed, "R100"):
                pytest.fail("the lock is held")
    assert str(waited.value) == (
        "R100: another bit write of this client held it past the call's deadline "
        "(no request was sent)"
    )
    assert len(locks) == 0


@pytest.mark.parametrize(
    ("kwargs", "words"),
    [
        (
            {"port": 41001, "native_port": 41002},
            "port 41002 would be both the port of machine 1 and the native port of machine 0",
        ),
        (
            {"ports": [41011, 41011]},
            "port 41011 would be both the port of machine 0 and the port of machine 1",
        ),
    ],
)
def test_a_fleets_ports_that_repeat_are_refused_before_anything_listens(
    kwargs: dict[str, Any], words: str
) -> None:
    machines = [default_machine("m0"), default_machine("m1")]
    with pytest.raises(ValueError, match=re.escape(words) + ": each listens on a port of its own"):
        FocasServer(machines, **kwargs)


async def test_ports_of_zero_repeat_freely() -> None:
    machines = [default_machine("m0"), default_machine("m1")]
    async with FocasServer(machines, ports=[0, 0], native_port=0) as server:
        assert len({port for _, port in server.addresses}) == 2
