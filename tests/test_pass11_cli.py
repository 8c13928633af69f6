"""A new user's eleventh pass over the command line: one rule for the form of a refusal (a
value the command judges alone, before connecting, is refused in the parser's words naming
the argument; one the CNC's answer decides, in ``focas-net:``'s), ``serve``'s refusals of
options together in the parser's words too, FANUC's ``F0`` rapid override named so, a macro
variable typed ``#100``, a refused cycle start saying whether an alarm or the emergency stop
stopped it.

Each test runs ``focas-net`` as a user does (a subprocess) and checks its one line and its
exit code.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Final

import pytest
from cli_support import at, fails, ok
from support import serving

from focas_net.cli import EXIT_CNC, EXIT_USAGE
from focas_net.client import FocasClient
from focas_net.errors import EW, CncError
from focas_net.sim import default_machine, load_machine
from focas_net.web import ActionError, Station, perform

PROTOCOLS: Final = (["--protocol", "packed"], ["--protocol", "native"])
#: A port nothing listens on: a refusal there came before anything was connected.
NOBODY: Final = ("--port", "1")


def _usage(command: str, said: str) -> str:
    """The parser's one line of a usage error of ``command``."""
    return f"focas-net {command}: error: {said}; see focas-net {command} --help"


# -- a value judged without the CNC: the parser's words ------------------------------------------


@pytest.mark.parametrize(
    ("argv", "command", "said"),
    [
        (
            ("program", "show", "0x10"),
            "program",
            "argument N|FILE: '0x10' is not a program number (O1..O99999999, e.g. O1000)",
        ),
        (
            ("program", "select", "O0"),
            "program",
            "argument N|FILE: 'O0' is not a program number (O1..O99999999, e.g. O1000)",
        ),
        (
            ("pmc", "write", "R", "0", "1", "--hex", "02"),
            "pmc write",
            "argument --hex: not allowed with BYTE values: give the bytes either as values or "
            "with --hex",
        ),
        (
            ("param", "get", "abc"),
            "param get",
            "argument NUMBER[.BIT]: expected NUMBER or NUMBER.BIT (e.g. 1815 or 1815.0), got 'abc'",
        ),
        (
            ("param", "get", "99999"),
            "param get",
            "argument NUMBER[.BIT]: parameter number 99999 is outside 0..32767",
        ),
        (
            ("param", "set", "0x10000", "1"),
            "param set",
            "argument NUMBER[.BIT]: 0x10000 reads as 65536: parameter number 65536 is outside "
            "0..32767",
        ),
        (
            ("diag", "40000"),
            "diag",
            "argument NUMBER: diagnostic number 40000 is outside 0..32767",
        ),
        (
            ("macro", "get", "40000"),
            "macro get",
            "argument NUMBER: macro variable number 40000 is outside -32768..32767",
        ),
        (("macro", "set", "100", "abc"), "macro set", "argument VALUE: #100: not a number: 'abc'"),
        (
            ("pmc", "bit", "R", "1.x"),
            "pmc bit",
            "argument BYTE.BIT: '1.x': the bit after the dot must be a bit number (0..7 of a "
            "byte), got 'x'",
        ),
        (
            ("pmc", "read", "R", "70000"),
            "pmc read",
            "argument START: PMC start address 70000 is outside 0..65535",
        ),
        (
            ("pmc", "read", "R", "0", "0"),
            "pmc read",
            "argument COUNT: PMC byte count 0 is outside 1..65536 (a PMC range holds one byte "
            "at least)",
        ),
        (
            ("alarms", "--count", "2"),
            "alarms",
            "--count applies to --follow (focas-net alarms --follow --count 2)",
        ),
    ],
)
async def test_a_value_judged_without_the_cnc_is_refused_in_the_parsers_words(
    argv: tuple[str, ...], command: str, said: str
) -> None:
    """``program show 0x10`` said ``focas-net: program show: '0x10' is not a program
    number``, ``pmc write R 0 1 --hex 02`` ``focas-net: give the bytes either as values or
    with --hex``, ``param get 99999`` ``focas-net: parameter number ...`` after connecting,
    though ``param set 1 abc`` and ``serve --fleet 0x0`` are refused in the parser's words:
    whatever the command judges alone is refused so, before anything is connected."""
    line = await fails(EXIT_USAGE, *argv, *NOBODY, prefix="focas-net")
    assert line == _usage(command, said), line


