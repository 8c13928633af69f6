"""The Python API as a new user meets it, an eleventh pass: a PMC range of no bytes refused
in one rule's words by the machine and both clients, a PMC write past an area's end checked
before its first chunk where the client knows the area's size, and the arguments of the
public calls refused by kind (a type for a type, a range for a range) before anything is
sent."""

from __future__ import annotations

import inspect
from decimal import Decimal
from pathlib import Path
from typing import Any

import pytest

from focas_net import (
    EW,
    ChunkedWriteError,
    CncError,
    FocasClient,
    FocasServer,
    NativeClient,
    default_machine,
)
from focas_net._refusals import axis_past
from focas_net._typed import pmc_count_unfit
from focas_net.client import AlarmProjection
from focas_net.client._values import history_depth
from focas_net.protocol import PositionKind
from focas_net.sim import DataItem, Machine, MachineError, MacroRange, PathSpec

Both = tuple[Machine, FocasClient, NativeClient]


# -- a PMC range of no bytes: one rule, the machine's and the clients' -------------------------
@pytest.mark.parametrize("count", [0, -1, -40])
async def test_a_pmc_range_of_no_bytes_is_refused_in_one_rule_s_words(
    both_clients: Both, count: int
) -> None:
    """The machine said ``PMC byte count 0: a PMC range holds one byte at least`` where both
    clients said ``PMC byte count 0 is outside 1..65536``."""
    machine, cnc, native = both_clients
    words = pmc_count_unfit(count)
    assert words is not None and words.startswith(f"PMC byte count {count} is outside 1..65536")
    assert "one byte at least" in words
    with pytest.raises(MachineError) as refused:
        machine.read_pmc("R", 10, count)
    assert (refused.value.ew, refused.value.detail) == (EW.LENGTH, words)
    for client in (cnc, native):
        with pytest.raises(ValueError) as given:
            await client.read_pmc("R", 10, count)
        assert str(given.value) == words, type(client).__name__
    if count == 0:
        with pytest.raises(MachineError) as refused:
            machine.write_pmc("R", 10, b"")
        assert refused.value.detail == words
        for client in (cnc, native):
            with pytest.raises(ValueError) as given:
                await client.write_pmc("R", 10, b"")
            assert str(given.value) == words, type(client).__name__


# -- a chunked PMC write names why its first failing chunk was refused ------------------------
@pytest.mark.parametrize(
    ("client_kind", "area", "start", "size", "reason"),
    [
        ("packed", "R", 7000, 2000, "pmc_wrpmcrng: R7992..R8023 goes past the end of PMC area R"),
        ("native", "R", 6000, 2500, "pmc_wrpmcrng: R7420..R8499 goes past the end of PMC area R"),
        ("packed", "X", 0, 64, "pmc_wrpmcrng: PMC area X is write-protected (the machine drives"),
        ("sim", "X", 120, 40, "sim_set_pmc: X120..X151 goes past the end of PMC area X"),
    ],
)
async def test_a_chunked_pmc_write_names_why_its_chunk_was_refused(
    both_clients: Both, client_kind: str, area: str, start: int, size: int, reason: str
) -> None:
    """``ChunkedWriteError`` said ``PMC write to R failed (EW_NUMBER (3): data number / address
    range error: pmc_wrpmcrng); ...``, the code without its reason, where a write of one call
    names it (``R7990..R8009 goes past the end of PMC area R``)."""
    _, cnc, native = both_clients
    client = native if client_kind == "native" else cnc
    write = cnc.sim.set_pmc if client_kind == "sim" else client.write_pmc
    with pytest.raises(ChunkedWriteError) as failed:
        await write(area, start, bytes(size))
    assert reason in str(failed.value.cause)
    assert reason in str(failed.value)
    assert str(failed.value).count("goes past") <= 1  # named once, not once per wrapper


