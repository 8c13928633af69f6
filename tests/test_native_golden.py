"""Golden bytes captured from FANUC's FOCAS library (libfwlib32 1.0.5), checked with the codec.

The data files come from ``tests/fwlib_capture.py`` (run with ``FOCAS_NET_FWLIB`` set); these
tests need no library. For both command sets (answer version 2, "16i class", and version 3,
"30i class"):

* every request frame the library sent decodes to typed requests that re-encode byte for byte,
  and ``focas_net.native.calls`` predicts it from the call's arguments;
* every answer that made the library return EW_OK decodes to its record and re-encodes byte
  for byte, passes the library's checks, and carries the values the library read back;
* the binary macro conversions agree with the library on every captured case;
* the simulator's own answers, captured with the library against a real server in both command
  sets (``fwlib_sim.json``), are what the native adapter answers to the same requests today,
  and pass the library's checks.
"""

from __future__ import annotations

import json
from collections.abc import Callable, Iterator
from functools import cache
from pathlib import Path
from typing import Any

import pytest
from fwlib_capture import simulator_machine

from focas_net.adapters import NativeAdapter
from focas_net.errors import EW
from focas_net.native import (
    AlarmMessages,
    FrameType,
    ItemRecord,
    ItemValues,
    NativeAlarmHistory,
    NativeRequest,
    NativeSysInfo,
    OpenRequest,
    ParamType,
    ParamWrite3Request,
    ParamWriteRequest,
    PathDescription,
    PositionAxisNames,
    RequestBlock,
    ScaledItemValues,
    ScaledValues,
    answer_refusal,
    binary_to_decimal,
    build_open_answer,
    calls,
    decimal_to_binary,
    decode_frame,
    decode_open_answer,
    decode_request,
    decode_request_body,
    decode_response_body,
    encode_close_request,
    encode_close_response,
    encode_native_response,
    encode_open_request,
    encode_open_response,
    encode_request,
    max_response_body,
    open_answer_size,
)
from focas_net.native.calls import CommandSet, LibraryCall

DATA = Path(__file__).with_name("data")
VERSIONS = (2, 3)


@cache
def capture(version: int) -> dict[str, Any]:
    data: dict[str, Any] = json.loads((DATA / f"fwlib_v{version}.json").read_text())
    return data


def _json(name: str) -> Any:
    return json.loads((DATA / name).read_text())


def data_exchanges(version: int) -> Iterator[tuple[dict[str, Any], bytes, bytes]]:
    """(call, request frame, answer frame) of every data request the library sent."""
    for call in capture(version)["calls"]:
        for ex in call["exchanges"]:
            request = bytes.fromhex(ex["request"])
            if decode_frame(request).type == FrameType.DATA_REQUEST:
                assert ex["connection"] == "B"
                yield call, request, bytes.fromhex(ex["answer"])


def _typed(block: RequestBlock) -> NativeRequest:
    request = decode_request(block)
    assert request is not None, block
    return request


def test_captures_are_present() -> None:
    functions = {c["function"] for c in capture(2)["calls"]} | {
        c["function"] for c in capture(3)["calls"]
    }
    expected = {
        "cnc_allclibhndl3", "cnc_sysinfo", "cnc_statinfo", "cnc_rdmacro", "cnc_wrmacro",
        "cnc_rdmacror2", "cnc_wrmacror2", "cnc_rdparam", "cnc_wrparam", "cnc_rdparainfo",
        "cnc_diagnoss", "pmc_rdpmcrng", "pmc_wrpmcrng", "cnc_rdalmmsg", "cnc_rdalmmsg2",
        "cnc_alarm", "cnc_alarm2", "cnc_rdprgnum", "cnc_rdprgnumo8", "cnc_exeprgname",
        "cnc_rdseqnum", "cnc_rdcncid", "cnc_rdtimer", "cnc_rdalmhistry", "cnc_actf", "cnc_acts",
        "cnc_absolute", "cnc_machine", "cnc_relative", "cnc_distance", "cnc_rdposition",
        "cnc_rddynamic2", "cnc_rdspload", "cnc_rdsvmeter", "cnc_rdaxisname",
        "cnc_getfocas1opt", "cnc_freelibhndl",
    }  # fmt: skip
    assert functions == expected
    for version in VERSIONS:
        assert capture(version)["version"] == version
        assert CommandSet.for_version(version).value == capture(version)["command_set"]


