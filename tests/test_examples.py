"""Every script in ``examples/`` runs as a subprocess against a real server started here."""

from __future__ import annotations

import os
import re
from decimal import Decimal
from pathlib import Path

import pytest
from examples_support import EXAMPLES, SCRIPTS, port_args, run_example
from support import Served, serving, wait_until

from focas_net.server import FocasServer
from focas_net.sim import Machine, default_machine, load_machine
from focas_net.sim.nc import RealTimeClock


def test_every_example_is_tested() -> None:
    tested = {
        "read_status.py",
        "write_param_with_unlock.py",
        "pmc_bits.py",
        "alarm_watch.py",
        "fleet_poll.py",
        "versamax_config.py",
        "fwlib_client.py",
        "run_program.py",
        "fleet_dashboard.py",
    }
    assert set(SCRIPTS) == tested
    assert {p.name for p in EXAMPLES.glob("_*.py")} == {"_options.py"}


@pytest.mark.parametrize(
    ("argv", "words"),
    [
        (["--param", "1001", "--axis", "0", "--value", "300"], "bit parameter 1001 holds 0..255"),
        (["--param", "99999", "--axis", "0", "--value", "3"], "parameter number 99999 is outside"),
        (["--param", "1001", "--value", "3"], "1001 is not an axis parameter: give --axis 0"),
        (["--param", "1320", "--axis", "0", "--value", "3"], "1320 is an axis parameter"),
    ],
)
async def test_write_param_says_what_is_wrong_without_a_traceback(
    server: Served, argv: list[str], words: str
) -> None:
    code, _out, err = await run_example("write_param_with_unlock.py", *port_args(server), *argv)
    assert code == 2 and "Traceback" not in err and words in err
    assert (server.machine.panel.mode, server.machine.panel.pwe) == (1, 0)


@pytest.mark.parametrize(
    ("name", "args", "words"),
    [
        ("read_status.py", ["--timeout", "0"], "timeout must be positive, got 0.0"),
        ("read_status.py", ["--host", ""], "empty host ''"),
        ("pmc_bits.py", ["--area", "Q"], "unknown PMC area 'Q'"),
        ("pmc_bits.py", ["--start", "99999999999"], "PMC start address 99999999999 is outside"),
        ("versamax_config.py", ["--rack", "-1"], "rack -1 is outside 0..7"),
        ("alarm_watch.py", ["--timeout", "0"], "timeout must be positive, got 0.0"),
        ("run_program.py", ["--seconds", "1", "--port", "0"], "port 0 is outside 1..65535"),
        ("fleet_poll.py", ["--rounds", "1", "--port", "0"], "port 0 is outside 1..65535"),
    ],
)
async def test_an_argument_the_client_refuses_is_one_line_and_exit_2(
    server: Served, name: str, args: list[str], words: str
) -> None:
    """They printed a ValueError's traceback (exit 1)."""
    given = dict(zip(args[::2], args[1::2], strict=True))
    address = [] if "--port" in given or "--host" in given else port_args(server)
    code, out, err = await run_example(name, *address, *args)
    stem = name.removesuffix(".py")
    assert (code, out) == (2, ""), (code, out, err)
    assert err.startswith(f"{stem}: {words}") and err.count("\n") == 1, err


@pytest.mark.parametrize("protocol", ["packed", "native"])
async def test_read_status(server: Served, protocol: str) -> None:
    server.machine.raise_alarm(0, 3, 100, "PARAMETER WRITE ENABLE")
    code, out, err = await run_example("read_status.py", *port_args(server), "--protocol", protocol)
    assert (code, err) == (0, "")
    lines = out.splitlines()
    assert lines[0] == f"CNC {server.host}:{server.port}: series D4F1 version 32.0, 3 axes"
    assert lines[1] == "mode=MEM run=**** emergency=**** alarm=ALM"
    assert lines[2:] == ["active alarms: 1", "  PS0100 PARAMETER WRITE ENABLE"]


async def test_read_status_unreachable() -> None:
    async with serving() as served:
        args = port_args(served)
    code, out, err = await run_example("read_status.py", *args)  # the server is gone
    assert code == 1 and out == ""
    assert err.startswith("read_status: cannot connect to")


