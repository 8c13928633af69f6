"""The client commands of ``focas-net`` against a real server, and their formatting helpers.

The command line runs in-process (``main([...])`` in a worker thread, with its own event loop)
while the server runs on the test's loop; one test runs it as a subprocess to send Ctrl-C.
"""

from __future__ import annotations

import asyncio
import dataclasses
import json
import signal
import struct
from collections.abc import AsyncIterator
from datetime import UTC, datetime
from decimal import Decimal

import pytest
from cli_support import CLI_TIMEOUT, Cli, at, focas_net_process, killed_at_exit
from support import Served, free_port, serving

from focas_net.cli import (
    EXIT_CNC,
    EXIT_CONNECTION,
    EXIT_OK,
    EXIT_PROTOCOL,
    EXIT_USAGE,
    main,
)
from focas_net.cli import _format as fmt
from focas_net.errors import AccessDeniedError, CncError, FocasTimeoutError
from focas_net.protocol import (
    ActiveAlarm,
    AlarmHistoryEntry,
    AlarmState,
    AutMode,
    EditState,
    FrameDecoder,
    ProgramNumbers,
    StatusInfo,
    SysInfo,
    encode_frame,
    status_member,
)
from focas_net.sim import default_machine
from focas_net.sim.default import mdd844_record


@pytest.fixture
async def cli(server: Served, capsys: pytest.CaptureFixture[str]) -> Cli:
    return Cli(server, capsys)


@pytest.fixture
async def locked_cli(capsys: pytest.CaptureFixture[str]) -> AsyncIterator[Cli]:
    """A CLI against a machine with the parameter password ``1234``."""
    async with serving(default_machine(param_password="1234")) as served:
        yield Cli(served, capsys)


# -- status and identity --------------------------------------------------------------------


async def test_status_table_and_json(cli: Cli) -> None:
    out = await cli.ok("status")
    first, *rest = out.splitlines()
    assert first == "mode=MEM run=**** motion=*** mstb=*** emergency=**** alarm=**** edit=****"
    assert any(line.split()[:3] == ["mode", "1", "MEM"] for line in rest)
    data = await cli.json("status")
    assert data["mode"] == {"value": 1, "name": "MEM", "meaning": "memory (automatic operation)"}
    assert data["alarm"]["name"] == "****"
    assert set(data) == {"hdck", "tmmode", "mode", "run", "motion", "mstb", "emergency",
                         "alarm", "edit"}  # fmt: skip


async def test_status_follows_the_panel_and_alarms(cli: Cli) -> None:
    out = await cli.ok("sim", "panel", "--mode", "MDI", "--emergency", "on")
    assert out.startswith("mode=MDI ") and "emergency=EMG" in out
    await cli.ok("sim", "alarm", "PS0100", "PARAMETER", "WRITE", "ENABLE")
    data = await cli.json("status")
    assert (data["mode"]["name"], data["emergency"]["name"], data["alarm"]["name"]) == (
        "MDI",
        "EMG",
        "ALM",
    )
    # mode unchanged when --mode is omitted; emergency back off
    out = await cli.ok("sim", "panel", "--emergency", "off")
    assert "mode=MDI" in out and "emergency=****" in out


async def test_sysinfo(cli: Cli) -> None:
    out = await cli.ok("sysinfo")
    assert "D4F1" in out and "Series 0i" in out and "3 controlled axes" in out
    data = await cli.json("sysinfo")
    assert data["series"] == "D4F1" and data["version"] == "32.0"
    assert data["axes_count"] == 3
    assert data["mt_type"] == {"value": "M", "meaning": "machining center (M series)"}
    assert data["cnc_type"] == {"value": "0", "meaning": "Series 0i"}


# -- parameters, diagnostics, macros --------------------------------------------------------


async def test_param_get(cli: Cli) -> None:
    out = await cli.ok("param", "get", "1420", "--axis", "2")
    assert out.strip() == "1420 axis 2 = 24000 (0x00005DC0), two-word parameter"
    data = await cli.json("param", "get", "3216")
    assert data == {"number": 3216, "axis": 0, "value": 10, "width": 2, "type": "word"}
    # 1815 is 0b00110000 on every axis by default
    assert (await cli.ok("param", "get", "1815.4", "--axis", "1")).strip() == "1815.4 axis 1 = 1"
    data = await cli.json("param", "get", "1815.0", "--axis", "1")
    assert (data["bit"], data["bit_value"], data["value"]) == (0, 0, 0b0011_0000)


async def test_param_get_errors(cli: Cli) -> None:
    err = await cli.fails(EXIT_CNC, "param", "get", "1320")  # axis item without an axis
    assert err == (
        "focas-net: EW_ATTRIB (4): data attribute / data type error (cnc_rdparam); "
        "parameter 1320 is an axis parameter: give --axis 1..3"
    )
    err = await cli.fails(EXIT_CNC, "param", "get", "9999")
    assert err.startswith("focas-net: EW_NUMBER (3): data number / address range error")
    err = await cli.fails(EXIT_USAGE, "param", "get", "1815.8", "--axis", "1")
    assert err == "focas-net: bit 8 is outside 0..7: parameter 1815 is 1 byte wide"