# ---------------------------------------------------------------------------------------------
# Open and close


@pytest.mark.parametrize("version", VERSIONS)
def test_open_exchange(version: int) -> None:
    data = capture(version)
    connect = data["calls"][0]
    assert connect["function"] == "cnc_allclibhndl3"
    assert connect["return"] == 0
    opens = [ex for ex in connect["exchanges"] if bytes.fromhex(ex["request"])[6:8] == b"\1\1"]
    assert [ex["connection"] for ex in opens] == ["A", "B"]
    body = bytes.fromhex(data["open_answer"])
    for channel, ex in enumerate(opens, start=1):
        request = bytes.fromhex(ex["request"])
        assert request == encode_open_request(channel)
        assert OpenRequest.decode(decode_frame(request).body) == OpenRequest(channel)
        assert bytes.fromhex(ex["answer"]) == encode_open_response(body, version)
    path = PathDescription(" M", data["axes"], data["spindles"])
    assert build_open_answer([path], data["max_axes"], option_bits=1, version=version) == body
    assert open_answer_size(body, version) == len(body)
    opened = decode_open_answer(body, version)
    assert opened.present() == (path,)
    assert opened.max_axes == data["max_axes"]
    assert opened.encode() == body
    assert opened.option_bits == (None if version == 2 else 1)


@pytest.mark.parametrize("version", VERSIONS)
def test_close_exchange(version: int) -> None:
    (free,) = [c for c in capture(version)["calls"] if c["function"] == "cnc_freelibhndl"]
    assert free["return"] == 0
    assert [ex["connection"] for ex in free["exchanges"]] == ["A", "B"]
    for ex in free["exchanges"]:
        assert bytes.fromhex(ex["request"]) == encode_close_request()
        assert bytes.fromhex(ex["answer"]) == encode_close_response(version)


# ---------------------------------------------------------------------------------------------
# Requests


@pytest.mark.parametrize("version", VERSIONS)
def test_every_request_decodes_and_reencodes(version: int) -> None:
    count = 0
    for _, request, _ in data_exchanges(version):
        frame = decode_frame(request)
        assert frame.version == 1
        blocks = decode_request_body(frame.body)
        assert blocks
        for block in blocks:
            typed = _typed(block)
            assert typed.to_block(block.path) == block
            assert block.encode() == typed.to_block(block.path).encode()
            count += 1
        assert encode_request(blocks) == request
    assert count > 100