async def test_a_value_the_cnc_decides_keeps_the_command_lines_words() -> None:
    """A parameter value judged by the parameter's kind, which the CNC tells, is refused
    after connecting in ``focas-net:``'s words, on both transports (docs/cli.md)."""
    async with serving() as served:
        lines = [
            await fails(EXIT_USAGE, "param", "set", "1020", "300", *at(served), *p)
            for p in PROTOCOLS
        ]
    assert lines == ["focas-net: parameter 1020 is a byte parameter: 300 is outside -128..127"] * 2


# -- serve: options refused together --------------------------------------------------------------


@pytest.mark.parametrize(
    ("argv", "said"),
    [
        (
            ("--fleet", "2", "--workers", "3"),
            "argument --workers: at most 64, and no more than the 2 machines of --fleet, got 3",
        ),
        (
            ("--workers", "2"),
            "argument --workers: 2 workers spread a fleet over processes, and the fleet is 1 "
            "machine (without --fleet): give --fleet N (at least 2 machines)",
        ),
        (
            ("--seed", "3"),
            "argument --seed: the machines do not run (give --run, or a machine file with a "
            "[run] section)",
        ),
        (("--tls-key", "k.pem"), "argument --tls-key: needs --tls-cert"),
        (
            ("--port", "65534", "--fleet", "0x3"),
            "argument --fleet: 0x3 reads as 3: 3 machines from --port 65534 run past 65535 (the "
            "last machine would get port 65536)",
        ),
    ],
)
async def test_serve_refuses_options_together_in_the_parsers_words(
    argv: tuple[str, ...], said: str
) -> None:
    """``serve --fleet 2 --workers 3`` said ``focas-net serve: error: --workers 3: ...`` with
    no ``argument`` and no help, unlike ``serve --fleet 0x0``: both are the parser's line."""
    line = await fails(EXIT_USAGE, "serve", *argv, prefix="focas-net")
    assert line == _usage("serve", said), line


# -- FANUC's F0 rapid override --------------------------------------------------------------------


async def test_the_f0_rapid_override_is_named_f0() -> None:
    """``sim override --rapid F0`` printed ``rapid 0 %``: FANUC's F0 is a rate of its own (a
    parameter's), no percentage; the text and the JSON of ``sim override`` and ``watch``
    name it ``F0``, the other steps in percent."""
    async with serving() as served:
        text = await ok("sim", "override", "--rapid", "F0", *at(served))
        data = json.loads(await ok("sim", "override", "--json", *at(served)))
        frame = await ok("watch", "--count", "1", *at(served))
        watched = json.loads(await ok("watch", "--count", "1", "--json", *at(served)))
        back = json.loads(await ok("sim", "override", "--rapid", "25", "--json", *at(served)))
    assert text == "feed 100 %, rapid F0, spindle 100 %\n", text
    assert data["rapid"] == "F0", data
    assert "rapid F0  spindle" in frame, frame
    assert watched["state"]["overrides"]["rapid"] == "F0", watched
    assert back["rapid"] == 25, back


# -- a macro variable typed #100 ------------------------------------------------------------------


@pytest.mark.parametrize("typed", ["#100", " #100", "#0x64"])
async def test_a_macro_number_typed_with_its_hash_is_read(typed: str) -> None:
    """``macro set '#100' 5`` said ``argument NUMBER: not a whole number: '#100'``: a FANUC
    user names a variable ``#100``; the command line and the page read it as 100."""
    async with serving() as served:
        written = await ok("macro", "set", typed, "5", *at(served))
        read = [await ok("macro", "get", typed, *at(served), *p) for p in PROTOCOLS]
        station = Station(0, served.machine)
        page = perform(station, "write_macro", {"number": typed, "value": "7"})
    assert written == "#100 = 5 (written)\n", written
    assert read == ["#100 = 5\n"] * 2, read
    assert page == {"ok": True, "number": 100, "value": "7"}, page


async def test_a_hash_alone_is_refused_naming_it() -> None:
    line = await fails(EXIT_USAGE, "macro", "get", "#", *NOBODY, prefix="focas-net")
    assert line == _usage("macro get", "argument NUMBER: not a whole number: '#'"), line


# -- a refused cycle start: an alarm or the emergency stop ----------------------------------------