async def test_a_pmc_write_past_the_end_writes_what_the_docs_say(both_clients: Both) -> None:
    """docs/client.md, "A PMC write past the end of its area": the spans each client writes."""
    machine, cnc, native = both_clients
    expected = [
        (cnc, 7000, 2000, [(7000, 7991)], [(7992, 8999)]),
        (native, 7000, 2000, [], [(7000, 8999)]),
        (native, 6000, 2500, [(6000, 7419)], [(7420, 8499)]),
    ]
    for client, start, size, written, not_written in expected:
        machine.write_pmc("R", 6000, bytes(2000))
        with pytest.raises(ChunkedWriteError) as failed:
            await client.write_pmc("R", start, b"\x01" * size)
        assert (failed.value.written, failed.value.not_written) == (written, not_written)
        ones = machine.read_pmc("R", 6000, 2000).count(1)
        assert ones == sum(last - first + 1 for first, last in written)


# -- an alarm history depth of any size -----------------------------------------------------
@pytest.mark.parametrize("depth", [2**63, 10**20, 10**400], ids=["2**63", "10**20", "10**400"])
async def test_a_huge_alarm_history_depth_reads_the_250_the_history_holds(
    both_clients: Both, depth: int
) -> None:
    """``read_alarm_history(10**20)`` said ``history depth ... is outside
    -9223372036854775808..9223372036854775808``, a range no one gave, where the docs say more
    than 250 reads as 250."""
    machine, cnc, native = both_clients
    machine.raise_alarm(0, 1, 100, "ONE")
    for client in (cnc, native):
        history = await client.read_alarm_history(depth)
        assert [e.alm_no for e in history.entries] == [100], type(client).__name__


@pytest.mark.parametrize("depth", [-(2**63) - 1, -(10**20)])
def test_a_hugely_negative_history_depth_is_below_one(depth: int) -> None:
    with pytest.raises(ValueError, match=rf"^history depth {depth} is below 1 \("):
        history_depth(depth)


# -- the program folders: an EW_DATA names what the CNC has not ------------------------------
@pytest.mark.parametrize(
    ("call", "words"),
    [
        (lambda n: n.read_drive_usage("//USB/"), "cnc_rdpdf_inf: no drive '//USB/'"),
        (
            lambda n: n.read_folder("//CNC_MEM/NOPE/"),
            "cnc_rdpdf_alldir: no folder '//CNC_MEM/NOPE/'",
        ),
        (lambda n: n.read_subfolders("NOPE"), "cnc_rdpdf_subdir: no folder 'NOPE'"),
        (lambda n: n.read_folder_counts("5"), "cnc_rdpdf_subdirn: no folder '5'"),
        (lambda n: n.write_current_folder("5"), "cnc_wrpdf_curdir: no folder '5'"),
        (lambda n: n.read_file_info("O7777"), "cnc_rdpdf_prginf: no program file 'O7777'"),
        (lambda n: n.delete_file("5"), "cnc_pdf_del: no program file '5'"),
        (
            lambda n: n.select_main_file("//CNC_MEM/USER/PATH1/O7777"),
            "cnc_pdf_slctmain: no program file '//CNC_MEM/USER/PATH1/O7777' in the path's folder",
        ),
    ],
)
async def test_a_folder_call_refused_names_what_the_cnc_has_not(
    both_clients: Both, call: Any, words: str
) -> None:
    """``select_main_file("5")`` raised ``EW_DATA (5): data error: cnc_pdf_slctmain`` and
    nothing more, where the machine knows there is no such file."""
    _, _, native = both_clients
    with pytest.raises(CncError) as refused:
        await call(native)
    assert refused.value.ew == EW.DATA
    assert refused.value.detail == words


