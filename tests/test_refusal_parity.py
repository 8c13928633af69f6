"""One refusal, one reason, on every front end: each case below is a machine set-up and one
action the machine refuses, driven through every front end that offers the action (the
machine itself, the packed ``FocasClient`` and the ``NativeClient`` against the machine served,
the page's action, the command line, the gateway's write methods on either transport); each
front end's words must carry the reason in the same words, from one source (the shared
functions of ``focas_net/_refusals.py`` and ``focas_net/_typed.py``), whatever its own lead.

The wire carries a refusal's EW code only: a client rebuilds the reason from what the call
named (and what it can read of the CNC), as the command line and the gateway do. Where a
front end cannot know the reason, :data:`CANNOT_KNOW` says why and what it says instead.
"""

from __future__ import annotations

from collections.abc import Awaitable, Callable, Mapping
from dataclasses import dataclass
from decimal import Decimal
from pathlib import Path
from typing import Any, Final, Literal

import pytest
from cli_support import at, fails
from gateway_support import gated_writer
from support import serving, with_both_clients
from web_support import page_refusal

from focas_net._refusals import (
    NO_CONTROL,
    PARAM_GATE,
    READ_ONLY_MACHINE,
    SEARCH,
    axis_misfit,
    axis_past,
    cycle_refusal,
    mode_refusal,
    no_item,
    no_path,
    param_refusal,
    parts_refusal,
    pmc_protected,
    pmc_refusal,
    program_busy,
    program_missing,
    program_refusal,
    select_busy,
    system_read_only,
)
from focas_net._typed import (
    WRONG_PASSWORD,
    alarm_axis_unfit,
    alarm_key_unfit,
    alarm_text_unfit,
    macro_unfit,
    override_unfit,
)
from focas_net.cli import EXIT_CNC, EXIT_USAGE
from focas_net.errors import EW
from focas_net.gateway import WriteGates
from focas_net.gateway.writer import GatedWriter
from focas_net.protocol import FaultKind, FaultScope
from focas_net.server.faults import fault_refusal
from focas_net.sim import Machine, MachineError, default_machine, machine_from_dict
from focas_net.sim.default import DEMO_PROGRAM
from focas_net.sim.nc import ManualClock
from focas_net.web import Station

#: The machine's words of the write gate closed by PWE.
PWE_OFF: Final = "parameter write enable (PWE) is off"

#: The front ends, each a way to the same machine.
FRONTS: Final = ("machine", "packed", "native", "page", "cli", "gateway-packed", "gateway-native")

#: Every write the gateway's gates can allow.
_GATES: Final = WriteGates(
    macros=((-32768, 32767),),
    params=((0, 32767),),
    pmc=tuple((a, 0, 65535) for a in "XYFGRTCDKAE"),
)


def _as_is(machine: Machine) -> None:
    """No set-up: the default machine as built."""


def _read_only_600() -> Machine:
    """A machine whose file makes #600..#699 read-only."""
    ranges = [{"first": 600, "last": 699, "writable": False}]
    return machine_from_dict(
        {"machine": {"name": "m", "axes": ["X", "Z"]}, "macros": {"ranges": ranges}}
    )


def _running() -> Machine:
    """O0001 running (on a clock that stands still), O0002 stored."""
    machine = default_machine(sim_clock=ManualClock(), programs=(DEMO_PROGRAM, "O0002\nM30\n"))
    machine.cycle_start()
    return machine


def _alarm_on(machine: Machine) -> None:
    """PS0100 active."""
    machine.raise_alarm(0, 2, 100)


def _mdi_pwe(machine: Machine) -> None:
    """MDI mode and PWE on: the parameter write gate open."""
    machine.set_panel(0, 1, 0)


@dataclass(frozen=True)
class Case:
    """A machine set-up and one action, as each front end offers it (None: it does not)."""

    reason: str
    machine: Callable[[Machine], object] | None
    client: Callable[[Any], Awaitable[object]] | None = None  # (either client)
    native: bool = True  # whether the NativeClient offers the client's call
    page: tuple[str, Mapping[str, Any]] | None = None
    cli: tuple[str, ...] | None = None
    gateway: Callable[[GatedWriter], Awaitable[None]] | None = None
    setup: Callable[[Machine], None] = _as_is
    build: Callable[[], Machine] = default_machine
    program: str = ""  # the text of the file a ``{file}`` argument of ``cli`` names
    cli_exit: int = EXIT_CNC  # EXIT_USAGE: refused by the command line before it connects