def _expected_call(cs: CommandSet, call: dict[str, Any], requests: list[bytes]) -> LibraryCall:
    """What ``focas_net.native.calls`` says the library sends for ``call``."""
    name = call["function"]
    a = call["arguments"]
    builders: dict[str, Callable[[], LibraryCall]] = {
        "cnc_allclibhndl3": lambda: calls.cnc_allclibhndl3(cs, a["paths"]),
        "cnc_rdmacro": lambda: calls.cnc_rdmacro(cs, a["number"]),
        "cnc_wrmacro": lambda: calls.cnc_wrmacro(cs, a["number"], a["mcr_val"], a["dec_val"]),
        "cnc_rdmacror2": lambda: calls.cnc_rdmacror2(cs, a["first"], a["count"]),
        "cnc_wrmacror2": lambda: calls.cnc_wrmacror2(cs, a["number"], a["value"]),
        "cnc_rdparam": lambda: calls.cnc_rdparam(cs, a["number"], a["axis"]),
        "cnc_rdparainfo": lambda: calls.cnc_rdparainfo(cs, a["first"], a["count"]),
        "cnc_diagnoss": lambda: calls.cnc_diagnoss(cs, a["number"], a["axis"]),
        "pmc_rdpmcrng": lambda: calls.pmc_rdpmcrng(
            cs, a["area"], a["data_type"], a["first"], a["last"]
        ),
        "pmc_wrpmcrng": lambda: calls.pmc_wrpmcrng(
            cs, a["area"], a["data_type"], a["first"], a["last"], a["values"]
        ),
        "cnc_rdalmmsg": lambda: calls.cnc_rdalmmsg(cs, a["type"], a["count"]),
        "cnc_rdalmmsg2": lambda: calls.cnc_rdalmmsg2(cs, a["type"], a["count"]),
        "cnc_rdtimer": lambda: calls.cnc_rdtimer(cs, a["type"]),
        "cnc_rdalmhistry": lambda: calls.cnc_rdalmhistry(cs, a["first"], a["last"]),
        "cnc_absolute": lambda: calls.cnc_absolute(cs, a["axis"]),
        "cnc_machine": lambda: calls.cnc_machine(cs, a["axis"]),
        "cnc_relative": lambda: calls.cnc_relative(cs, a["axis"]),
        "cnc_distance": lambda: calls.cnc_distance(cs, a["axis"]),
        "cnc_rddynamic2": lambda: calls.cnc_rddynamic2(cs, a["axis"]),
        "cnc_rdspload": lambda: calls.cnc_rdspload(cs, a["spindle"]),
    }
    if name == "cnc_wrparam":
        # the 0x0F/0x8E record carries stale bytes in unused slots: take it from the capture
        (block,) = decode_request_body(decode_frame(requests[1]).body)
        write = _typed(block)
        assert isinstance(write, ParamWriteRequest | ParamWrite3Request)
        assert (write.record.number, write.record.axis) == (a["number"], a["axis"])
        return calls.cnc_wrparam(cs, write.record)
    if name in builders:
        return builders[name]()
    built: LibraryCall = getattr(calls, name)(cs)
    return built


@pytest.mark.parametrize("version", VERSIONS)
def test_calls_table_predicts_every_frame(version: int) -> None:
    cs = CommandSet.for_version(version)
    for call in capture(version)["calls"]:
        requests = [
            bytes.fromhex(ex["request"])
            for ex in call["exchanges"]
            if decode_frame(bytes.fromhex(ex["request"])).type == FrameType.DATA_REQUEST
        ]
        if not requests:
            continue
        expected = _expected_call(cs, call, requests)
        assert expected.function == call["function"]
        assert list(expected.encode()) == requests, call["function"]
        decoded = [
            tuple(_typed(block) for block in decode_request_body(decode_frame(raw).body))
            for raw in requests
        ]
        assert decoded == list(expected.frames), call["function"]


def test_calls_differ_between_command_sets() -> None:
    assert calls.cnc_rdparam(CommandSet.FS16I, 1320, -1).frames[0][0].COMMAND == 0x0E
    assert calls.cnc_rdparam(CommandSet.FS30I, 1320, -1).frames[0][0].COMMAND == 0x8D
    assert len(calls.cnc_rdposition(CommandSet.FS16I).frames[0]) == 9
    assert len(calls.cnc_rdposition(CommandSet.FS30I).frames[0]) == 10
    assert len(calls.cnc_allclibhndl3(CommandSet.FS16I).frames) == 2
    assert len(calls.cnc_allclibhndl3(CommandSet.FS30I).frames) == 1
    history = calls.cnc_rdalmhistry(CommandSet.FS16I, 1, 50)
    assert [(f[0].first, f[0].last) for f in history.frames] == [(1, 23), (24, 46), (47, 50)]  # type: ignore[attr-defined]


# ---------------------------------------------------------------------------------------------
# Answers


@pytest.mark.parametrize("version", VERSIONS)
def test_every_answer_decodes_and_reencodes(version: int) -> None:
    max_axes = capture(version)["max_axes"]
    for call, request, answer in data_exchanges(version):
        frame = decode_frame(answer)
        assert (frame.version, frame.type) == (version, FrameType.DATA_RESPONSE)
        blocks = decode_request_body(decode_frame(request).body)
        answers = decode_response_body(frame.body)
        assert answer_refusal(frame.body, len(blocks), version) is None
        assert len(answers) == len(blocks)
        assert encode_native_response(answers, version) == answer
        for block, reply in zip(blocks, answers, strict=True):
            assert (reply.device, reply.path, reply.command) == (
                block.device,
                block.path,
                block.command,
            )
            if reply.ew:
                assert reply.data == b""
                continue
            typed = _typed(block)
            record = typed.decode_answer(reply.data, max_axes)
            assert typed.encode_answer(record) == reply.data, (call["function"], typed)
            assert isinstance(record, typed.ANSWER | PositionAxisNames)