async def test_param_set_needs_mdi_and_pwe(cli: Cli) -> None:
    err = await cli.fails(EXIT_CNC, "param", "set", "1320", "5000", "--axis", "1")
    assert err.startswith("focas-net: EW_PASSWD (17): protection / password error (cnc_wrparam)")
    assert "--pwe on" in err
    assert cli.served.machine.read_param(1320, 1) == 999_999_999  # nothing changed

    await cli.ok("sim", "panel", "--mode", "MDI", "--pwe", "on")
    out = await cli.ok("param", "set", "1320", "5000", "--axis", "1")
    assert out.strip() == "1320 axis 1 = 5000 (0x00001388), two-word parameter (written)"
    assert cli.served.machine.read_param(1320, 1) == 5000
    data = await cli.json("param", "set", "3216", "0x20", "--width", "2")
    assert data == {"number": 3216, "axis": 0, "value": 32, "width": 2, "type": "word"}

    data = await cli.json("param", "set", "1815.0", "1", "--axis", "2")
    assert (data["value"], data["bit_value"]) == (0b0011_0001, 1)
    out = await cli.ok("param", "set", "1815.5", "off", "--axis", "2")
    assert out.startswith("1815.5 axis 2 = 0; 1815 axis 2 = 17 (00010001), bit parameter")
    assert cli.served.machine.read_param(1815, 1) == 0b0011_0000  # other axes untouched

    err = await cli.fails(EXIT_CNC, "param", "set", "3216", "5", "--width", "4")
    assert err.startswith("focas-net: EW_LENGTH (2)")
    err = await cli.fails(EXIT_CNC, "param", "set", "3216", "10000")  # outside 0..9999
    assert err.startswith("focas-net: EW_DATA (5)")
    err = await cli.fails(EXIT_USAGE, "param", "set", "3216", "99999")  # not an i16 at all
    assert "parameter 3216 is a word parameter: 99999 is outside -32768..32767" in err


async def test_param_set_with_password(locked_cli: Cli) -> None:
    cli = locked_cli
    await cli.ok("sim", "panel", "--mode", "MDI", "--pwe", "on")
    err = await cli.fails(EXIT_CNC, "param", "set", "6711", "42")
    assert err.startswith("focas-net: EW_PASSWD (17): protection / password error")
    err = await cli.fails(EXIT_CNC, "param", "set", "6711", "42", "--password", "nope")
    assert err.startswith("focas-net: EW_PASSWD (17)")
    data = await cli.json("param", "set", "6711", "42", "--password", "1234")
    assert data["value"] == 42
    assert cli.served.machine.read_param(6711, 0) == 42


async def test_unlock(locked_cli: Cli) -> None:
    out = await locked_cli.ok("unlock", "1234")
    assert out.startswith("password accepted")
    assert await locked_cli.json("unlock", "1234") == {"unlocked": True, "password_set": True}
    err = await locked_cli.fails(EXIT_CNC, "unlock", "4321")
    assert err == (
        "focas-net: EW_PASSWD (17): protection / password error (cnc_wrunlockparam); "
        "the password is not the CNC's"
    )


async def test_diag(cli: Cli) -> None:
    assert (await cli.ok("diag", "308", "--axis", "1")).strip() == "308 axis 1 = 31"
    assert await cli.json("diag", "410") == {"number": 410, "axis": 0, "value": 0}
    err = await cli.fails(EXIT_CNC, "diag", "300")
    assert err.startswith("focas-net: EW_ATTRIB (4)")


async def test_macro(cli: Cli) -> None:
    assert (await cli.ok("macro", "get", "100")).strip() == "#100 = <vacant>"
    assert await cli.json("macro", "get", "100") == {"number": 100, "value": None}
    assert (await cli.ok("macro", "set", "100", "12.50")).strip() == "#100 = 12.50 (written)"
    assert await cli.json("macro", "get", "100") == {"number": 100, "value": "12.50"}
    data = await cli.json("macro", "set", "500", "-3")
    assert data == {"number": 500, "value": "-3"}
    value = cli.served.machine.read_macro(500)
    assert value is not None and value.as_tuple() == (1, (3,), 0)
    assert Decimal(data["value"]) == -3


async def test_macro_errors(cli: Cli) -> None:
    err = await cli.fails(EXIT_USAGE, "macro", "set", "100", "1" + "0" * 30, prefix="focas-net")
    assert "1000000000000000000000000000000 does not fit a macro variable: give at most 9" in err
    err = await cli.fails(EXIT_USAGE, "macro", "set", "100", "1e30", prefix="focas-net")
    assert "not a number: '1e30' (no exponent: write the digits)" in err
    err = await cli.fails(EXIT_USAGE, "macro", "set", "100", "twelve", prefix="focas-net")
    assert "not a number" in err
    err = await cli.fails(EXIT_CNC, "macro", "set", "4001", "1")  # modal G code: read-only
    assert err.startswith("focas-net: EW_PROT (7): write-protected")
    err = await cli.fails(EXIT_CNC, "macro", "get", "3000")
    assert err.startswith("focas-net: EW_NUMBER (3)")