async def test_write_param_without_password(server: Served) -> None:
    code, out, err = await run_example(
        "write_param_with_unlock.py", *port_args(server), "--param", "1420", "--axis", "3",
        "--value", "30000",
    )  # fmt: skip
    assert (code, err) == (0, "")
    assert "parameter 1420 axis 3: 24000" in out
    # what happened, in its order: the panel is restored after the read-back
    assert out.splitlines()[-2:] == [
        "wrote 30000, read back 30000",
        "panel: mode restored, PWE off",
    ]
    assert "unlocked" not in out
    assert server.machine.read_param(1420, 3) == 30000
    # the panel went back to MEM with PWE off
    assert (server.machine.panel.mode, server.machine.panel.pwe) == (1, 0)


async def test_write_param_with_password() -> None:
    async with serving(default_machine(param_password="1234")) as served:
        code, out, err = await run_example(
            "write_param_with_unlock.py", *port_args(served), "--password", "1234"
        )
        assert (code, err) == (0, "")
        assert "unlocked with the parameter password" in out
        assert out.splitlines()[-2] == "wrote 500000, read back 500000"
        assert served.machine.read_param(1320, 1) == 500_000

        code, out, err = await run_example("write_param_with_unlock.py", *port_args(served))
        assert code == 1
        assert "give --password" in err
        assert "panel: mode restored, PWE off" in out
        assert served.machine.panel.pwe == 0

        served.machine.read_only = True
        code, _out, err = await run_example("write_param_with_unlock.py", *port_args(served))
        assert code == 1 and err.startswith("write_param_with_unlock: EW_PROT (7)")


@pytest.mark.parametrize("protocol", ["packed", "native"])
async def test_pmc_bits(server: Served, protocol: str) -> None:
    code, out, err = await run_example(
        "pmc_bits.py", *port_args(server), "--area", "D", "--start", "500", "--bytes", "16",
        "--protocol", protocol,
    )  # fmt: skip
    assert (code, err) == (0, "")
    assert out.startswith("128 concurrent bit writes to D500..")
    assert out.splitlines()[-1] == "every bit as written"
    assert "MISMATCH" not in out
    rows = [line.split() for line in out.splitlines() if line.startswith("D5")]
    assert len(rows) == 16
    written = server.machine.read_pmc("D", 500, 16)
    assert [int(r[2], 2) for r in rows] == list(written)
    assert all(r[1] == r[2] for r in rows)


@pytest.mark.parametrize("protocol", ["packed", "native"])
async def test_alarm_watch(server: Served, protocol: str) -> None:
    code, out, err = await run_example(
        "alarm_watch.py", *port_args(server), "--interval", "0.05", "--events", "6",
        "--protocol", protocol,
    )  # fmt: skip
    assert (code, err) == (0, "")
    lines = out.splitlines()
    assert lines[-1].startswith("6 events; polls: ")
    events = sorted(re.sub(r"^\s*\d+\s+", "", line).split(" UTC ")[-1] for line in lines[:-1])
    assert len(events) == 6
    assert sum(e.startswith("raised") for e in events) == 2
    assert sum(e.startswith("cleared") for e in events) == 2
    assert sum(e.startswith("PS0100") or e.startswith("OT0500") for e in events) == 2
    assert "raised   OT0500 (axis 1) + OVERTRAVEL ( SOFT 1 )" in events
    # the demonstration cleaned up after itself; the history keeps both
    assert server.machine.active_alarms() == []
    assert len(server.machine.alarm_history(10)) == 2


async def test_alarm_watch_gives_up_when_nothing_happens(server: Served) -> None:
    code, out, err = await run_example(
        "alarm_watch.py", *port_args(server), "--watch-only", "--events", "1",
        "--interval", "0.05", "--seconds", "0.5",
    )  # fmt: skip
    assert code == 1 and out == ""
    assert err.strip() == "only 0 of 1 events in 0.5 s"


async def test_versamax_config(server: Served) -> None:
    code, out, err = await run_example("versamax_config.py", *port_args(server))
    assert (code, err) == (0, "")
    assert "rack 0 slot 0: empty" in out
    assert "rack 0 slot 1: GBI1" in out
    assert "rack 0 slot 3: D844  primary 0x8080 secondary 0x8008  16 inputs, 16 outputs" in out
    assert "    reference 1: %I offset 17, 2 bytes" in out
    assert out.splitlines()[-1] == "2 module(s) configured in rack 0"

    code, out, err = await run_example("versamax_config.py", *port_args(server), "--slot", "3")
    assert (code, err) == (0, "")
    assert out.splitlines()[0].startswith("rack 0 slot 3: D844")
    code, out, _ = await run_example("versamax_config.py", *port_args(server), "--rack", "5")
    assert code == 1 and out.splitlines()[-1] == "0 module(s) configured in rack 5"