def _session_write(number: int, value: int, axis: int = 0) -> Callable[[Machine], object]:
    return lambda m: m.write_param(m.new_session(), number, axis, value)


CASES: Final[Mapping[str, Case]] = {
    "param-out-of-range": Case(
        param_refusal(EW.DATA, 6711, 1_000_000_000) or "",
        _session_write(6711, 1_000_000_000),
        lambda c: c.write_param(6711, 1_000_000_000),
        page=("write_param", {"number": 6711, "value": 1_000_000_000}),
        cli=("param", "set", "6711", "1000000000"),
        gateway=lambda g: g.write_param("m1", 6711, 1_000_000_000, 0),
        setup=_mdi_pwe,
    ),
    "param-pwe-off": Case(
        f"{PARAM_GATE}: {PWE_OFF}",
        _session_write(6711, 5),
        lambda c: c.write_param(6711, 5),
        page=("write_param", {"number": 6711, "value": 5}),
        cli=("param", "set", "6711", "5"),
        gateway=lambda g: g.write_param("m1", 6711, 5, 0),
        setup=lambda m: m.set_panel(0, 0, 0),
    ),
    "param-password-locked": Case(
        f"{PARAM_GATE}: the parameter password is not unlocked on this connection",
        _session_write(6711, 5),
        lambda c: c.write_param(6711, 5),
        page=("write_param", {"number": 6711, "value": 5}),
        cli=("param", "set", "6711", "5"),
        gateway=lambda g: g.write_param("m1", 6711, 5, 0),
        setup=_mdi_pwe,
        build=lambda: default_machine(param_password="1234"),
    ),
    "param-no-such": Case(
        no_item("parameter", 1),
        _session_write(1, 5),
        lambda c: c.write_param(1, 5),
        page=("write_param", {"number": 1, "value": 5}),
        cli=("param", "set", "1", "5"),
        gateway=lambda g: g.write_param("m1", 1, 5, 0),
        setup=_mdi_pwe,
    ),
    "param-width-not-its-own": Case(
        "parameter 6711 is 4 bytes wide",
        lambda m: m.write_param(m.new_session(), 6711, 0, 5, width=2),
        lambda c: c.write_param(6711, 5, width=2),
        cli=("param", "set", "6711", "5", "--width", "2"),
        setup=_mdi_pwe,
    ),
    "param-axis-past-the-path": Case(
        axis_past(9, 3),
        _session_write(1420, 5, 9),
        lambda c: c.write_param(1420, 5, axis=9),
        page=("write_param", {"number": 1420, "value": 5, "axis": 9}),
        cli=("param", "set", "1420", "5", "--axis", "9"),
        gateway=lambda g: g.write_param("m1", 1420, 5, 9),
        setup=_mdi_pwe,
    ),
    "param-axis-missing": Case(
        axis_misfit("parameter", 1420, 0),
        _session_write(1420, 5),
        lambda c: c.write_param(1420, 5),
        page=("write_param", {"number": 1420, "value": 5}),
        cli=("param", "set", "1420", "5"),
        gateway=lambda g: g.write_param("m1", 1420, 5, 0),
        setup=_mdi_pwe,
    ),
    "param-axis-given": Case(
        axis_misfit("parameter", 6711, 1),
        _session_write(6711, 5, 1),
        lambda c: c.write_param(6711, 5, axis=1),
        page=("write_param", {"number": 6711, "value": 5, "axis": 1}),
        cli=("param", "set", "6711", "5", "--axis", "1"),
        gateway=lambda g: g.write_param("m1", 6711, 5, 1),
        setup=_mdi_pwe,
    ),
    "macro-read-only-system": Case(
        system_read_only(5001) or "",
        lambda m: m.write_macro(5001, Decimal(1)),
        lambda c: c.write_macro(5001, 1),
        page=("write_macro", {"number": 5001, "value": 1}),
        cli=("macro", "set", "5001", "1"),
        gateway=lambda g: g.write_macro("m1", 5001, Decimal(1), 1),
    ),
    "macro-read-only-by-file": Case(
        "macro variable #600 is read-only",
        lambda m: m.write_macro(600, Decimal(1)),
        lambda c: c.write_macro(600, 1),
        page=("write_macro", {"number": 600, "value": 1}),
        cli=("macro", "set", "600", "1"),
        gateway=lambda g: g.write_macro("m1", 600, Decimal(1), 1),
        build=_read_only_600,
    ),
    "macro-no-such": Case(
        no_item("macro variable", "#50"),
        lambda m: m.write_macro(50, Decimal(1)),
        lambda c: c.write_macro(50, 1),
        page=("write_macro", {"number": 50, "value": 1}),
        cli=("macro", "set", "50", "1"),
        gateway=lambda g: g.write_macro("m1", 50, Decimal(1), 1),
    ),
    "macro-parts-negative": Case(
        parts_refusal(3901, -1),
        lambda m: m.write_macro(3901, Decimal(-1)),
        lambda c: c.write_macro(3901, -1),
        page=("write_macro", {"number": 3901, "value": -1}),
        cli=("macro", "set", "3901", "-1"),
        gateway=lambda g: g.write_macro("m1", 3901, Decimal(-1), 1),
    ),
    "macro-parts-vacated": Case(
        parts_refusal(3901, None),
        lambda m: m.write_macro(3901, None),
        lambda c: c.sim.vacate_macro(3901),
        native=False,
        page=("write_macro", {"number": 3901, "value": None}),
        cli=("macro", "clear", "3901"),
    ),
    "macro-path-missing": Case(
        no_path(3, 1),
        lambda m: m.write_macro(100, Decimal(1), path=3),
        lambda c: c.write_macro(100, 1, path=3),
        page=("write_macro", {"number": 100, "value": 1, "path": 3}),
        cli=("macro", "set", "100", "1", "--path", "3"),
        gateway=lambda g: g.write_macro("m1", 100, Decimal(1), 3),
    ),
    "pmc-past-the-area": Case(
        pmc_refusal(EW.NUMBER, "R", 8000, 8000) or "",
        lambda m: m.write_pmc("R", 8000, b"\x01"),
        lambda c: c.write_pmc("R", 8000, b"\x01"),
        page=("pmc_bit", {"area": "R", "address": 8000, "bit": 0, "value": 1}),
        cli=("pmc", "write", "R", "8000", "1"),
        gateway=lambda g: g.write_pmc("m1", "R", 8000, 1),
    ),
    "pmc-bit-past-the-area": Case(
        pmc_refusal(EW.NUMBER, "R", 8000, 8000) or "",
        lambda m: m.read_pmc("R", 8000, 1),
        lambda c: c.write_pmc_bit("R", 8000, 0, True),
        page=("pmc_bit", {"area": "R", "address": 8000, "bit": 0, "value": 1}),
        cli=("pmc", "bit", "R", "8000.0", "1"),
    ),
    "pmc-driven-area": Case(
        pmc_protected("X"),
        lambda m: m.write_pmc("X", 0, b"\x01"),
        lambda c: c.write_pmc("X", 0, b"\x01"),
        cli=("pmc", "write", "X", "0", "1"),
        gateway=lambda g: g.write_pmc("m1", "X", 0, 1),
    ),
    "pmc-no-such-area": Case(
        pmc_refusal(EW.NOOPT, "E", 0, 0) or "",
        lambda m: m.write_pmc("E", 0, b"\x01"),
        lambda c: c.write_pmc("E", 0, b"\x01"),
        page=("pmc_bit", {"area": "E", "address": 0, "bit": 0, "value": 1}),
        cli=("pmc", "write", "E", "0", "1"),
        gateway=lambda g: g.write_pmc("m1", "E", 0, 1),
    ),
    "program-without-o-line": Case(
        program_refusal(EW.DATA, "G01 X1\nM30\n") or "",
        lambda m: m.store_program("G01 X1\nM30\n"),
        lambda c: c.write_program("G01 X1\nM30\n"),
        native=False,
        cli=("program", "load", "{file}"),
        program="G01 X1\nM30\n",
    ),
    "program-select-missing": Case(
        program_missing(1234),
        lambda m: m.select_program(1234),
        lambda c: c.select_program(1234),
        native=False,
        page=("select_program", {"number": "O1234"}),
        cli=("program", "select", "1234"),
    ),
    "read-only-param": Case(
        READ_ONLY_MACHINE,
        _session_write(6711, 5),
        lambda c: c.write_param(6711, 5),
        page=("write_param", {"number": 6711, "value": 5}),
        cli=("param", "set", "6711", "5"),
        gateway=lambda g: g.write_param("m1", 6711, 5, 0),
        build=lambda: default_machine(read_only=True),
    ),
    "read-only-macro": Case(
        READ_ONLY_MACHINE,
        lambda m: m.write_macro(500, Decimal(1)),
        lambda c: c.write_macro(500, 1),
        page=("write_macro", {"number": 500, "value": 1}),
        cli=("macro", "set", "500", "1"),
        gateway=lambda g: g.write_macro("m1", 500, Decimal(1), 1),
        build=lambda: default_machine(read_only=True),
    ),
    "param-path-missing": Case(
        no_path(3, 1),
        lambda m: m.write_param(m.new_session(), 6711, 0, 5, path=3),
        lambda c: c.write_param(6711, 5, path=3),
        page=("write_param", {"number": 6711, "value": 5, "path": 3}),
        cli=("param", "set", "6711", "5", "--path", "3"),
        setup=_mdi_pwe,
    ),
    "macro-clock": Case(
        system_read_only(3011) or "",
        lambda m: m.write_macro(3011, Decimal(20240101)),
        lambda c: c.write_macro(3011, 20240101),
        page=("write_macro", {"number": 3011, "value": 20240101}),
        cli=("macro", "set", "3011", "20240101"),
        gateway=lambda g: g.write_macro("m1", 3011, Decimal(20240101), 1),
    ),
    "macro-clear-read-only-system": Case(
        system_read_only(5001) or "",
        lambda m: m.write_macro(5001, None),
        lambda c: c.sim.vacate_macro(5001),
        native=False,
        page=("write_macro", {"number": 5001, "value": None}),
        cli=("macro", "clear", "5001"),
    ),
    "pmc-read-only": Case(
        READ_ONLY_MACHINE,
        lambda m: m.write_pmc("R", 0, b"\x01"),
        lambda c: c.write_pmc("R", 0, b"\x01"),
        page=("pmc_bit", {"area": "R", "address": 0, "bit": 0, "value": 1}),
        cli=("pmc", "write", "R", "0", "1"),
        gateway=lambda g: g.write_pmc("m1", "R", 0, 1),
        build=lambda: default_machine(read_only=True),
    ),
    "program-stored-twice": Case(
        program_refusal(EW.REJECT, DEMO_PROGRAM) or "",
        lambda m: m.store_program(DEMO_PROGRAM),
        lambda c: c.write_program(DEMO_PROGRAM),
        native=False,
        cli=("program", "load", "{file}"),
        program=DEMO_PROGRAM,
    ),
    "program-delete-missing": Case(
        program_missing(1234),
        lambda m: m.delete_program(1234),
        lambda c: c.delete_program(1234),
        native=False,
        cli=("program", "delete", "1234"),
    ),
    "program-delete-running": Case(
        program_busy(1),
        lambda m: m.delete_program(1),
        lambda c: c.delete_program(1),
        native=False,
        cli=("program", "delete", "1"),
        build=_running,
    ),
    "program-load-running": Case(
        program_refusal(EW.BUSY, DEMO_PROGRAM) or "",
        lambda m: m.store_program(DEMO_PROGRAM, replace=True),
        lambda c: c.write_program(DEMO_PROGRAM, replace=True),
        native=False,
        cli=("program", "load", "{file}", "--replace"),
        program=DEMO_PROGRAM,
        build=_running,
    ),
    "program-select-while-running": Case(
        select_busy(2),
        lambda m: m.select_program(2),
        lambda c: c.select_program(2),
        native=False,
        page=("select_program", {"number": "O0002"}),
        cli=("program", "select", "2"),
        build=_running,
    ),
    "program-select-in-jog": Case(
        mode_refusal(SEARCH, "MEM or EDIT", "JOG"),
        lambda m: m.select_program(1),
        lambda c: c.select_program(1),
        native=False,
        page=("select_program", {"number": "O0001"}),
        cli=("program", "select", "1"),
        setup=lambda m: m.set_panel(5, None, None),
    ),
    "program-load-read-only": Case(
        READ_ONLY_MACHINE,
        lambda m: m.store_program(DEMO_PROGRAM, replace=True),
        lambda c: c.write_program(DEMO_PROGRAM, replace=True),
        native=False,
        cli=("program", "load", "{file}", "--replace"),
        program=DEMO_PROGRAM,
        build=lambda: default_machine(read_only=True),
    ),
    "cycle-start-in-edit": Case(
        cycle_refusal(EW.MODE, mode="EDIT") or "",
        lambda m: m.cycle_start(),
        lambda c: c.sim.cycle_start(),
        native=False,
        page=("cycle", {"action": "start"}),
        cli=("sim", "cycle", "start"),
        setup=lambda m: m.set_panel(3, None, None),
    ),
    "cycle-start-emergency": Case(
        cycle_refusal(EW.ALARM, emergency=True) or "",
        lambda m: m.cycle_start(),
        lambda c: c.sim.cycle_start(),
        native=False,
        page=("cycle", {"action": "start"}),
        cli=("sim", "cycle", "start"),
        setup=lambda m: m.set_panel(None, None, 1),
    ),
    "cycle-start-alarm": Case(
        cycle_refusal(EW.ALARM, emergency=False) or "",
        lambda m: m.cycle_start(),
        lambda c: c.sim.cycle_start(),
        native=False,
        page=("cycle", {"action": "start"}),
        cli=("sim", "cycle", "start"),
        setup=_alarm_on,
    ),
    "cycle-start-no-program": Case(
        cycle_refusal(EW.DATA) or "",
        lambda m: m.cycle_start(),
        lambda c: c.sim.cycle_start(),
        native=False,
        page=("cycle", {"action": "start"}),
        cli=("sim", "cycle", "start"),
        build=lambda: default_machine(programs=()),
    ),
    "cycle-start-path-missing": Case(
        no_path(2, 1),
        lambda m: m.cycle_start(path=2),
        lambda c: c.sim.cycle_start(path=2),
        native=False,
        page=("cycle", {"action": "start", "path": 2}),
        cli=("sim", "cycle", "start", "--path", "2"),
    ),
    "alarm-clear-path-missing": Case(
        no_path(2, 1),
        lambda m: m.clear_alarms(path=2),
        lambda c: c.sim.clear_alarms(path=2),
        native=False,
        page=("clear_alarms", {"path": 2}),
        cli=("sim", "clear", "--path", "2"),
    ),
    "overrides-path-missing": Case(
        no_path(2, 1),
        lambda m: m.set_overrides(100, None, None, path=2),
        lambda c: c.sim.set_overrides(feed=100, path=2),
        native=False,
        page=("overrides", {"feed": 100, "path": 2}),
        cli=("sim", "override", "--feed", "100", "--path", "2"),
    ),
    "panel-read-only": Case(
        READ_ONLY_MACHINE,
        lambda m: m.set_panel(0, None, None),
        lambda c: c.sim.set_panel("MDI"),
        native=False,
        page=("panel", {"mode": "MDI"}),
        cli=("sim", "panel", "--mode", "MDI"),
        build=lambda: default_machine(read_only=True),
    ),
    "panel-no-control": Case(
        NO_CONTROL,
        None,
        lambda c: c.sim.set_panel("MDI"),
        native=False,
        cli=("sim", "panel", "--mode", "MDI"),
        build=lambda: default_machine(control_enabled=False),
    ),
    "alarm-axis-past-the-path": Case(
        alarm_axis_unfit(9, 3) or "",
        lambda m: m.raise_alarm(9, 2, 100),
        lambda c: c.sim.raise_alarm("PS", 100, axis_no=9),
        native=False,
        page=("raise_alarm", {"axis_no": 9, "alm_type": "PS", "alm_no": 100}),
        cli=("sim", "alarm", "PS0100", "--axis", "9"),
    ),
    "alarm-number-out-of-range": Case(
        alarm_key_unfit(2, 40000) or "",
        lambda m: m.raise_alarm(0, 2, 40000),
        lambda c: c.sim.raise_alarm("PS", 40000),
        native=False,
        page=("raise_alarm", {"alm_type": "PS", "alm_no": 40000}),
        cli=("sim", "alarm", "PS40000"),
        cli_exit=EXIT_USAGE,
    ),
    "alarm-type-not-a-number": Case(
        "alarm type must be an integer, got 1.5",
        lambda m: m.raise_alarm(0, 1.5, 100),  # type: ignore[arg-type]
        lambda c: c.sim.raise_alarm(1.5, 100),
        native=False,
    ),
    "alarm-read-only": Case(
        READ_ONLY_MACHINE,
        lambda m: m.raise_alarm(0, 2, 100),
        lambda c: c.sim.raise_alarm("PS", 100),
        native=False,
        page=("raise_alarm", {"alm_type": "PS", "alm_no": 100}),
        cli=("sim", "alarm", "PS0100"),
        build=lambda: default_machine(read_only=True),
    ),
    "fault-arg-out-of-range": Case(
        fault_refusal(int(FaultKind.DELAY), int(FaultScope.MACHINE), 1, 999_999) or "",
        None,
        lambda c: c.sim.inject_fault("delay", arg=999_999, scope="machine"),
        native=False,
        page=("inject_fault", {"kind": "delay", "arg": 999_999}),
        cli=("sim", "fault", "delay", "--arg", "999999", "--scope", "machine"),
        cli_exit=EXIT_USAGE,
    ),
    "unlock-wrong-password": Case(
        WRONG_PASSWORD,
        lambda m: m.unlock(m.new_session(), "9999"),
        lambda c: c.unlock("9999"),
        native=False,  # FOCAS/2 has no cnc_wrunlockparam
        page=("unlock", {"password": "9999"}),
        cli=("unlock", "9999"),
        build=lambda: default_machine(param_password="1234"),
    ),
    "overrides-rapid-between-steps": Case(
        override_unfit("rapid", 30) or "",
        lambda m: m.set_overrides(None, 30, None),
        lambda c: c.sim.set_overrides(rapid=30),
        native=False,
        page=("overrides", {"rapid": 30}),
        cli=("sim", "override", "--rapid", "30"),
        cli_exit=EXIT_USAGE,
    ),
    "panel-unknown-mode": Case(
        "unknown mode 99",
        lambda m: m.set_panel(99, None, None),
        lambda c: c.sim.set_panel(99),
        native=False,
        page=("panel", {"mode": 99}),
        cli=("sim", "panel", "--mode", "99"),
        cli_exit=EXIT_USAGE,
    ),
    "alarm-message-control-character": Case(
        alarm_text_unfit("a\tb") or "",
        lambda m: m.raise_alarm(0, 2, 100, "a\tb"),
        lambda c: c.sim.raise_alarm("PS", 100, "a\tb"),
        native=False,
        page=("raise_alarm", {"alm_type": "PS", "alm_no": 100, "msg": "a\tb"}),
        cli=("sim", "alarm", "PS0100", "a\tb"),
        cli_exit=EXIT_USAGE,
    ),
    "macro-value-too-long": Case(
        f"#500: macro value {macro_unfit(Decimal(10**20))}",
        lambda m: m.write_macro(500, Decimal("1E+20")),
        lambda c: c.write_macro(500, Decimal("1E+20")),
        page=("write_macro", {"number": 500, "value": str(10**20)}),
        cli=("macro", "set", "500", str(10**20)),
        gateway=lambda g: g.write_macro("m1", 500, Decimal("1E+20"), 1),
        cli_exit=EXIT_USAGE,
    ),
    "fault-read-only": Case(
        READ_ONLY_MACHINE,
        None,
        lambda c: c.sim.inject_fault("delay", arg=10, scope="machine"),
        native=False,
        page=("inject_fault", {"kind": "delay", "arg": 10}),
        cli=("sim", "fault", "delay", "--arg", "10", "--scope", "machine"),
        build=lambda: default_machine(read_only=True),
    ),
    "overrides-out-of-range": Case(
        override_unfit("feed", 300) or "",
        lambda m: m.set_overrides(300, None, None),
        lambda c: c.sim.set_overrides(feed=300),
        native=False,
        page=("overrides", {"feed": 300}),
        cli=("sim", "override", "--feed", "300"),
        cli_exit=EXIT_USAGE,
    ),
}