# -- a program stored twice ----------------------------------------------------------------
async def test_a_program_already_stored_is_named_with_how_to_replace_it(
    both_clients: Both,
) -> None:
    """``write_program`` of a number already stored raised ``EW_REJECT (13): execution
    rejected: cnc_download`` and nothing more, where the machine says ``program O9999 is
    already stored`` and the command line how to replace it."""
    _, cnc, _ = both_clients
    text = "%\nO9999 (TWICE)\nM30\n%\n"
    assert await cnc.write_program(text) == 9999
    with pytest.raises(CncError) as refused:
        await cnc.write_program(text)
    assert refused.value.ew == EW.REJECT
    assert refused.value.detail == (
        "cnc_download: program O9999 is already stored (replace=True replaces it)"
    )
    assert await cnc.write_program(text, replace=True) == 9999


# -- the machine's write_param and check_setting refuse another type by kind ----------------
@pytest.mark.parametrize(
    ("kwargs", "words"),
    [
        ({"width": "1"}, "parameter width must be an integer, got '1'"),
        ({"width": 1.0}, "parameter width must be an integer, got 1.0"),
        ({"width": True}, "parameter width must be an integer, got True"),
        ({"decimals": "3"}, "parameter decimals must be an integer, got '3'"),
        ({"decimals": 1.5}, "parameter decimals must be an integer, got 1.5"),
        ({"decimals": True}, "parameter decimals must be an integer, got True"),
    ],
)
def test_the_machine_refuses_a_parameter_width_or_decimals_of_another_type(
    kwargs: dict[str, object], words: str
) -> None:
    """``Machine.write_param(..., width="1")`` was EW_LENGTH ``parameter 20 is 1 bytes wide``
    (a range for a type), ``width=True`` was taken as 1 and ``decimals="3"`` was ignored."""
    machine = default_machine()
    machine.set_panel("MDI", pwe=True)
    version = machine.version
    with pytest.raises(TypeError) as refused:
        machine.write_param(machine.new_session(), 20, 0, 1, **kwargs)  # type: ignore[arg-type]
    assert str(refused.value) == words
    assert machine.version == version


def test_the_machine_names_a_parameter_s_width_in_bytes_of_one_byte() -> None:
    machine = default_machine()
    with pytest.raises(MachineError) as refused:
        machine.write_param(machine.new_session(), 20, 0, 1, width=2)
    assert refused.value.detail == "parameter 20 is 1 byte wide"


@pytest.mark.parametrize("number", [None, "0", 1.5, True])
def test_the_machine_refuses_a_setting_number_of_another_type_by_kind(number: object) -> None:
    """``check_setting(None)`` was EW_NUMBER ``no setting data None``; ``True`` a TypeError
    naming a parameter number."""
    with pytest.raises(TypeError, match=r"^setting number must be an integer, got "):
        default_machine().check_setting(number)  # type: ignore[arg-type]


@pytest.mark.parametrize("given", [2**63, 10**20])
def test_a_huge_max_in_flight_is_named_with_the_range_it_takes(given: int) -> None:
    """``FocasClient(max_in_flight=10**20)`` said ``... is outside
    -9223372036854775808..9223372036854775808`` where ``max_in_flight=0`` says ``1..32768``."""
    with pytest.raises(ValueError) as refused:
        FocasClient("127.0.0.1", max_in_flight=given)
    assert str(refused.value) == f"max_in_flight {given} is outside 1..32768"


# -- words that mislead ---------------------------------------------------------------------
@pytest.mark.parametrize("kind", ["3", " 0 "])
async def test_a_position_kind_as_digits_is_told_to_be_given_as_a_number(
    both_clients: Both, kind: str
) -> None:
    """``read_positions("3")`` said ``unknown position kind '3' (absolute, machine, relative,
    distance or 0..3)``: 3 is in 0..3, as text it is not taken."""
    _, cnc, native = both_clients
    for client in (cnc, native):
        with pytest.raises(ValueError) as refused:
            await client.read_positions(kind)
        assert str(refused.value) == (
            f"unknown position kind {kind!r} (absolute, machine, relative, distance, or 0..3 "
            "as an integer)"
        )