def _table_rows(out: str) -> list[list[str]]:
    lines = out.splitlines()
    assert lines[0].split() == ["machine", "address", "cnc", "mode", "run", "alarm", "parts", "ms"]
    return [line.split() for line in lines[1:-1]]


@pytest.mark.parametrize("protocol", ["packed", "native"])
async def test_fleet_poll_simulates_its_own_fleet(protocol: str) -> None:
    code, out, err = await run_example(
        "fleet_poll.py", "--simulate", "21", "--rounds", "2", "--interval", "0.05",
        "--protocol", protocol,
    )  # fmt: skip
    assert (code, err) == (0, "")
    rows = _table_rows(out)
    assert [r[0] for r in rows] == [f"sim-{i:03d}" for i in range(1, 22)]
    assert [int(r[6]) for r in rows] == [100 * i + 7 for i in range(21)]  # parts counts
    assert rows[0][3:5] == ["MEM", "STRT"] and rows[2][3] == "MDI"
    running = [r for r in rows if r[4] == "STRT"]
    assert len(running) == 3 and all(r[3] == "MEM" for r in running)  # cycle start: MEM only
    assert rows[5][5] == "PS0105"
    assert out.splitlines()[-1].startswith(
        "21 machines, 2 round(s): 42 polls of 3 calls each, 0 failed"
    )


async def test_fleet_poll_of_ports_given() -> None:
    machines = [default_machine(f"cell-{i}") for i in range(20)]
    machines[7].raise_alarm(2, 4, 500, "OVER TRAVEL")
    async with FocasServer(machines, host="127.0.0.1", port=0, grace_period=1.0) as server:
        ports = ",".join(str(lst.port) for lst in server.listeners)
        code, out, err = await run_example(
            "fleet_poll.py", "--ports", ports, "--rounds", "2", "--interval", "0.05"
        )
    assert (code, err) == (0, "")
    rows = _table_rows(out)
    assert len(rows) == 20
    assert [r[1] for r in rows] == [f"127.0.0.1:{lst.port}" for lst in server.listeners]
    assert rows[7][5] == "OT0500" and all(r[5] == "-" for i, r in enumerate(rows) if i != 7)
    assert all(r[2] == "D4F1/32.0" and r[3] == "MEM" for r in rows)
    assert "40 polls of 3 calls each, 0 failed" in out.splitlines()[-1]


async def test_fleet_poll_reports_unreachable_machines(server: Served) -> None:
    async with serving() as gone:
        dead = gone.port
    code, out, err = await run_example(
        "fleet_poll.py", "--ports", f"{server.port},{dead}", "--rounds", "1"
    )
    assert code == 1 and err == ""
    rows = _table_rows(out)
    assert rows[0][3] == "MEM"
    assert rows[1][2:4] == ["ERROR", "unreachable:"]
    assert "1 failed" in out.splitlines()[-1]


# -- run_program.py and fleet_dashboard.py: machines at work ---------------------------------

#: Machine time runs this many times as fast as the wall clock on the servers of these tests.
FAST = 20.0


async def test_run_program_runs_a_part_end_to_end() -> None:
    machine = default_machine(sim_clock=RealTimeClock(FAST))
    async with serving(machine) as served:
        code, out, err = await run_example(
            "run_program.py", *port_args(served), "--interval", "0.02", "--seconds", "30"
        )
    assert (code, err) == (0, "")
    lines = out.splitlines()
    assert lines[0] == f"O7001 stored and selected on {served.host}:{served.port}; cycle start"
    trace = [line.split() for line in lines[1:-1]]
    sequences = [int(t[2].removeprefix("N")) for t in trace]
    assert sequences == sorted(sequences) and set(sequences) <= set(range(10, 111, 10))
    assert any(t[3] == "STRT" for t in trace)
    cutting = 3 / 600 * 60 + 4 * 30 / 1800 * 60  # Z-1 at F600, then the square's sides at F1800
    assert lines[-1].startswith("O7001 finished after ")
    assert lines[-1].endswith(f"parts 0 -> 1, cutting {cutting:.2f} s")
    assert machine.parts_counts()[0] == 1
    assert machine.programs.text(7001).startswith("O7001 (EXAMPLE SQUARE)")


