"""The native client sends what FANUC's library sends, byte for byte, in both command sets.

The captures of ``tests/data/fwlib_v2.json`` (16i class) and ``fwlib_v3.json`` (30i class)
hold every frame libfwlib32 1.0.5 sent for a list of calls and the answer it got. A replay
peer answers the client with exactly those answers; every call of the capture that a client
method makes is made through the client, and the frames the client sent (open requests on A
and B, the connect-time data requests, every data request of the call, the closes on A and B)
must equal the library's. Where a capture's call made the library return an EW code, the
client must raise :class:`CncError` with that code.

``cnc_wrparam`` leaves the slots it does not write as the library's buffer held them; the
client keeps the same buffer, and before each write the test loads it with the slots the
library's buffer held then (the library's all-axes writes, which the client does not make,
changed them).
"""

from __future__ import annotations

import asyncio
import json
from collections import deque
from collections.abc import Awaitable, Callable
from decimal import Decimal
from pathlib import Path
from typing import Any

import pytest
from support import IO_TIMEOUT, LoopbackPeer

from focas_net.client.native import NativeClient
from focas_net.errors import CncError, PayloadError
from focas_net.native import FrameType, NativePmcArea, ScaledNumber
from focas_net.native.frame import NATIVE_HEADER, NATIVE_HEADER_SIZE

DATA = Path(__file__).with_name("data")
VERSIONS = (2, 3)


def capture(version: int) -> dict[str, Any]:
    data: dict[str, Any] = json.loads((DATA / f"fwlib_v{version}.json").read_text())
    return data


class ReplayPeer(LoopbackPeer):
    """Answers each frame with the captured answer; records what each connection received."""

    def __init__(self, opens: dict[int, bytes], closes: dict[str, bytes]) -> None:
        self.opens = opens
        self.closes = closes
        self.answers: deque[bytes] = deque()
        self.received: dict[str, list[bytes]] = {"A": [], "B": []}
        self.unexpected: list[bytes] = []

    async def _serve(self, reader: asyncio.StreamReader, writer: asyncio.StreamWriter) -> None:
        side = "?"
        try:
            while True:
                head = await reader.readexactly(NATIVE_HEADER_SIZE)
                _, _, frame_type, length = NATIVE_HEADER.unpack(head)
                frame = head + await reader.readexactly(length)
                if frame_type == FrameType.OPEN_REQUEST:
                    channel = int.from_bytes(frame[-2:], "big")
                    side = "A" if channel == 1 else "B"
                    self.received[side].append(frame)
                    writer.write(self.opens[channel])
                elif frame_type == FrameType.CLOSE_REQUEST:
                    self.received[side].append(frame)
                    writer.write(self.closes[side])
                elif self.answers:
                    self.received[side].append(frame)
                    writer.write(self.answers.popleft())
                else:
                    self.unexpected.append(frame)
                    break
                await writer.drain()
        except (asyncio.IncompleteReadError, ConnectionError):
            pass
        finally:
            writer.close()


def _action(client: NativeClient, call: dict[str, Any]) -> Callable[[], Awaitable[Any]] | None:
    """The client method making ``call`` of the capture, or None when no method makes it."""
    f = call["function"]
    a = call["arguments"]
    c = client
    simple: dict[str, Callable[[], Awaitable[Any]]] = {
        "cnc_sysinfo": c.read_sysinfo,
        "cnc_statinfo": c.read_status,
        "cnc_alarm": c.read_alarm_status,
        "cnc_alarm2": c.read_alarm_status,
        "cnc_rdprgnum": c.read_program_numbers,
        "cnc_rdprgnumo8": c.read_program_numbers,
        "cnc_exeprgname": c.read_program_name,
        "cnc_rdseqnum": c.read_sequence_number,
        "cnc_rdcncid": c.read_cnc_id,
        "cnc_actf": c.read_feed,
        "cnc_acts": c.read_spindle_speed,
        "cnc_rdposition": c.read_positions,
        "cnc_rdsvmeter": c.read_servo_meters,
        "cnc_rdaxisname": c.read_axis_names,
    }
    if f in simple:
        return simple[f]
    if f == "cnc_rdmacro":
        return lambda: c.read_macro(a["number"])
    if f == "cnc_wrmacro":
        value = Decimal(a["mcr_val"]).scaleb(-a["dec_val"])
        return lambda: c.write_macro(a["number"], value)
    if f in ("cnc_rdparam", "cnc_diagnoss") and a["axis"] >= 0:
        if f == "cnc_rdparam":
            return lambda: c.read_param_value(a["number"], axis=a["axis"])
        return lambda: c.read_diag(a["number"], axis=a["axis"])
    if f == "cnc_wrparam" and a["axis"] >= 0 and isinstance(a["values"][0], int):
        return lambda: c.write_param(a["number"], a["values"][0], axis=a["axis"])
    if f in ("pmc_rdpmcrng", "pmc_wrpmcrng") and a["data_type"] == 0:
        letter = NativePmcArea(a["area"]).name
        if f == "pmc_rdpmcrng":
            return lambda: c.read_pmc(letter, a["first"], a["last"] - a["first"] + 1)
        return lambda: c.write_pmc(letter, a["first"], bytes(a["values"]))
    if f == "cnc_rdalmmsg2":
        return lambda: c.read_alarms(alm_type=a["type"], count=a["count"])
    if f == "cnc_rdtimer":
        return lambda: c.read_timer(a["type"])
    if f == "cnc_rdalmhistry" and a["first"] == 1:
        return lambda: c.read_alarm_history(a["last"])
    if f == "cnc_rddynamic2":
        return lambda: c.read_dynamic(a["axis"])
    if f == "cnc_rdspload":
        return lambda: c.read_spindle_loads(a["spindle"])
    return None