# -- PMC ------------------------------------------------------------------------------------


async def test_pmc_write_and_read(cli: Cli) -> None:
    out = await cli.ok("pmc", "write", "R", "10", "1", "2", "0xff")
    assert out.strip() == "wrote 3 bytes to R10..R12: 01 02 ff"
    data = await cli.json("pmc", "read", "R", "10", "3")
    assert data == {"area": "R", "start": 10, "count": 3, "hex": "0102ff", "data": [1, 2, 255]}
    await cli.ok("pmc", "write", "D", "0", "--hex", "00 11 22 33")
    out = await cli.ok("pmc", "read", "D", "0", "20")
    assert out.splitlines() == [
        "D0000  00 11 22 33 " + " ".join(["00"] * 12),
        "D0016  00 00 00 00",
    ]
    data = await cli.json("pmc", "write", "G", "100", "1,2,3")
    assert data["count"] == 3 and data["hex"] == "010203"


async def test_pmc_chunked_range(cli: Cli) -> None:
    payload = bytes(range(100))
    await cli.ok("pmc", "write", "D", "1000", "--hex", payload.hex())
    data = await cli.json("pmc", "read", "D", "1000", "100")
    assert bytes(data["data"]) == payload and data["count"] == 100


async def test_pmc_errors(cli: Cli) -> None:
    err = await cli.fails(EXIT_CNC, "pmc", "write", "X", "0", "1")
    assert err.startswith("focas-net: EW_PROT (7): write-protected (pmc_wrpmcrng); PMC area X")
    err = await cli.fails(EXIT_CNC, "pmc", "read", "E", "0")
    assert err == (
        "focas-net: EW_NOOPT (6): option not installed (pmc_rdpmcrng); the CNC has no PMC area E"
    )
    err = await cli.fails(EXIT_CNC, "pmc", "read", "K", "99", "2")
    assert err.startswith("focas-net: EW_NUMBER (3)")
    err = await cli.fails(
        EXIT_USAGE, "pmc", "write", "R", "0", "1", "--hex", "02", prefix="focas-net"
    )
    assert "argument --hex: not allowed with BYTE values" in err
    err = await cli.fails(EXIT_USAGE, "pmc", "write", "R", "0", "256", prefix="focas-net")
    assert "outside 0..255" in err
    err = await cli.fails(EXIT_USAGE, "pmc", "write", "R", "0", prefix="focas-net")
    assert "no data bytes" in err
    err = await cli.fails(EXIT_USAGE, "pmc", "bit", "R", "10", prefix="focas-net")
    assert "BYTE.BIT" in err
    # --force writes protected inputs through simulator control
    await cli.ok("pmc", "write", "X", "5", "0x80", "--force")
    assert (await cli.json("pmc", "read", "X", "5"))["data"] == [0x80]


async def test_pmc_bit(cli: Cli) -> None:
    await cli.ok("pmc", "write", "R", "20", "0x0f")
    assert (await cli.ok("pmc", "bit", "R", "20.7", "1")).strip() == "R20.7 = 1 (written)"
    assert (await cli.ok("pmc", "bit", "R", "20.0", "off")).strip() == "R20.0 = 0 (written)"
    assert await cli.json("pmc", "bit", "R", "20.7") == {
        "area": "R",
        "byte": 20,
        "bit": 7,
        "value": 1,
    }
    assert (await cli.json("pmc", "read", "R", "20"))["data"] == [0x8E]


# -- alarms ---------------------------------------------------------------------------------


async def test_alarms_and_history(cli: Cli) -> None:
    assert (await cli.ok("alarms")).strip() == "active alarms: 0"
    out = await cli.ok("sim", "alarm", "PS0100", "PARAMETER WRITE ENABLE")
    assert out.strip() == "raised PS0100 PARAMETER WRITE ENABLE"
    await cli.ok("sim", "alarm", "SV401", "SERVO", "V-READY", "OFF", "--axis", "2")
    out = await cli.ok("alarms", "--history", "5")
    lines = out.splitlines()
    assert lines[:3] == [
        "active alarms: 2",
        "  PS0100 PARAMETER WRITE ENABLE",
        "  SV0401 (axis 2) SERVO V-READY OFF",
    ]
    assert lines[3] == "alarm history, newest first: 2"
    assert lines[4].endswith("Z SV0401 (axis 2) SERVO V-READY OFF")
    assert lines[5].endswith("Z PS0100 PARAMETER WRITE ENABLE")
    data = await cli.json("alarms", "--history", "1")
    assert [a["code"] for a in data["active"]] == ["PS0100", "SV0401"]
    assert data["active"][1] == {
        "code": "SV0401",
        "axis_no": 2,
        "alm_type": 6,
        "alm_no": 401,
        "msg": "SERVO V-READY OFF",
    }
    assert [h["code"] for h in data["history"]] == ["SV0401"]
    datetime.strptime(data["history"][0]["occurred_at"], "%Y-%m-%dT%H:%M:%SZ")

    out = await cli.ok("sim", "clear", "PS")
    assert out.strip() == "cleared PS0100; 1 still active"
    data = await cli.json("sim", "clear")
    assert data["cleared"] == "all" and data["active"] == []
    assert [a["code"] for a in data["alarms"]] == ["SV0401"]
    assert "history" not in await cli.json("alarms")