async def test_run_program_stops_at_an_alarm(tmp_path: Path) -> None:
    program = tmp_path / "bad.nc"
    program.write_text("O7002 (BAD)\nN10 G1 X5. F6000\nN20 G07\nN30 M30\n")
    async with serving(default_machine(sim_clock=RealTimeClock(FAST))) as served:
        code, out, err = await run_example(
            "run_program.py", *port_args(served), "--program", str(program), "--interval", "0.02"
        )
        assert served.machine.active_alarms()[0].alm_no == 10
    assert code == 1 and out.startswith("O7002 stored and selected")
    assert err.startswith("run_program: O7002 stopped by an alarm: PS0010")


async def test_run_program_leaves_a_running_machine_alone() -> None:
    machine = default_machine(sim_clock=RealTimeClock(FAST))
    machine.cycle_start(repeat=True)
    async with serving(machine) as served:
        code, out, err = await run_example("run_program.py", *port_args(served))
    assert (code, out) == (1, "")
    assert err.strip() == (
        "run_program: the CNC is running a program: reset it first (focas-net sim cycle reset)"
    )
    assert 7001 not in {p.number for p in machine.program_directory()}


def _dashboard_tables(out: str) -> list[list[list[str]]]:
    tables = [table.splitlines() for table in out.rstrip("\n").split("\n\n")]
    for lines in tables:
        assert lines[0].split() == [
            "machine", "run", "program", "seq", "parts", "feed", "spindle", "alarm"
        ]  # fmt: skip
    return [[line.split() for line in lines[1:]] for lines in tables]


async def test_fleet_dashboard_of_ports_given() -> None:
    clock = RealTimeClock(FAST)
    machines = [default_machine(f"cell-{i}", sim_clock=clock) for i in range(3)]
    for machine in machines:
        machine.cycle_start(repeat=True)
    machines[1].raise_alarm(1, 4, 500, "OVER TRAVEL")
    async with FocasServer(machines, host="127.0.0.1", port=0, grace_period=1.0) as server:
        async with serving() as gone:
            dead = gone.port
        ports = [lst.port for lst in server.listeners]
        code, out, err = await run_example(
            "fleet_dashboard.py", "--ports", ",".join(map(str, [*ports, dead])), "--count", "3",
            "--interval", "0.05", "--timeout", "1",
        )  # fmt: skip
    assert (code, err) == (0, "")
    assert "\x1b" not in out  # piped: no control sequences
    tables = _dashboard_tables(out)
    assert len(tables) == 3
    for rows in tables:
        assert [r[0] for r in rows] == [f"127.0.0.1:{p}" for p in [*ports, dead]]
        assert [r[1] for r in rows[:3]] == ["STRT", "STOP", "STRT"]  # the alarm stopped cell-1
        assert all(r[2] == "O0001" for r in rows[:3])
        assert [r[7] for r in rows[:3]] == ["-", "OT0500", "-"]
        assert rows[3][1] == "ERROR:"


async def test_fleet_dashboard_simulates_its_own_fleet() -> None:
    code, out, err = await run_example(
        "fleet_dashboard.py", "--simulate", "5", "--count", "2", "--interval", "0.05"
    )
    assert (code, err) == (0, "")
    tables = _dashboard_tables(out)
    assert [len(rows) for rows in tables] == [5, 5]
    assert all(r[1] == "STRT" and r[2] == "O0001" for rows in tables for r in rows)


@pytest.mark.parametrize("name", SCRIPTS)
async def test_examples_document_their_options(name: str) -> None:
    code, out, _ = await run_example(name, "--help")
    assert code == 0
    assert "--host" in out and "--port" in out


# -- fwlib_client.py: FANUC's own library, when it is there ----------------------------------

FWLIB = os.environ.get("FOCAS_NET_FWLIB")
needs_fwlib = pytest.mark.skipif(
    not FWLIB,
    reason="set FOCAS_NET_FWLIB to the path of FANUC's libfwlib32 (e.g. libfwlib32.so.1) "
    "to run examples/fwlib_client.py against the simulator",
)
MACHINE_16I = Path(__file__).with_name("data") / "fwlib_16i_machine.toml"