def _answers(version: int, function: str) -> Iterator[tuple[dict[str, Any], list[Any]]]:
    """(call, decoded answers of its last data frame) of every successful ``function`` call."""
    max_axes = capture(version)["max_axes"]
    for call in capture(version)["calls"]:
        if call["function"] != function or call["return"] != 0:
            continue
        frames = [
            ex
            for ex in call["exchanges"]
            if decode_frame(bytes.fromhex(ex["request"])).type == FrameType.DATA_REQUEST
        ]
        ex = frames[-1]
        blocks = decode_request_body(decode_frame(bytes.fromhex(ex["request"])).body)
        replies = decode_response_body(decode_frame(bytes.fromhex(ex["answer"])).body)
        decoded = [
            _typed(b).decode_answer(r.data, max_axes) if not r.ew else None
            for b, r in zip(blocks, replies, strict=True)
        ]
        yield call, decoded


@pytest.mark.parametrize("version", VERSIONS)
def test_values_the_library_read_back(version: int) -> None:
    data = capture(version)
    axes = data["axes"]
    connect = data["calls"][0]
    sysinfo_answer = decode_response_body(
        decode_frame(bytes.fromhex(connect["exchanges"][2]["answer"])).body
    )[0]
    (sysinfo_call,) = [c for c in data["calls"] if c["function"] == "cnc_sysinfo"]
    assert NativeSysInfo.decode(sysinfo_answer.data) == NativeSysInfo(
        *sysinfo_call["values"]["odbsys"]
    )

    for call, (values,) in _answers(version, "cnc_rdmacro"):
        assert isinstance(values, ScaledValues)
        v = call["values"]
        assert values.values[0].to_macro() == (v["mcr_val"], v["dec_val"])

    for call, (items,) in _answers(version, "cnc_rdparam"):
        assert isinstance(items, ItemValues | ScaledItemValues)
        (rec,) = items.records
        v = call["values"]
        assert (rec.number & 0xFFFF, rec.axis) == (v["datano"], v["type"])
        count = axes if rec.axis == -1 else 1
        if rec.type == ParamType.REAL:
            if isinstance(rec, ItemRecord):
                reals = rec.reals()[:count]
            else:
                reals = rec.values[:count]
            assert [[r.mantissa, r.decimals] for r in reals] == v["data"]
        elif isinstance(rec, ItemRecord):
            width = {0: 1, 1: 1, 2: 2, 3: 4}[rec.type]
            assert [_signed(x, width) for x in rec.values[:count]] == v["data"]
        else:
            width = {0: 1, 1: 1, 2: 2, 3: 4}[rec.type]
            assert [_signed(x.mantissa, width) for x in rec.values[:count]] == v["data"]

    for call, (history,) in _answers(version, "cnc_rdalmhistry"):
        assert isinstance(history, NativeAlarmHistory)
        # the last chunk fills the end of ODBAHIS
        rows = call["values"]["records"][-len(history.records) :]
        for r, row in zip(history.records, rows, strict=True):
            assert [r.group, r.alarm_no, r.axis, r.year % 100, r.month, r.day] == row[:6]
            assert [r.hour, r.minute, r.second, r.length, r.message.decode()] == row[6:]

    for function in ("cnc_rdalmmsg", "cnc_rdalmmsg2"):
        for call, (alarms,) in _answers(version, function):
            assert isinstance(alarms, AlarmMessages)
            assert [
                [a.number, a.alarm_type, a.axis, len(a.message), a.message.decode()]
                for a in alarms.alarms
            ] == call["values"]["alarms"]

    for function in ("cnc_absolute", "cnc_machine", "cnc_relative", "cnc_distance"):
        for call, (positions,) in _answers(version, function):
            assert isinstance(positions, ScaledValues)
            assert [p.mantissa for p in positions.values[:axes]] == call["values"]["data"]

    for call, answers in _answers(version, "cnc_rdposition"):
        positions = [a for a in answers if isinstance(a, ScaledValues)]
        (names,) = [a for a in answers if isinstance(a, PositionAxisNames)]
        rows = call["values"]["positions"]
        for kind, values in enumerate(positions):
            assert [p.mantissa for p in values.values[:axes]] == [row[kind][0] for row in rows]
            assert [p.decimals for p in values.values[:axes]] == [row[kind][1] for row in rows]
        for entry, row in zip(names.records, rows, strict=False):
            _, absolute, machine, relative = entry.names()
            assert [absolute.name.decode(), absolute.suffix.decode()] == row[0][4:]
            assert [machine.name.decode(), machine.suffix.decode()] == row[1][4:]
            assert [relative.name.decode(), relative.suffix.decode()] == row[2][4:]
            assert [absolute.name.decode(), absolute.suffix.decode()] == row[3][4:]

    for call, answers in _answers(version, "cnc_rdsvmeter"):
        (loads,) = [a for a in answers if isinstance(a, ScaledValues)]
        assert [abs(v.mantissa) for v in loads.values[:axes]] == [
            r[0] for r in call["values"]["loads"]
        ]