async def test_sim_alarm_reports_the_message_as_the_cnc_keeps_it(cli: Cli) -> None:
    long = "M" * 40
    out = await cli.ok("sim", "alarm", "PS0102", long)
    assert out.strip() == "raised PS0102 " + "M" * 32
    data = await cli.json("alarms")
    assert data["active"][0]["msg"] == "M" * 32
    raised = await cli.json("sim", "alarm", "PS0103", long)
    assert raised["raised"]["msg"] == "M" * 32


async def test_alarm_usage_errors(cli: Cli) -> None:
    err = await cli.fails(EXIT_USAGE, "sim", "alarm", "XX0100", prefix="focas-net")
    assert "unknown alarm type 'XX'" in err
    err = await cli.fails(EXIT_USAGE, "alarms", "--count", "3", prefix="focas-net")
    assert "--follow" in err
    err = await cli.fails(EXIT_CNC, "sim", "alarm", "OT0500", "--axis", "4")  # 3 axes
    assert err.startswith("focas-net: EW_ATTRIB (4)")


async def test_alarms_follow_json(server: Served, capsys: pytest.CaptureFixture[str]) -> None:
    machine = server.machine
    machine.raise_alarm(0, 3, 100, "PARAMETER WRITE ENABLE")
    capsys.readouterr()
    argv = ["alarms", "--follow", "--json", "--count", "3", "--interval", "0.05"]
    follow = asyncio.ensure_future(asyncio.to_thread(main, [*argv, "--port", str(server.port)]))
    printed = ""

    async def wait_for_line(count: int) -> None:
        nonlocal printed
        for _ in range(int(CLI_TIMEOUT / 0.01)):
            printed += capsys.readouterr().out
            if printed.count("\n") >= count or follow.done():
                return
            await asyncio.sleep(0.01)

    try:
        await wait_for_line(1)  # the alarm active at start
        machine.raise_alarm(1, 4, 500, "OVER TRAVEL")
        await wait_for_line(2)
        machine.clear_alarms(3, 100)
        code = await asyncio.wait_for(follow, CLI_TIMEOUT)
    finally:
        if not follow.done():
            for n in range(3):  # three more events: the command reaches its --count
                machine.raise_alarm(0, 3, 990 + n, "")
            await asyncio.wait_for(follow, CLI_TIMEOUT)
    out, err = capsys.readouterr()
    printed += out
    assert (code, err) == (EXIT_OK, "")
    events = [json.loads(line) for line in printed.splitlines()]
    assert [(e["event"], e["alarm"]["code"]) for e in events] == [
        ("raised", "PS0100"),
        ("raised", "OT0500"),
        ("cleared", "PS0100"),
    ]
    assert events[1]["alarm"]["axis_no"] == 1


async def test_alarms_follow_history_text(cli: Cli) -> None:
    cli.served.machine.raise_alarm(0, 3, 100, "PARAMETER WRITE ENABLE")
    code, out, err = await cli.run(
        "alarms", "--follow", "--history", "5", "--count", "2", "--interval", "0.05"
    )
    assert (code, err) == (EXIT_OK, "")
    lines = out.splitlines()
    assert lines[0] == "raised   PS0100 PARAMETER WRITE ENABLE"
    assert lines[1].startswith("history  ") and lines[1].endswith("Z PS0100 PARAMETER WRITE ENABLE")


async def test_alarms_follow_stops_on_ctrl_c(server: Served) -> None:
    server.machine.raise_alarm(0, 3, 100, "PARAMETER WRITE ENABLE")
    proc = await focas_net_process("alarms", "--follow", "--interval", "0.05", *at(server))
    async with killed_at_exit(proc):
        first = await asyncio.wait_for(proc.stdout.readline(), CLI_TIMEOUT)  # type: ignore[union-attr]
        assert first.decode() == "raised   PS0100 PARAMETER WRITE ENABLE\n"
        proc.send_signal(signal.SIGINT)
        out, err = await asyncio.wait_for(proc.communicate(), CLI_TIMEOUT)
    assert proc.returncode == EXIT_OK
    assert err == b""
    assert out == b""  # nothing new after the first event


# -- unlock / VersaMax ----------------------------------------------------------------------


async def test_versamax(cli: Cli) -> None:
    out = await cli.ok("versamax", "0", "3")
    assert out.startswith("rack 0 slot 3: D844, 16 inputs, 16 outputs")
    assert "0x8080 (discrete dc, 0 in, 16 out)" in out
    assert "defaults defined, fault reporting on" in out
    data = await cli.json("versamax", "0", "3")
    assert data["label"] == "D844"
    assert data["primary_id"]["id"] == "0x8080" and data["secondary_id"]["inputs"] == 16
    assert [(r["type"], r["offset"], r["bytes"]) for r in data["references"]] == [
        ("%I", 17, 2),
        ("%Q", 8, 2),
    ]
    assert (await cli.json("versamax", "0", "1"))["label"] == "GBI1"
    err = await cli.fails(EXIT_CNC, "versamax", "0", "2")
    assert err == (
        "focas-net: EW_NUMBER (3): data number / address range error (versamax_rdconfig); "
        "rack 0 slot 2 holds no module"
    )