def fwlib_expected(machine: Machine) -> list[str]:
    """What ``fwlib_client.py --macro 500 --pmc D0:4`` prints for ``machine``, from the
    machine's own state (the handle number aside)."""
    i, st = machine.identity(), machine.status()
    macro = machine.read_macro(500)
    alarm_bits = 0
    for a in machine.active_alarms():
        alarm_bits |= 1 << a.alm_type
    m = machine.motion
    lines = [
        f"cnc: type {i.cnc_type.strip()}{i.mt_type.strip()} series {i.series} version "
        f"{i.version}, {len(machine.axes)} axes",
        f"status: mode={st.aut} run={st.run} motion={st.motion} mstb={st.mstb} "
        f"emergency={st.emergency} alarm={st.alarm} edit={st.edit}",
        f"macro #500: {'<vacant>' if macro is None else macro}",
        f"pmc D0..D3: {machine.read_pmc('D', 0, 4).hex(' ')}",
        f"dynamic: alarm={alarm_bits} program=O{m.program_running} main=O{m.program_main} "
        f"sequence=N{m.sequence} feed={m.feed} spindle={m.spindle_speed}",
    ]
    for kind, name in (
        ("absolute", "absolute"),
        ("machine", "machine"),
        ("relative", "relative"),
        ("distance_to_go", "distance"),
    ):
        values = " ".join(str(v) for _, v in machine.positions(kind))
        lines.append(f"{name}: {values}")
    return lines


def busy(machine: Machine) -> None:
    """Give every figure the example prints a value that is not its default."""
    machine.write_macro(500, Decimal("-12.345"))
    machine.write_pmc("D", 0, bytes([0x01, 0x80, 0xFE, 0x7F]))
    machine.set_run(3, 1)
    machine.raise_alarm(0, 3, 100, "PARAMETER WRITE ENABLE")
    machine.set_motion(
        absolute=[1000, -2000, 30000],
        machine=[1100, -2100, 31000],
        relative=[-5, 6, 7],
        distance_to_go=[10, 0, -10],
        feed=1500,
        spindle_speed=2400,
        program_running=1234,
        program_main=1000,
        sequence=42,
    )


@needs_fwlib
@pytest.mark.parametrize("control", ["0i-F", "16i"])
async def test_fwlib_client(control: str) -> None:
    machine = default_machine() if control == "0i-F" else load_machine(MACHINE_16I)
    busy(machine)
    assert FWLIB is not None
    async with serving(machine) as served:
        code, out, err = await run_example(
            "fwlib_client.py", "--library", FWLIB, *port_args(served), "--macro", "500",
            "--pmc", "D0:4",
        )  # fmt: skip
        lines = out.splitlines()
        assert (code, err) == (0, ""), out
        assert re.fullmatch(rf"handle \d+ to {re.escape(served.host)}:{served.port}", lines[0])
        assert lines[1:] == fwlib_expected(machine)
        # cnc_freelibhndl closed both of the library's connections
        await wait_until(lambda: not served.listener.connections)


@needs_fwlib
async def test_fwlib_client_exits_with_the_ew_code() -> None:
    async with serving() as served:
        args = port_args(served)
    assert FWLIB is not None
    code, out, err = await run_example(
        "fwlib_client.py", "--library", FWLIB, *args, "--timeout", "1"
    )
    assert out == ""
    assert err == "fwlib_client: cnc_allclibhndl3 returned EW -16\n"
    assert code == 256 - 16  # EW_SOCKET, as an exit status


async def test_fwlib_client_needs_the_library(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.delenv("FOCAS_NET_FWLIB", raising=False)
    code, out, err = await run_example("fwlib_client.py", "--port", "1")
    assert (code, out) == (2, "")
    assert "name FANUC's library with --library or FOCAS_NET_FWLIB" in err


async def test_fwlib_client_names_a_library_it_cannot_load(tmp_path: Path) -> None:
    missing = tmp_path / "libfwlib32.so.1"
    code, out, err = await run_example("fwlib_client.py", "--library", str(missing))
    assert (code, out) == (1, "")
    assert err.startswith(f"fwlib_client: cannot load {str(missing)!r}")


async def test_fwlib_client_names_a_bad_pmc_range(tmp_path: Path) -> None:
    code, out, err = await run_example(
        "fwlib_client.py", "--library", str(tmp_path / "x.so"), "--pmc", "Q7"
    )
    assert (code, out) == (2, "")
    assert "--pmc 'Q7': area 'Q' is not one of" in err