async def test_a_cycle_start_refused_says_emergency_stop_or_alarm() -> None:
    """``sim cycle start`` refused with EW_ALARM advised both what clears an alarm and what
    releases the emergency stop, whichever it was: the advice is the one of the reason the
    client read from the status after the refusal."""
    machine = default_machine()
    async with serving(machine) as served:
        machine.set_panel(emergency=1)
        stopped = await fails(EXIT_CNC, "sim", "cycle", "start", *at(served))
        async with FocasClient("127.0.0.1", served.port) as cnc:
            with pytest.raises(CncError) as refused:
                await cnc.sim.cycle_start()
        machine.set_panel(emergency=0)
        machine.raise_alarm(1, 4, 411, "SERVO")
        alarmed = await fails(EXIT_CNC, "sim", "cycle", "start", *at(served))
    assert refused.value.ew == EW.ALARM
    assert "cycle start refused: the emergency stop is on" in str(refused.value), refused.value
    assert stopped == (
        "focas-net: EW_ALARM (15): alarm has occurred (sim_cycle); cycle start refused: "
        "the emergency stop is on (focas-net sim panel --emergency off releases it)"
    ), stopped
    assert alarmed == (
        "focas-net: EW_ALARM (15): alarm has occurred (sim_cycle); cycle start refused: an "
        "alarm is active (focas-net alarms lists them; focas-net sim clear or sim cycle reset "
        "clears them)"
    ), alarmed


# -- a --width that is not the parameter's ------------------------------------------------------


@pytest.mark.parametrize("protocol", PROTOCOLS)
async def test_a_width_not_the_parameters_is_said_once(protocol: list[str]) -> None:
    """``param set 6711 1 --width 1`` said "(cnc_wrparam: 6711 is 4 bytes wide, not 1);
    parameter 6711 is not 1 bytes wide: leave out --width": the widths once, and a byte as
    one."""
    async with serving() as served:
        line = await fails(
            EXIT_CNC, "param", "set", "6711", "1", "--width", "1", *at(served), *protocol
        )
    assert line == (
        "focas-net: EW_LENGTH (2): data block length error (cnc_wrparam); parameter 6711 is 4 "
        "bytes wide, not 1: leave out --width (the CNC's own width is used)"
    ), line


# -- a decimal comma ------------------------------------------------------------------------------


@pytest.mark.parametrize(("argv", "command"), [(("macro", "set", "100", "1,5"), "macro set")])
async def test_a_decimal_comma_is_refused_naming_the_point(
    argv: tuple[str, ...], command: str
) -> None:
    """``macro set 100 1,5`` (a decimal comma, as much of Europe writes it) said only "not a
    number": it says the decimal point is ``.``, on the page too."""
    line = await fails(EXIT_USAGE, *argv, *NOBODY, prefix="focas-net")
    said = "not a number: '1,5' (the decimal point is '.': 1.5)"
    assert line == _usage(command, f"argument VALUE: #100: {said}"), line
    with pytest.raises(ActionError) as page:
        perform(Station(0, default_machine()), "write_macro", {"number": 100, "value": "1,5"})
    assert str(page.value) == f"value: {said}"


# -- a program stored on another path -------------------------------------------------------------

LATHE: Final = Path(__file__).resolve().parent.parent / "examples" / "lathe_2path.toml"


@pytest.mark.parametrize("action", ["show", "select", "delete"])
async def test_a_program_on_another_path_is_named_where_it_is(action: str) -> None:
    """``program show 1001 --path 2`` on a lathe of two paths said "no program O1001
    (focas-net program list --path 2)", though O1001 is path 1's: the refusal says where it
    is, as ``sim clear`` says where an alarm is."""
    async with serving(load_machine(LATHE)) as served:
        line = await fails(EXIT_CNC, "program", action, "1001", "--path", "2", *at(served))
    assert line.endswith(
        f"; no program O1001 on path 2 (O1001 is on path 1: focas-net program {action} O1001)"
    ), line


# -- sim clear of a type by its number ------------------------------------------------------------


async def test_sim_clear_takes_a_type_by_the_number_its_refusal_offers() -> None:
    """``sim clear QQ`` says "unknown alarm type 'QQ' (one of SW PW ... PC, or 0..31)", yet
    ``sim clear 3`` was refused as no alarm code: a type is taken by its number too, and a
    type of no name as it is printed (``T31``)."""
    machine = default_machine()
    machine.raise_alarm(0, 3, 100)
    machine.raise_alarm(0, 31, 5)
    async with serving(machine) as served:
        by_number = json.loads(await ok("sim", "clear", "3", "--json", *at(served)))
        unnamed = await ok("sim", "clear", "T31", *at(served))
        line = await fails(EXIT_USAGE, "sim", "clear", "32", *NOBODY, prefix="focas-net")
    assert by_number["cleared"] == "PS" and len(by_number["alarms"]) == 1, by_number
    assert unnamed == "cleared T31:0005; 0 still active\n", unnamed
    assert line == _usage("sim clear", "argument ALARM: alarm type 32 is outside 0..31"), line