# -- simulator control and faults -----------------------------------------------------------


async def test_sim_fault_error(cli: Cli) -> None:
    out = await cli.ok("sim", "fault", "error", "--arg", "EW_BUSY")
    assert out.strip() == "the next answer of this machine: answered with EW_BUSY (-1): busy, retry"
    err = await cli.fails(EXIT_CNC, "status")
    assert err == "focas-net: EW_BUSY (-1): busy, retry (cnc_statinfo)"
    await cli.ok("status")  # the fault was used up
    data = await cli.json("sim", "fault", "error", "--arg", "7", "--count", "2")
    assert data == {
        "kind": "error",
        "scope": "machine",
        "count": 2,
        "arg": 7,
        "queued_behind": 0,
        "first_answer": 1,
        "last_answer": 2,
    }
    for _ in range(2):
        err = await cli.fails(EXIT_CNC, "sysinfo")
        assert err.startswith("focas-net: EW_PROT (7)")
    await cli.ok("sysinfo")


async def test_sim_fault_delay_times_out(cli: Cli) -> None:
    await cli.ok("sim", "fault", "delay", "--arg", "1500")
    err = await cli.fails(EXIT_CONNECTION, "status", "--timeout", "0.2")
    assert err.startswith("focas-net: timed out after 0.2 s: no answer to cnc_rdcncstat")
    assert err.count("127.0.0.1:") == 1, err


async def test_sim_fault_drop_is_a_connection_error(cli: Cli) -> None:
    await cli.ok("sim", "fault", "drop")
    err = await cli.fails(EXIT_CONNECTION, "param", "get", "3216")
    assert "closed" in err or "lost" in err


#: How ``sim fault`` refuses its ``--arg``: as the parser refuses an option.
FAULT = "focas-net sim fault: error: argument --arg: "
SEE_FAULT = "; see focas-net sim fault --help"


async def test_sim_fault_usage(cli: Cli) -> None:
    err = await cli.fails(EXIT_USAGE, "sim", "fault", "error", prefix="focas-net")
    assert "--arg" in err
    err = await cli.fails(
        EXIT_USAGE, "sim", "fault", "error", "--arg", "EW_NOSUCH", prefix="focas-net"
    )
    assert "unknown EW code" in err
    # the server's ranges, checked before anything is sent
    err = await cli.fails(EXIT_USAGE, "sim", "fault", "delay", "--arg", "70000", prefix="focas-net")
    assert err == f"{FAULT}a delay is 0..60000 ms, got 70000{SEE_FAULT}"
    err = await cli.fails(EXIT_USAGE, "sim", "fault", "error", "--arg", "0", prefix="focas-net")
    assert err == f"{FAULT}an error fault's EW code is a nonzero -32768..32767, got 0{SEE_FAULT}"
    err = await cli.fails(EXIT_USAGE, "sim", "fault", "drop", "--arg", "5", prefix="focas-net")
    assert err == f"{FAULT}does not apply to a drop fault{SEE_FAULT}"


async def test_control_disabled(capsys: pytest.CaptureFixture[str]) -> None:
    async with serving(default_machine(control_enabled=False)) as served:
        cli = Cli(served, capsys)
        err = await cli.fails(EXIT_CNC, "sim", "alarm", "PS0100")
        assert err.startswith("focas-net: EW_FUNC (1): function not available (sim_raise_alarm); ")
        assert err.endswith(
            "the server takes no simulator control commands (a real CNC, or serve --no-control)"
        )
        await cli.ok("status")


# -- connection and protocol failures -------------------------------------------------------


async def test_connection_refused(cli: Cli) -> None:
    port = free_port()
    code, out, err = await cli.run("status", port=port)
    assert (code, out) == (EXIT_CONNECTION, "")
    assert err.startswith(f"focas-net: cannot connect to 127.0.0.1:{port}")
    assert err.count("\n") == 1


async def test_protocol_violation(capsys: pytest.CaptureFixture[str]) -> None:
    """A peer whose status answer is 3 bytes short: exit 4, one line."""

    async def peer(reader: asyncio.StreamReader, writer: asyncio.StreamWriter) -> None:
        decoder = FrameDecoder()
        try:
            while True:
                chunk = await reader.read(4096)
                if not chunk:
                    break
                for frame in decoder.feed(chunk):
                    payload = struct.pack("<h", 0) + bytes(15)  # ODBST needs 18 bytes
                    writer.write(encode_frame(frame.command, frame.request_id, payload))
        finally:
            writer.close()

    srv = await asyncio.start_server(peer, "127.0.0.1", 0)
    try:
        port = srv.sockets[0].getsockname()[1]
        code = await asyncio.wait_for(
            asyncio.to_thread(main, ["status", "--port", str(port)]), CLI_TIMEOUT
        )
        out, err = capsys.readouterr()
    finally:
        srv.close()
        await srv.wait_closed()
    assert (code, out) == (EXIT_PROTOCOL, "")
    assert err.startswith("focas-net: ") and err.count("\n") == 1