def _signed(value: int, width: int) -> int:
    bits = 8 * width
    value &= (1 << bits) - 1
    return value - (1 << bits) if value >> (bits - 1) else value


# ---------------------------------------------------------------------------------------------
# The binary macro record


def test_binary_to_decimal_matches_the_library() -> None:
    table = _json("fwlib_float.json")["binary_to_decimal"]
    assert table["columns"] == ["mantissa", "exponent", "mcr_val", "dec_val"]
    assert len(table["cases"]) > 300
    for mantissa, exponent, mcr_val, dec_val in table["cases"]:
        assert binary_to_decimal(mantissa, exponent) == (mcr_val, dec_val), (mantissa, exponent)


def test_decimal_to_binary_matches_the_library() -> None:
    table = _json("fwlib_float.json")["decimal_to_binary"]
    assert table["columns"] == ["mcr_val", "dec_val", "mantissa", "exponent"]
    assert len(table["cases"]) > 300
    for mcr_val, dec_val, mantissa, exponent in table["cases"]:
        assert decimal_to_binary(mcr_val, dec_val) == (mantissa, exponent), (mcr_val, dec_val)


# ---------------------------------------------------------------------------------------------
# Probes of the facts the fact sheet left inferred


def _probes() -> dict[str, list[dict[str, Any]]]:
    return {p["probe"]: p["notes"] for p in _json("fwlib_probes.json")["probes"]}


def test_probe_answer_body_limits() -> None:
    probes = _probes()
    for version in (3, 4, 5):
        limit = max_response_body(version)
        assert probes[f"limit-{version}-{limit}"][0]["result"] == 0
        assert probes[f"limit-{version}-{limit + 1}"][0]["result"] == -17


def test_probe_results() -> None:
    probes = _probes()
    # kind 3 at version 2: one data frame (sysinfo, no 9968), option bits 1, rddynamic2 works
    assert probes["kind3"][0]["result"] == [0, 1, 1, 0]
    # option bit 0 clear: EW_NOOPT without sending anything
    assert probes["no-option"][0]["result"] == [6, 0]
    # 0xA3: bit 0 machine, bit 1 absolute + relative, bit 2 distance, bit 3 all but machine
    disp = probes["display-flags"]
    assert disp[0]["result"] == [0, [[0, 1, 0, 0], [1, 0, 1, 0], [0, 0, 0, 1]]]
    assert disp[1]["result"] == [0, [[1, 0, 1, 1], [0, 0, 0, 0], [0, 0, 0, 0]]]
    assert disp[2]["result"] == [0, [[0, 0, 0, 0]] * 3]
    assert all(note["result"] == [0, [[0, 0, 0, 0]] * 3] for note in disp[3:])
    # 0xA4(1) = 0: EW_NOOPT after the request; a spindle above the path's count: EW_NUMBER unsent
    spindles = probes["spindle-count"]
    assert spindles[0]["result"][0] == 6 and len(spindles[0]["result"][1]) == 1
    assert spindles[1]["result"] == [3, []]
    assert spindles[2]["result"][0] == 0
    # type numbering: parameter type 5 copies nothing, diagnostic types 3 and 4 read a byte
    types = [note["result"] for note in probes["types"]]
    assert types[0] == types[1] == [0, "ee" * 8]
    assert types[2] == [0, "4433221103000000"]
    assert types[3] == types[4] == types[6] == types[7] == [0, "44" + "ee" * 7]
    assert types[5] == types[8] == [0, "4433221103000000"]
    # alarm history: a short second chunk ends the list; EW_NUMBER on the first is returned
    history = probes["history-end"]
    assert history[0]["result"] == [0, 1, 25, 2]
    assert history[1]["result"] == 3
    # 16i class writes no REAL parameter: EW_LENGTH before the 0x0F
    real = [note["result"] for note in probes["real-write-16i"]]
    assert real == [[2, 1], [2, 1], [2, 1], [0, 2]]
    # a lathe path connects in both classes
    assert [note["result"] for note in probes["lathe"]] == [[0, 0], [0, 0]]