async def test_a_parameter_width_refused_names_the_parameter(both_clients: Both) -> None:
    """``write_param(20, 1, width=2)`` said ``cnc_wrparam: 20 is 1 byte wide, not 2``, where
    the machine says ``parameter 20 is 1 byte wide``."""
    _, cnc, native = both_clients
    for client in (cnc, native):
        with pytest.raises(CncError) as refused:
            await client.write_param(20, 1, width=2)
        assert refused.value.detail == "cnc_wrparam: parameter 20 is 1 byte wide, not 2"


# -- a panel mode as digits: the machine reads it as every other front end does ------------
@pytest.mark.parametrize(("typed", "aut"), [("5", 5), (" 3 ", 3), ("0", 0)])
async def test_the_machine_reads_a_panel_mode_typed_as_digits_as_the_client_does(
    both_clients: Both, typed: str, aut: int
) -> None:
    """``cnc.sim.set_panel("5")`` (and ``sim panel --mode 5``, the page) select JOG, where
    ``Machine.set_panel("5")`` was EW_DATA ``unknown mode '5'``."""
    machine, cnc, _ = both_clients
    machine.set_panel(typed)
    assert machine.status().aut == aut
    machine.set_panel("MEM")
    await cnc.sim.set_panel(typed)
    assert machine.status().aut == aut


@pytest.mark.parametrize("typed", ["--5", "-", "5-", "+5"])
def test_a_panel_mode_that_is_neither_a_name_nor_a_number_is_an_unknown_mode(typed: str) -> None:
    """``Machine.set_panel("--5")`` leaked Python's ``invalid literal for int()``."""
    with pytest.raises(MachineError) as refused:
        Machine("m").set_panel(typed)
    assert refused.value.detail.startswith(f"unknown mode {typed!r} (one of MDI, MEM, EDIT")


@pytest.mark.parametrize("mode", [True, 1.5, b"1"])
async def test_a_panel_mode_of_another_type_is_worded_alike(
    both_clients: Both, mode: object
) -> None:
    machine, cnc, _ = both_clients
    with pytest.raises(TypeError) as by_machine:
        machine.set_panel(mode)  # type: ignore[arg-type]
    with pytest.raises(TypeError) as by_client:
        await cnc.sim.set_panel(mode)  # type: ignore[arg-type]
    assert str(by_machine.value) == str(by_client.value)
    assert str(by_machine.value) == f"mode must be an AutMode, its name or its number, got {mode!r}"


@pytest.mark.parametrize("depth", ["5", 5.0, True])
async def test_the_alarm_projection_names_a_depth_of_another_type_as_the_clients_do(
    both_clients: Both, depth: object
) -> None:
    """``AlarmProjection(cnc, depth="5")`` said ``depth must be an integer`` and ``depth=0``
    ``history depth 0 is below 1``: one argument under two labels; the clients say ``history
    depth`` for both."""
    _, cnc, _ = both_clients
    with pytest.raises(TypeError) as by_projection:
        AlarmProjection(cnc, depth=depth)  # type: ignore[arg-type]
    with pytest.raises(TypeError) as by_client:
        await cnc.read_alarm_history(depth)  # type: ignore[arg-type]
    assert str(by_projection.value) == str(by_client.value)
    assert str(by_projection.value) == f"history depth must be an integer, got {depth!r}"


# -- a machine built with a macro value no variable holds ------------------------------------
@pytest.mark.parametrize(
    "value", [Decimal("1E+20"), 2**40, Decimal("1.0000000001"), Decimal("NaN")]
)
def test_a_machine_built_with_a_macro_value_no_variable_holds_says_why(value: object) -> None:
    """``Machine(..., macro_values={100: Decimal("1E+20")})`` said ``macro #100: value 1E+20
    invalid``, where a write of the same value says what a variable holds."""
    ranges = [MacroRange(100, 199)]
    written = Machine("m", macro_ranges=ranges)
    with pytest.raises(MachineError) as by_write:
        written.write_macro(100, value)  # type: ignore[arg-type]
    with pytest.raises(ValueError) as by_build:
        Machine("m", macro_ranges=ranges, macro_values={100: value})  # type: ignore[dict-item]
    assert str(by_build.value) == by_write.value.detail