#: Why EW_PASSWD alone cannot tell which of the gate's conditions is not met.
_GATE_UNTOLD: Final = (
    "EW_PASSWD is the whole of FANUC's answer: whether the mode, PWE (a setting, not read "
    "over FOCAS) or the password closed the gate is not on the wire; the gate is named"
)

#: Front ends that offer a case's action but cannot know its reason, with why, and the words
#: they say instead (from the same source).
CANNOT_KNOW: Final[Mapping[tuple[str, str], tuple[str, str]]] = {
    (case, front): (_GATE_UNTOLD, PARAM_GATE)
    for case in ("param-pwe-off", "param-password-locked")
    for front in ("packed", "native", "cli", "gateway-packed", "gateway-native")
}


def _offers(case: Case, front: str) -> bool:
    if front == "machine":
        return case.machine is not None
    if front == "packed":
        return case.client is not None
    if front == "native":
        return case.client is not None and case.native
    if front == "page":
        return case.page is not None
    if front == "cli":
        return case.cli is not None
    return case.gateway is not None


TABLE: Final = [
    pytest.param(name, front, id=f"{name}-{front}")
    for name, case in CASES.items()
    for front in FRONTS
    if _offers(case, front)
]


def _machine(case: Case) -> Machine:
    machine = case.build()
    case.setup(machine)
    return machine