def test_usage_errors_exit_2(capsys: pytest.CaptureFixture[str]) -> None:
    for argv in (
        ["status", "--port", "70000"],
        ["status", "--timeout", "0"],
        ["pmc", "read", "Q", "0"],
        ["param", "set", "1320", "1", "--width", "3"],
        ["sim", "fault", "explode"],
        ["sim", "panel", "--mode", "TURBO"],
        ["param"],
    ):
        with pytest.raises(SystemExit) as info:
            main(argv)
        assert info.value.code == EXIT_USAGE, argv
    # errors found after parsing, before connecting: one line, exit 2, no connection tried
    assert main(["param", "get", "abc", "--port", "1"]) == EXIT_USAGE
    assert main(["param", "set", "1815.1", "maybe", "--port", "1"]) == EXIT_USAGE
    assert main(["param", "set", "1815.1", "1", "--width", "1", "--port", "1"]) == EXIT_USAGE
    assert main(["pmc", "bit", "R", "-1.0", "1", "--port", "1"]) == EXIT_USAGE
    err = capsys.readouterr().err.splitlines()
    assert err.pop() == (
        "focas-net pmc bit: error: argument BYTE.BIT: PMC start address -1 is outside 0..65535; "
        "see focas-net pmc bit --help"
    )
    assert err[-3:] == [
        "focas-net param get: error: argument NUMBER[.BIT]: expected NUMBER or NUMBER.BIT "
        "(e.g. 1815 or 1815.0), got 'abc'; see focas-net param get --help",
        "focas-net param set: error: argument VALUE: expected 1, on, true, yes or set, or 0, "
        "off, false, no or clear, got 'maybe'; see focas-net param set --help",
        "focas-net param set: error: argument --width: does not apply to a bit write "
        "(NUMBER.BIT); see focas-net param set --help",
    ]


def test_every_command_has_the_common_options(capsys: pytest.CaptureFixture[str]) -> None:
    leaves = [
        ["status"], ["sysinfo"], ["param", "get"], ["param", "set"], ["macro", "get"],
        ["macro", "set"], ["diag"], ["pmc", "read"], ["pmc", "write"], ["pmc", "bit"],
        ["alarms"], ["unlock"], ["versamax"], ["sim", "panel"], ["sim", "alarm"],
        ["sim", "clear"], ["sim", "fault"],
    ]  # fmt: skip
    writes = {("param", "set"), ("macro", "set"), ("pmc", "write"), ("pmc", "bit")}
    for leaf in leaves:
        with pytest.raises(SystemExit) as info:
            main([*leaf, "--help"])
        assert info.value.code == 0
        text = capsys.readouterr().out
        for option in ("--host", "--port", "--timeout", "--json"):
            assert option in text, (leaf, option)
        assert ("--password" in text) == (tuple(leaf) in writes), leaf
        assert "exit status: 0 success, 1 CNC error" in text


# -- formatting helpers ---------------------------------------------------------------------


def test_status_formatting() -> None:
    st = StatusInfo(0, 1, 3, 3, 1, 1, 1, 1, 0)
    assert fmt.status_summary(st) == (
        "mode=EDIT run=STRT motion=MTN mstb=FIN emergency=EMG alarm=ALM edit=****"
    )
    rows = {r[0]: r for r in fmt.status_rows(st, "MT")}  # a compound machine selects T/M
    assert rows["run"] == ("run", "3", "STRT", "cycle start (running)")
    assert rows["tmmode"][2] == "M"
    assert fmt.status_dict(st, None)["emergency"] == {
        "value": 1,
        "name": "EMG",
        "meaning": "emergency stop",
    }
    odd = StatusInfo(0, 0, 42, 0, 0, 0, 0, 0, 99)
    assert fmt.status_summary(odd).startswith("mode=42 ")
    assert fmt.field_name(AlarmState, 3) == ("FAN", "fan alarm (CNC or servo amplifier)")
    assert fmt.field_name(EditState, 99) == ("99", "unknown value")
    assert fmt.field_name(AutMode, 0) == ("MDI", "manual data input")
    assert fmt.field_name(AutMode, 10) == ("RMT", "remote (DNC) operation")
    assert [f for f, _ in fmt.STATUS_FIELDS] == [
        "mode", "run", "motion", "mstb", "emergency", "alarm", "edit", "tmmode", "hdck",
    ]  # fmt: skip
    assert {status_member(f) for f, _ in fmt.STATUS_FIELDS} == {
        f.name for f in dataclasses.fields(StatusInfo)
    }