# -- a path described with a value of another type -----------------------------------------
def _spec(**fields: Any) -> PathSpec:
    """A path of axis X with ``fields`` as given, of whatever type."""
    return PathSpec(**{"axes": ("X",), **fields})


@pytest.mark.parametrize(
    ("spec", "error", "words"),
    [
        (_spec(spindles="2"), TypeError, "path 1: spindles must be an integer, got '2'"),
        (
            _spec(spindles=None),
            TypeError,
            "path 1: spindles must be an integer, got None",
        ),
        (_spec(spindles=1.5), TypeError, "path 1: spindles must be an integer, got 1.5"),
        (
            _spec(spindles=True),
            TypeError,
            "path 1: spindles must be an integer, got True",
        ),
        (_spec(spindles=9), ValueError, "path 1: 1..8 spindles, got 9"),
        (_spec(kind=5), TypeError, "path 1: kind must be text (str), got 5"),
        (_spec(name=5), TypeError, "path 1: name must be text (str), got 5"),
        (_spec(name="A\nB"), ValueError, "path 1: name 'A\\nB': '\\n' is not printable"),
        (_spec(axes=5), TypeError, "path 1: axes must be a list of axis names, got 5"),
        (_spec(axes=None), TypeError, "path 1: axes must be a list of axis names, got None"),
    ],
)
def test_a_path_described_with_a_value_of_another_type_is_refused_by_kind(
    spec: PathSpec, error: type[Exception], words: str
) -> None:
    """``PathSpec(("X",), spindles="2")`` raised ``'<=' not supported between instances of
    'int' and 'str'``, ``PathSpec(5)`` ``'int' object is not iterable``, and a name of
    another type or with a line break was taken."""
    with pytest.raises(error) as refused:
        Machine("m", paths=[spec])
    assert str(refused.value) == words


@pytest.mark.parametrize(
    ("ports", "count", "words"),
    [
        ([0, 0], 1, "2 ports for 1 machine: ports names each machine's port, one each"),
        ([0], 2, "1 port for 2 machines: ports names each machine's port, one each"),
    ],
)
async def test_a_server_given_ports_not_one_a_machine_counts_them_in_words(
    ports: list[int], count: int, words: str
) -> None:
    """``FocasServer(machine, ports=[0, 0])`` said ``2 ports for 1 machines``."""
    machines = [default_machine() for _ in range(count)]
    with pytest.raises(ValueError) as refused:
        FocasServer(machines, ports=ports)
    assert str(refused.value) == words


def test_the_docs_say_connect_takes_the_client_s_timeout() -> None:
    """docs/client.md said every method takes ``timeout=``; ``connect(timeout=2)`` is a
    TypeError: the docs say ``connect()`` is given the client's."""
    docs = (Path(__file__).parents[1] / "docs" / "client.md").read_text()
    assert "`connect()` takes no\n`timeout=`" in docs
    native = (Path(__file__).parents[1] / "docs" / "native-client.md").read_text()
    assert "Every method but `connect()` takes `timeout=`" in native
    for cls in (FocasClient, NativeClient):
        assert "timeout" not in inspect.signature(cls.connect).parameters


# -- a work offset of an axis the path has not ----------------------------------------------
@pytest.mark.parametrize(
    ("call", "function"),
    [
        (lambda n: n.read_work_offset(1, 4), "cnc_rdzofs"),
        (lambda n: n.read_work_offsets(1, 2, 4), "cnc_rdzofsr"),
        (lambda n: n.write_work_offset(1, [5], 4), "cnc_wrzofs"),
    ],
)
async def test_a_work_offset_of_an_axis_the_path_has_not_is_named_before_sending(
    both_clients: Both, call: Any, function: str
) -> None:
    """``read_work_offset(1, axis=4)`` on a path of 3 axes raised ``EW_ATTRIB: cnc_rdzofs`` from
    the CNC, with no reason, where every other per-axis call of the native client names the
    axis and the count before anything is sent, as FANUC's library checks it."""
    machine, _, native = both_clients
    before = machine.state_digest()
    with pytest.raises(CncError) as refused:
        await call(native)
    assert refused.value.ew == EW.ATTRIB
    assert refused.value.detail == f"{function}: {axis_past(4, 3)}"
    assert machine.state_digest() == before