async def _said(case: Case, front: str, tmp_path: Path) -> str:
    """What ``front`` says of ``case``'s action, refused."""
    machine = _machine(case)
    if front == "machine":
        assert case.machine is not None
        with pytest.raises((MachineError, TypeError, ValueError)) as refused:
            case.machine(machine)
        return str(refused.value)
    if front == "page":
        assert case.page is not None
        action, args = case.page
        return page_refusal(Station(0, machine), action, dict(args))
    if front in ("packed", "native"):
        assert case.client is not None
        async with with_both_clients(machine) as (_, cnc, native):
            with pytest.raises(Exception) as refused:
                await case.client(cnc if front == "packed" else native)
        return str(refused.value)
    if front == "cli":
        assert case.cli is not None
        file = tmp_path / "program.nc"
        file.write_text(case.program)
        argv = [str(file) if a == "{file}" else a for a in case.cli]
        async with serving(machine) as served:
            return await fails(case.cli_exit, *argv, *at(served), prefix="focas-net")
    assert case.gateway is not None
    protocol: Literal["packed", "native"] = "packed" if front == "gateway-packed" else "native"
    async with gated_writer(machine, protocol, _GATES) as (writer, _):
        with pytest.raises(Exception) as refused:
            await case.gateway(writer)
    return str(refused.value)


@pytest.mark.parametrize(("name", "front"), TABLE)
async def test_the_reason_is_said_alike(name: str, front: str, tmp_path: Path) -> None:
    """Each front end carries the machine's reason, in the words of its one source."""
    case = CASES[name]
    said = await _said(case, front, tmp_path)
    why, instead = CANNOT_KNOW.get((name, front), ("", case.reason))
    assert instead in said, f"{front} says {said!r}" + (f" ({why})" if why else "")


def test_every_exception_is_of_a_case_a_front_end_offers() -> None:
    """The exceptions name real cases of the table, each with why."""
    offered = {
        (name, front) for name, case in CASES.items() for front in FRONTS if _offers(case, front)
    }
    for key, (why, instead) in CANNOT_KNOW.items():
        assert key in offered and why and instead, key