def test_sysinfo_formatting() -> None:
    info = SysInfo(2, 8, b" 0", b" M", b"D4F1", b"32.0", b"03")
    assert fmt.sysinfo_dict(info)["cnc_type"] == "0"
    rows = {r[0]: r for r in fmt.sysinfo_rows(info)}
    assert rows["cnc_type"][2] == "Series 0i"
    assert rows["mt_type"][2].startswith("machining center")
    assert rows["axes"] == ("axes", "03", "3 controlled axes")
    info = SysInfo(0, 4, b"31", b" T", b"G4F1", b"01.0", b"??")
    rows = {r[0]: r for r in fmt.sysinfo_rows(info)}
    assert rows["cnc_type"][2] == "Series 31i" and rows["axes"][2] == ""


def test_alarm_formatting() -> None:
    assert fmt.alarm_code(3, 100) == "PS0100"
    assert fmt.alarm_code(6, 401) == "SV0401"
    assert fmt.alarm_code(19, 12345) == "PC12345"
    assert fmt.alarm_code(14, 1) == "T14:0001"  # no name for type 14
    assert fmt.format_active_alarm(ActiveAlarm(0, 3, 100, "PARAMETER WRITE ENABLE")) == (
        "PS0100 PARAMETER WRITE ENABLE"
    )
    assert fmt.format_active_alarm(ActiveAlarm(2, 4, 500, "")) == "OT0500 (axis 2)"
    when = datetime(2024, 5, 1, 12, 0, 7, tzinfo=UTC)
    entry = AlarmHistoryEntry(when, 1, 6, 401, "SERVO")
    assert fmt.format_history_entry(entry) == "2024-05-01T12:00:07Z SV0401 (axis 1) SERVO"
    assert fmt.history_dict(entry)["occurred_at"] == "2024-05-01T12:00:07Z"
    assert fmt.alarm_dict(ActiveAlarm(0, 0, 5, "x"))["code"] == "SW0005"


def test_alarm_parsing() -> None:
    assert fmt.parse_alarm("PS0100") == (3, 100)
    assert fmt.parse_alarm("ps100") == (3, 100)
    assert fmt.parse_alarm(" sv0401 ") == (6, 401)
    assert fmt.parse_alarm("14:7") == (14, 7)
    for bad in ("PS", "P0100", "0100", "PS-1", "XX0100", ""):
        with pytest.raises(ValueError):
            fmt.parse_alarm(bad)
    assert fmt.parse_alarm_filter(None) == (-1, -1)
    assert fmt.parse_alarm_filter("OT") == (4, -1)
    assert fmt.parse_alarm_filter("OT0500") == (4, 500)
    with pytest.raises(ValueError, match="unknown alarm type"):
        fmt.parse_alarm_filter("QQ")


def test_value_parsing() -> None:
    assert fmt.parse_number_bit("1815") == (1815, None)
    assert fmt.parse_number_bit("1815.0") == (1815, 0)
    assert fmt.parse_number_bit("0x717.4") == (1815, 4)  # as every whole number is read
    assert fmt.parse_number_bit("-1") == (-1, None)  # (the clients' range check refuses it)
    for bad in ("1815.", ".1", "18a", "1.2.3", "1e3"):
        with pytest.raises(ValueError):
            fmt.parse_number_bit(bad)
    assert fmt.parse_int("0x1F") == 31 and fmt.parse_int("-5") == -5
    assert fmt.parse_int("0b101") == 5 and fmt.parse_int("0x1_F") == 31
    for bad in ("five", "1_000", "1e3"):  # digits as a CNC's keys write them, as on the page
        with pytest.raises(ValueError, match="not a whole number"):
            fmt.parse_int(bad)
    assert [fmt.parse_bool(t) for t in ("1", "ON", "true", "0", "off", "No")] == [
        True, True, True, False, False, False,
    ]  # fmt: skip
    with pytest.raises(ValueError):
        fmt.parse_bool("2")
    assert fmt.parse_hex("01ff") == b"\x01\xff"
    assert fmt.parse_hex("0x01 FF:10") == b"\x01\xff\x10"
    for bad in ("0g", "123", "", "0x"):
        with pytest.raises(ValueError):
            fmt.parse_hex(bad)
    assert fmt.parse_byte_list(["1", "2,0xff", "0b1"]) == b"\x01\x02\xff\x01"
    with pytest.raises(ValueError):
        fmt.parse_byte_list(["-1"])
    with pytest.raises(ValueError):
        fmt.parse_byte_list([" , "])
    assert fmt.parse_aut("mdi") == 0 and fmt.parse_aut("MEM") == 1 and fmt.parse_aut("10") == 10
    assert fmt.parse_aut(" tjog ") is AutMode.TJOG and fmt.parse_aut("03") is AutMode.EDIT
    for bad in ("****", "2", "NOSEL", "2x", "11", "-1", ""):
        with pytest.raises(ValueError, match=r"unknown mode .* \(one of MDI, MEM, EDIT, HND, "):
            fmt.parse_aut(bad)
    assert fmt.parse_ew("EW_PASSWD") == 17 and fmt.parse_ew("busy") == -1
    assert fmt.parse_ew("-16") == -16 and fmt.parse_ew("0x11") == 17