# ---------------------------------------------------------------------------------------------
# The simulator's own answers, as FANUC's library took them (fwlib_sim.json)

#: The built-in 0i-F (30i set), the 16i-class file, and a 0i-F file with every parameter kind.
SIM_SETS = ("30i", "16i", "30i-file")
#: Every function of FANUC's library the simulator answers, in both command sets.
SIM_FUNCTIONS = {
    "cnc_allclibhndl3", "cnc_sysinfo", "cnc_statinfo", "cnc_rdmacro", "cnc_wrmacro",
    "cnc_rdmacror2", "cnc_wrmacror2", "cnc_rdparam", "cnc_wrparam", "cnc_diagnoss",
    "pmc_rdpmcrng", "pmc_wrpmcrng", "cnc_rdalmmsg", "cnc_rdalmmsg2", "cnc_alarm", "cnc_alarm2",
    "cnc_rdprgnum", "cnc_rdprgnumo8", "cnc_exeprgname", "cnc_rdseqnum", "cnc_rdcncid",
    "cnc_rdtimer", "cnc_rdalmhistry", "cnc_actf", "cnc_acts", "cnc_absolute", "cnc_machine",
    "cnc_relative", "cnc_distance", "cnc_rdposition", "cnc_rddynamic2", "cnc_rdspload",
    "cnc_rdsvmeter", "cnc_freelibhndl",
}  # fmt: skip


def _sim_set(set_name: str) -> dict[str, Any]:
    (found,) = [s for s in _json("fwlib_sim.json")["sets"] if s["command_set"] == set_name]
    return dict(found)


@pytest.mark.parametrize("set_name", SIM_SETS)
def test_simulator_answers_every_captured_request_as_the_library_took_it(set_name: str) -> None:
    data = _sim_set(set_name)
    assert {c["function"] for c in data["calls"]} == SIM_FUNCTIONS
    adapter = NativeAdapter(simulator_machine(set_name))
    assert adapter.command_set.value == set_name.removesuffix("-file")
    assert adapter.open_response().hex() == data["open_response"]
    for call in data["calls"]:
        # the library returned EW_OK, except for the refusals captured on purpose: EW_NUMBER,
        # and EW_LENGTH for a real parameter written in the 16i set (it has no way to)
        refusals = {EW.NUMBER}
        if call["function"] == "cnc_wrparam" and call["arguments"]["number"] == 1451:
            refusals = {EW.LENGTH} if set_name == "16i" else set()
        assert call["return"] in {0} | refusals, (call["function"], call["arguments"])
        if call["function"] not in ("cnc_sysinfo", "cnc_freelibhndl"):
            assert call["exchanges"], call["function"]
        for ex in call["exchanges"]:
            body = bytes.fromhex(ex["request"])
            answer = adapter.answer(body)
            assert answer.hex() == ex["answer"], (call["function"], call["arguments"])
            frame = decode_frame(answer)
            assert answer_refusal(frame.body, len(decode_request_body(body)), frame.version) is None