# -- a position kind named as the command line and the clients name it ----------------------
@pytest.mark.parametrize("kind", ["distance", "DISTANCE", "distance-to-go", "distance_to_go"])
async def test_the_machine_reads_the_distance_to_go_as_every_front_end_names_it(
    both_clients: Both, kind: str
) -> None:
    """``Machine.positions("distance")`` was EW_ATTRIB ``position kind 'distance': one of
    absolute, machine, relative, distance_to_go``, where ``position --kind distance`` and
    ``read_positions("distance")`` read it."""
    machine, cnc, _ = both_clients
    assert machine.positions(kind) == [("X", 0), ("Y", 0), ("Z", 0)]
    assert (await cnc.read_positions(kind)).kind is PositionKind.DISTANCE


def test_the_machine_names_the_position_kinds_as_the_clients_do() -> None:
    with pytest.raises(MachineError) as refused:
        default_machine().positions("abs")
    assert refused.value.detail == (
        "unknown position kind 'abs' (absolute, machine, relative, distance)"
    )


# -- the CNC's clock set to a date or a time of day that is none ----------------------------
@pytest.mark.parametrize(
    ("call", "words"),
    [
        (lambda m: m.set_cnc_date(2024, -1, 2), "month -1 is outside 1..12"),
        (lambda m: m.set_cnc_date(2024, 13, 2), "month 13 is outside 1..12"),
        (lambda m: m.set_cnc_date(2024, 1, 10**20), f"day {10**20} is outside 1..31 (2024-01)"),
        (lambda m: m.set_cnc_date(2023, 2, 29), "day 29 is outside 1..28 (2023-02)"),
        (lambda m: m.set_cnc_time(-1, 2, 3), "hour -1 is outside 0..23"),
        (lambda m: m.set_cnc_time(1, 60, 3), "minute 60 is outside 0..59"),
        (lambda m: m.set_cnc_time(1, 2, 10**20), f"second {10**20} is outside 0..59"),
    ],
)
def test_the_machine_names_the_field_of_a_date_or_time_that_is_none(call: Any, words: str) -> None:
    """``set_cnc_date(2024, -1, 2)`` said ``no date 2024--1-02`` and ``set_cnc_date(2024, 1,
    10**20)`` ``no date 2024-01100000000000000000000``: the field and its range are named."""
    machine = default_machine()
    with pytest.raises(MachineError) as refused:
        call(machine)
    assert (refused.value.ew, refused.value.detail) == (EW.DATA, words)


# -- an axis past the path's, worded alike by every call of the machine ---------------------
@pytest.mark.parametrize(
    "call",
    [
        lambda m: m.positions("absolute", 2),
        lambda m: m.work_offsets(1, 1, 2),
        lambda m: m.write_work_offset(1, 2, [0]),
        lambda m: m.read_param(1420, 2),
    ],
)
def test_an_axis_past_a_path_of_one_axis_is_worded_alike(call: Any) -> None:
    """``positions("absolute", 2)`` on a path of one axis said ``the path has 1 axes``, and
    ``work_offsets(1, 1, 2)`` ``axis 2 is outside 1..1`` without the count's words."""
    machine = Machine("m", paths=[PathSpec(("X",))], params=[DataItem(1420, 4, True)])
    with pytest.raises(MachineError) as refused:
        call(machine)
    assert (refused.value.ew, refused.value.detail) == (
        EW.ATTRIB,
        "axis 2 is outside 1..1: the path has 1 axis",
    )