def test_tables_and_dumps() -> None:
    table = fmt.render_table(("a", "long header"), [("xyz", "1"), ("q", "")])
    assert table.splitlines() == ["a    long header", "xyz  1", "q"]
    assert fmt.render_table(None, []) == ""
    assert fmt.hexdump("R", 8, bytes(range(18))).splitlines() == [
        "R0008  00 01 02 03 04 05 06 07 08 09 0a 0b 0c 0d 0e 0f",
        "R0024  10 11",
    ]
    assert fmt.hexdump("D", 9990, b"\xaa\xbb", per_line=1).splitlines() == [
        "D9990  aa",
        "D9991  bb",
    ]
    assert fmt.hexdump("D", 99_999, b"\x01") == "D99999  01"
    assert fmt.utc_text(datetime(2024, 1, 2, 3, 4, 5)) == "2024-01-02T03:04:05Z"
    assert fmt.macro_text(None) == "<vacant>" and fmt.macro_text(Decimal("1.50")) == "1.50"


def test_module_formatting() -> None:
    record = mdd844_record()
    data = fmt.module_dict(0, 3, record)
    assert data["label"] == "D844" and (data["inputs"], data["outputs"]) == (16, 16)
    assert data["defaults_defined"] and data["fault_reporting"]
    assert data["references"][0] == {
        "sequence": 1,
        "type": "%I",
        "offset": 17,
        "bytes": 2,
        "defaults_offset": data["references"][0]["defaults_offset"],
    }
    lines = fmt.module_lines(0, 3, record)
    assert lines[0] == "rack 0 slot 3: D844, 16 inputs, 16 outputs"
    assert "%Q" in lines[2]
    json.dumps(data)  # JSON-ready


def test_error_line() -> None:
    assert fmt.error_line(AccessDeniedError(17, "cnc_wrparam")) == (
        "EW_PASSWD (17): protection / password error (cnc_wrparam)"
    )
    assert fmt.error_line(CncError(-1)) == "EW_BUSY (-1): busy, retry"
    assert fmt.error_line(CncError(99, "x")) == "EW_UNKNOWN(99): unknown return code (x)"
    assert fmt.error_line(FocasTimeoutError("no\nanswer")) == "no answer"
    assert fmt.error_line(ValueError()) == "ValueError"


# -- program numbers, feed, spindle, positions ----------------------------------------------------


async def test_program_table_and_json(cli: Cli) -> None:
    cli.served.machine.set_motion(
        feed=1500, spindle_speed=3000, program_running=1234, program_main=1000
    )
    out = await cli.ok("program")
    rows = [line.split()[:2] for line in out.splitlines()]
    assert rows[0] == ["item", "value"]
    assert ["running", "O1234"] in rows and ["main", "O1000"] in rows
    assert ["feed", "1500"] in rows and ["spindle", "3000"] in rows
    assert await cli.json("program") == {
        "program_running": 1234,
        "program_main": 1000,
        "feed": 1500,
        "spindle_speed": 3000,
    }


async def test_position_table_and_json(cli: Cli) -> None:
    cli.served.machine.set_motion(absolute=[12345, -2, 100_000], machine=[1, 2, 3])
    out = await cli.ok("position")
    lines = out.splitlines()
    assert lines[0] == "absolute position"
    assert lines[2].split() == ["axis", "position", "increments"]
    assert [line.split() for line in lines[3:]] == [
        ["X", "12.345", "12345"],
        ["Y", "-0.002", "-2"],
        ["Z", "100.000", "100000"],
    ]
    data = await cli.json("position", "--kind", "machine", "--axis", "3")
    assert data == {
        "kind": "machine",
        "decimals": 3,
        "axes": [{"name": "Z", "position": "0.003", "increments": 3}],
    }
    data = await cli.json("position", "--kind", "distance")
    assert data["kind"] == "distance" and [a["name"] for a in data["axes"]] == ["X", "Y", "Z"]


async def test_position_errors(cli: Cli) -> None:
    err = await cli.fails(EXIT_CNC, "position", "--axis", "4")
    assert "EW_ATTRIB" in err and "cnc_rdposition" in err


@pytest.mark.parametrize("argv", [["--kind", "skip"], ["--axis", "0"], ["--axis", "x"]])
def test_position_usage_errors(argv: list[str], capsys: pytest.CaptureFixture[str]) -> None:
    with pytest.raises(SystemExit) as info:  # argparse refuses before connecting
        main(["position", *argv])
    assert info.value.code == EXIT_USAGE
    assert "focas-net position: error:" in capsys.readouterr().err


def test_program_and_position_formatting() -> None:
    data = fmt.program_dict(ProgramNumbers(0, 7), 0, 12)
    assert fmt.program_rows(data)[:2] == [
        ("running", "none", "program being executed (cnc_rdprgnum)"),
        ("main", "O0007", "main program (cnc_rdprgnum)"),
    ]
    pos = fmt.positions_dict("relative", 3, {"A1": Decimal("-1.500")}, {"A1": -1500})
    assert fmt.positions_rows(pos) == [("A1", "-1.500", "-1500")]