def _prime_write_buffer(client: NativeClient, version: int, call: dict[str, Any]) -> None:
    """Load the client's cnc_wrparam buffer with what the library's held before ``call``."""
    handle = client._handle
    assert handle is not None
    slots = call["values"]["record"]["slots"]
    if version == 2:
        handle.param_slots[:] = slots
    else:
        handle.param3_slots[:] = [ScaledNumber(v, d, b) for v, b, d in slots]


#: Library functions of the captures that no client method makes (and why).
NOT_MADE = {
    "cnc_rdalmmsg": "the client reads alarms with cnc_rdalmmsg2 (64-byte texts)",
    "cnc_rdmacror2": "no client method reads macros as doubles",
    "cnc_wrmacror2": "no client method writes macros as doubles",
    "cnc_rdparainfo": "no client method reads parameter information",
    "cnc_absolute": "read_positions uses cnc_rdposition",
    "cnc_machine": "read_positions uses cnc_rdposition",
    "cnc_relative": "read_positions uses cnc_rdposition",
    "cnc_distance": "read_positions uses cnc_rdposition",
    "cnc_getfocas1opt": "sends nothing",
}


async def _replay(version: int) -> tuple[set[str], int]:
    data = capture(version)
    calls = data["calls"]
    connect, free = calls[0], calls[-1]
    assert connect["function"] == "cnc_allclibhndl3" and free["function"] == "cnc_freelibhndl"
    opens = {}
    for ex in connect["exchanges"]:
        request = bytes.fromhex(ex["request"])
        if request[6:8] == b"\x01\x01":
            opens[int.from_bytes(request[-2:], "big")] = bytes.fromhex(ex["answer"])
    closes = {ex["connection"]: bytes.fromhex(ex["answer"]) for ex in free["exchanges"]}
    peer = ReplayPeer(opens, closes)
    await peer.start()
    made: set[str] = set()
    compared = 0
    closing: NativeClient | None = None
    try:
        peer.answers.extend(
            bytes.fromhex(ex["answer"])
            for ex in connect["exchanges"]
            if bytes.fromhex(ex["request"])[6:8] == b"\x21\x01"
        )
        client = NativeClient("127.0.0.1", peer.port, timeout=IO_TIMEOUT)
        await client.connect()
        closing = client
        expected_connect = [bytes.fromhex(ex["request"]) for ex in connect["exchanges"]]
        got = peer.received["A"][:1] + peer.received["B"]
        assert got == expected_connect
        compared += len(got)
        for call in calls[1:-1]:
            act = _action(client, call)
            if act is None:
                assert (
                    call["function"] in NOT_MADE
                    or call["arguments"].get("axis", 0) < 0
                    or (call["function"] in ("cnc_wrparam", "pmc_rdpmcrng", "pmc_wrpmcrng"))
                ), call
                continue
            if call["function"] == "cnc_wrparam":
                _prime_write_buffer(client, version, call)
            before = len(peer.received["B"])
            expected = [bytes.fromhex(ex["request"]) for ex in call["exchanges"]]
            peer.answers.extend(bytes.fromhex(ex["answer"]) for ex in call["exchanges"])
            try:
                await act()
            except CncError as exc:
                assert call["return"] == exc.ew, call
            except PayloadError:
                # A real-number parameter or diagnostic: sent like the library, refused by
                # the client's integer result type.
                assert call["function"] in ("cnc_rdparam", "cnc_diagnoss"), call
            else:
                assert call["return"] == 0, call
            assert peer.received["B"][before:] == expected, call
            assert not peer.answers, call
            compared += len(expected)
            made.add(call["function"])
        await client.aclose()
        assert [peer.received["A"][-1], peer.received["B"][-1]] == [
            bytes.fromhex(ex["request"]) for ex in free["exchanges"]
        ]
        assert not peer.unexpected
    finally:
        if closing is not None:
            await closing.aclose()
        await peer.stop()
    return made, compared


@pytest.mark.parametrize("version", VERSIONS)
async def test_every_client_request_is_the_librarys(version: int) -> None:
    made, compared = await _replay(version)
    assert made >= {
        "cnc_sysinfo", "cnc_statinfo", "cnc_rdmacro", "cnc_wrmacro", "cnc_rdparam",
        "cnc_wrparam", "cnc_diagnoss", "pmc_rdpmcrng", "pmc_wrpmcrng", "cnc_rdalmmsg2",
        "cnc_alarm2", "cnc_rdprgnumo8", "cnc_exeprgname", "cnc_rdseqnum", "cnc_rdcncid",
        "cnc_rdtimer", "cnc_rdalmhistry", "cnc_actf", "cnc_acts", "cnc_rdposition",
        "cnc_rddynamic2", "cnc_rdspload", "cnc_rdsvmeter", "cnc_rdaxisname",
    }  # fmt: skip
    assert compared > 50
