"""The native FOCAS/2 listener against running servers: pyfocas (a client written elsewhere),
the project's own native codec, and cross-checks with the packed front end on the same machine.

Both front ends run on 127.0.0.1, port 0, over ONE machine: the packed :class:`FocasServer`
driven through the project's packed client connection, and the :class:`NativeServer`.
"""

from __future__ import annotations

import asyncio
import logging
import math
import struct
from collections.abc import AsyncIterator
from dataclasses import dataclass
from decimal import Decimal
from typing import Any

import pytest
from pyfocas.protocol.packet import DecodingError, FOCASError
from pyfocas.protocol.protocol import FOCAS

from focas_net.client.connection import Connection, open_connection
from focas_net.errors import EW
from focas_net.native import (
    ActualFeedRequest,
    ActualSpindleSpeedRequest,
    AlarmMessageRequest,
    AlarmMessages,
    Device,
    DiagnosticRequest,
    FrameType,
    ItemValues,
    MacroDoubleReadRequest,
    MacroDoubles,
    MacroDoubleWriteRequest,
    MacroReadRequest,
    NativeCommand,
    NativeFrameDecoder,
    NativePmcArea,
    NativePmcData,
    NativePositionRequest,
    NativeProgramNumbers,
    NativeRequest,
    NativeSysInfo,
    ParamRead3Request,
    ParamReadRequest,
    ParamType,
    PmcReadRequest,
    RequestBlock,
    ResponseBlock,
    ScaledItemValues,
    ScaledNumber,
    ScaledValues,
    StatInfo,
    StatInfoRequest,
    SysInfoRequest,
    decode_response_body,
    encode_close_request,
    encode_native_frame,
    encode_open_request,
    encode_request,
)
from focas_net.native import ProgramNumberRequest as PrgNumRequest
from focas_net.protocol import (
    COMMANDS,
    Command,
    MacroRequest,
    MacroValue,
    RaiseAlarm,
    SetPanel,
    StatusInfo,
)
from focas_net.protocol import PmcData as PackedPmcData
from focas_net.protocol import SysInfo as PackedSysInfo
from focas_net.server import FocasServer, NativeServer, start_native
from focas_net.sim import Machine, default_machine

TIMEOUT = 5.0


# --------------------------------------------------------------------------------------------
# Fixtures and small clients


@dataclass
class Front:
    machine: Machine
    native: NativeServer
    packed: Connection
    packed_server: FocasServer

    @property
    def host(self) -> str:
        return self.native.address[0]

    @property
    def port(self) -> int:
        return self.native.address[1]

    async def packed_call(self, command: Command, payload: bytes = b"") -> Any:
        """One packed-protocol call; the decoded answer (an EwReply when refused)."""
        loop = asyncio.get_running_loop()
        answer = await self.packed.request(command, payload, loop.time() + TIMEOUT)
        return COMMANDS[command].response.decode(answer)


@pytest.fixture
async def front() -> AsyncIterator[Front]:
    machine = default_machine()
    async with (
        FocasServer(machine, port=0) as packed_server,
        NativeServer(machine, "127.0.0.1", 0) as native,
    ):
        host, port = packed_server.listeners[0].address
        conn = await open_connection(host, port)
        try:
            yield Front(machine, native, conn, packed_server)
        finally:
            conn.close()
            await conn.wait_closed()


class NativeClient:
    """A minimal native client on the project's codec (asyncio streams)."""

    def __init__(self, reader: asyncio.StreamReader, writer: asyncio.StreamWriter) -> None:
        self.reader = reader
        self.writer = writer
        self.decoder = NativeFrameDecoder(0xFFFF)
        self.pending: list[tuple[int, int, bytes]] = []

    @classmethod
    async def connect(cls, front: Front, *, open_: bool = True) -> NativeClient:
        reader, writer = await asyncio.open_connection(front.host, front.port)
        client = cls(reader, writer)
        if open_:
            version, frame_type, _ = await client.exchange(encode_open_request())
            assert frame_type == FrameType.OPEN_RESPONSE
            assert version == 3  # the built-in machine is a 0i-F: the 30i command set
        return client

    @property
    def local_port(self) -> int:
        return int(self.writer.get_extra_info("sockname")[1])

    async def read_frame(self) -> tuple[int, int, bytes]:
        async with asyncio.timeout(TIMEOUT):
            while not self.pending:
                chunk = await self.reader.read(65536)
                if not chunk:
                    raise EOFError
                self.pending.extend(self.decoder.feed(chunk))
        return self.pending.pop(0)

    async def exchange(self, frame: bytes) -> tuple[int, int, bytes]:
        self.writer.write(frame)
        await self.writer.drain()
        return await self.read_frame()

    async def blocks(self, *blocks: RequestBlock) -> tuple[ResponseBlock, ...]:
        _, frame_type, body = await self.exchange(encode_request(list(blocks)))
        assert frame_type == FrameType.DATA_RESPONSE
        answer = decode_response_body(body)
        assert len(answer) == len(blocks)
        for req, resp in zip(blocks, answer, strict=True):
            assert (resp.device, resp.path, resp.command) == (req.device, req.path, req.command)
        return answer

    async def call(self, request: NativeRequest) -> ResponseBlock:
        (answer,) = await self.blocks(request.to_block())
        return answer

    async def ok(self, request: NativeRequest) -> bytes:
        answer = await self.call(request)
        assert answer.ew == 0, f"EW {answer.ew} for {request}"
        return answer.data

    async def ew(self, request: NativeRequest) -> int:
        answer = await self.call(request)
        assert answer.data == b""
        return answer.ew

    async def closed_by_peer(self) -> bool:
        """True when the server closes the connection (EOF or reset) within the timeout."""
        try:
            async with asyncio.timeout(TIMEOUT):
                for _ in range(1000):
                    if not await self.reader.read(65536):
                        return True
        except (ConnectionResetError, BrokenPipeError):
            return True
        return False

    async def close(self) -> None:
        self.writer.close()
        try:
            await self.writer.wait_closed()
        except (ConnectionResetError, BrokenPipeError):
            pass


@pytest.fixture
async def native(front: Front) -> AsyncIterator[NativeClient]:
    client = await NativeClient.connect(front)
    yield client
    await client.close()


async def with_pyfocas(front: Front, work: Any) -> Any:
    """Run ``work(client)`` with a connected pyfocas client in a worker thread."""

    def run() -> Any:
        client = FOCAS(front.host, front.port)
        assert client.connect() is True
        try:
            return work(client)
        finally:
            assert client.socket is not None
            client.socket.close()

    return await asyncio.to_thread(run)


# --------------------------------------------------------------------------------------------
# pyfocas


async def test_pyfocas_sysinfo_and_status(front: Front) -> None:
    sys_info, stat = await with_pyfocas(front, lambda c: (c.get_sys_info(), c.get_status_info()))
    si = front.machine.identity()
    assert sys_info.addinfo == si.addinfo == 2
    assert sys_info.max_axis == si.max_axis == 32  # a 0i-F's
    assert (sys_info.cnc_type, sys_info.mt_type) == ("0", "M")
    assert (sys_info.series, sys_info.version, sys_info.axes) == ("D4F1", "32.0", "03")
    st = front.machine.status()
    assert (stat.aut, stat.run, stat.motion, stat.mstb, stat.emergency, stat.alarm, stat.edit) == (
        st.aut,
        st.run,
        st.motion,
        st.mstb,
        st.emergency,
        st.alarm,
        st.edit,
    )
    assert stat.aut == 1  # MEM


async def test_pyfocas_read_vacant_macro_raises_decoding_error(front: Front) -> None:
    def work(c: FOCAS) -> str:
        with pytest.raises(DecodingError) as info:
            c.read_macro(510)
        return str(info.value.message)

    assert await with_pyfocas(front, work) == "Sentinel value (FF FF) at the end"


async def test_pyfocas_read_set_and_range(front: Front) -> None:
    front.machine.write_macro(500, Decimal("15.00"))
    front.machine.write_macro(501, -7)
    front.machine.write_macro(502, Decimal("0.123456789"))
    result = await with_pyfocas(front, lambda c: (c.read_macro(500), c.read_macro(500, 502)))
    assert result[0] == {500: 15.0}
    assert result[1] == {500: 15.0, 501: -7.0, 502: 0.123456789}


async def test_pyfocas_write_macro_double_then_read(front: Front) -> None:
    def work(c: FOCAS) -> Any:
        packet = c.write_macro_double(502, 100.0)
        return packet, c.read_macro(502)

    packet, value = await with_pyfocas(front, work)
    assert packet.packet_type == FrameType.DATA_RESPONSE
    # The answer block: device 1, path 1, command 0xA8, EW 0, details 0, no data.
    assert packet.data == [b"\x00\x01\x00\x01\x00\xa8" + bytes(8)]
    assert value == {502: 100.0}
    assert front.machine.read_macro(502) == Decimal(100)


async def test_pyfocas_refused_block_surfaces_as_focas_error(front: Front) -> None:
    # #2000 does not exist: the block answers EW_NUMBER, which pyfocas reports this way.
    def work(c: FOCAS) -> str:
        with pytest.raises(FOCASError) as info:
            c.read_macro(2000)
        return str(info.value.message)

    assert await with_pyfocas(front, work) == "Payload does not match command"


async def test_pyfocas_refused_write_is_visible_only_in_the_block(front: Front) -> None:
    # pyfocas does not check the EW word of a write: the refusal is in the answer block.
    def work(c: FOCAS) -> list[bytes]:
        return [
            c.write_macro_double(1000, 1.0).data[0],
            c.write_macro_double(500, math.inf).data[0],
        ]

    no_such, infinite = await with_pyfocas(front, work)
    assert struct.unpack(">h", no_such[6:8])[0] == EW.NUMBER  # #1000 is not a variable here
    assert struct.unpack(">h", infinite[6:8])[0] == EW.DATA
    assert front.machine.read_macro(500) is None


# --------------------------------------------------------------------------------------------
# Cross-checks between the two front ends


async def test_macro_written_natively_reads_back_through_packed(front: Front) -> None:
    await with_pyfocas(front, lambda c: c.write_macro_double(503, 2.5))
    answer = await front.packed_call(Command.RDMACRO, MacroRequest(503).encode())
    assert answer == MacroValue(503, 8, 25, 1)
    await with_pyfocas(front, lambda c: c.write_macro_double(504, -0.001))
    answer = await front.packed_call(Command.RDMACRO, MacroRequest(504).encode())
    assert answer == MacroValue(504, 8, -1, 3)


async def test_macro_written_through_packed_reads_back_natively(
    front: Front, native: NativeClient
) -> None:
    ok = await front.packed_call(Command.WRMACRO, MacroValue(505, 8, -12345, 3).encode())
    assert ok is None
    assert await with_pyfocas(front, lambda c: c.read_macro(505)) == {505: -12.345}
    data = await native.ok(MacroReadRequest(505, 505))
    assert ScaledValues.decode(data).values == (ScaledNumber(-12345, 3),)
    data = await native.ok(MacroDoubleReadRequest(505, 1))
    assert MacroDoubles.decode(data).values == (-12.345,)


async def test_status_and_sysinfo_agree_between_front_ends(
    front: Front, native: NativeClient
) -> None:
    for panel in (SetPanel(1, 0, 0), SetPanel(0, 1, 1)):
        assert await front.packed_call(Command.SIM_SET_PANEL, panel.encode()) is None
        packed = await front.packed_call(Command.RDCNCSTAT)
        assert isinstance(packed, StatusInfo)
        stat = StatInfo.decode(await native.ok(StatInfoRequest()))
        assert stat == StatInfo(
            packed.aut,
            packed.run,
            packed.motion,
            packed.mstb,
            packed.emergency,
            packed.alarm,
            packed.edit,
        )
        assert (stat.aut, stat.emergency) == (panel.mode, panel.emergency)
        seen = await with_pyfocas(front, lambda c: c.get_status_info())
        assert (seen.aut, seen.emergency, seen.alarm) == (stat.aut, stat.emergency, stat.alarm)
    packed_si = await front.packed_call(Command.SYSINFO)
    assert isinstance(packed_si, PackedSysInfo)
    si = NativeSysInfo.decode(await native.ok(SysInfoRequest()))
    assert si == NativeSysInfo(
        packed_si.addinfo,
        packed_si.max_axis,
        packed_si.cnc_type.decode(),
        packed_si.mt_type.decode(),
        packed_si.series.decode(),
        packed_si.version.decode(),
        packed_si.axes.decode(),
    )


async def test_alarm_raised_through_packed_is_seen_natively(
    front: Front, native: NativeClient
) -> None:
    assert await native.ok(AlarmMessageRequest()) == b""  # no active alarm: no data
    raise_ = RaiseAlarm(2, 9, 410, b"SERVO ALARM: EXCESS ERROR")
    assert await front.packed_call(Command.SIM_RAISE_ALARM, raise_.encode()) is None
    data = await native.ok(AlarmMessageRequest(-1, 10, 2, 64))
    assert len(data) == 16 + 64
    (alarm,) = AlarmMessages.decode(data, 64).alarms
    assert (alarm.number, alarm.alarm_type, alarm.axis) == (410, 9, 2)
    assert alarm.message == b"SERVO ALARM: EXCESS ERROR"
    # text_mode 0: no text, the field still text_length bytes long
    (bare,) = AlarmMessages.decode(await native.ok(AlarmMessageRequest(-1, 10, 0, 32)), 32).alarms
    assert bare.message == b""
    # a type that matches nothing, a short text field, bad counts
    assert await native.ok(AlarmMessageRequest(3, 10, 2, 64)) == b""
    (cut,) = AlarmMessages.decode(await native.ok(AlarmMessageRequest(9, 1, 2, 5)), 5).alarms
    assert cut.message == b"SERVO"
    assert await native.ew(AlarmMessageRequest(-1, 0, 2, 64)) == EW.LENGTH
    assert await native.ew(AlarmMessageRequest(-1, 10, 2, -1)) == EW.LENGTH
    assert await native.ew(AlarmMessageRequest(-1, 10, 2, 5000)) == EW.LENGTH
    stat = StatInfo.decode(await native.ok(StatInfoRequest()))
    assert stat.alarm == 1


# --------------------------------------------------------------------------------------------
# Every supported command through the project's codec


async def test_macro_commands(front: Front, native: NativeClient) -> None:
    front.machine.write_macro(101, 42)
    data = await native.ok(MacroReadRequest(100, 102))
    assert ScaledValues.decode(data).values == (
        ScaledNumber(0, -1),
        ScaledNumber(42, 0),
        ScaledNumber(0, -1),
    )
    assert (await native.ok(MacroReadRequest(101, 101)))[4:] == b"\x00\x0a\x00\x00"
    assert (await native.ok(MacroReadRequest(100, 100))) == b"\x00\x00\x00\x00\x00\x0a\xff\xff"
    doubles = MacroDoubles.decode(await native.ok(MacroDoubleReadRequest(100, 3))).values
    assert doubles == (None, 42.0, None)
    assert await native.ok(MacroDoubleWriteRequest(102, 0.1)) == b""
    assert front.machine.read_macro(102) == Decimal("0.1")
    assert await native.ok(MacroDoubleWriteRequest(101, None)) == b""  # NaN -> vacant
    assert front.machine.read_macro(101) is None
    packed = await front.packed_call(Command.RDMACRO, MacroRequest(101).encode())
    assert packed == MacroValue(101, 8, 0, -1)
    # refusals
    assert await native.ew(MacroReadRequest(2000, 2000)) == EW.NUMBER
    assert await native.ew(MacroReadRequest(5, 4)) == EW.LENGTH
    assert await native.ew(MacroReadRequest(500, 999)) == EW.LENGTH  # 4000 bytes > 1450
    assert await native.ew(MacroDoubleReadRequest(500, 0)) == EW.LENGTH
    assert await native.ew(MacroDoubleReadRequest(2000, 1)) == EW.NUMBER
    assert await native.ew(MacroDoubleWriteRequest(5001, 1.0)) == EW.PROT
    assert await native.ew(MacroDoubleWriteRequest(2000, 1.0)) == EW.NUMBER
    assert await native.ew(MacroDoubleWriteRequest(500, math.inf)) == EW.DATA
    assert await native.ew(MacroDoubleWriteRequest(500, 3e9)) == EW.DATA
    assert await native.ew(MacroDoubleWriteRequest(5001, None)) == EW.PROT
    short = RequestBlock(Device.CNC, 1, NativeCommand.WRMACRO_DOUBLE, (500, 0, 0, 0, 4), b"\0" * 4)
    (answer,) = await native.blocks(short)
    assert answer.ew == EW.LENGTH
    assert front.machine.read_macro(500) is None


def _most(front: Front) -> int:
    """Slots of an all-axes record: the machine's max axes (32 on the built-in 0i-F)."""
    return front.machine.identity().max_axis


async def test_parameter_reads(front: Front, native: NativeClient) -> None:
    most = front.machine.identity().max_axis  # the slots of a record: 32 on a 0i-F
    data = await native.ok(ParamReadRequest(1420, 1420, -1))
    (rec,) = ItemValues.decode(data, most).records
    assert (rec.number, rec.axis, rec.type) == (1420, -1, ParamType.TWO_WORD)
    assert rec.values == (24000, 24000, 24000) + (0,) * (most - 3)
    (rec,) = ItemValues.decode(await native.ok(ParamReadRequest(20, 20, 0)), _most(front)).records
    assert (rec.number, rec.axis, rec.type, rec.values[0]) == (20, 0, ParamType.BYTE, 4)
    (rec,) = ItemValues.decode(
        await native.ok(ParamReadRequest(1825, 1825, 2)), _most(front)
    ).records
    assert (rec.axis, rec.type, rec.values) == (2, ParamType.WORD, (3000,) + (0,) * (most - 1))
    # a range reads the parameters that exist in it, in order
    records = ItemValues.decode(
        await native.ok(ParamReadRequest(1000, 1010, -1)), _most(front)
    ).records
    assert [r.number for r in records] == [1001, 1005, 1006]
    assert records[0].axis == 0  # a non-axis parameter read with axis -1
    # 30i style: 8-byte scaled slots, the same type numbering
    data = await native.ok(ParamRead3Request(1825, 1825, -1))
    (srec,) = ScaledItemValues.decode(data, _most(front)).records
    assert (srec.number, srec.axis, srec.type) == (1825, -1, 2)
    assert srec.values[:3] == (ScaledNumber(3000, 0),) * 3
    (srec,) = ScaledItemValues.decode(
        await native.ok(ParamRead3Request(1410, 1410, 0)), _most(front)
    ).records
    assert (srec.type, srec.values[0]) == (3, ScaledNumber(5000, 0))
    # refusals
    assert await native.ew(ParamReadRequest(2, 19, 0)) == EW.NUMBER
    assert await native.ew(ParamReadRequest(20, 20, 1)) == EW.ATTRIB
    assert await native.ew(ParamReadRequest(1420, 1420, 0)) == EW.ATTRIB
    assert await native.ew(ParamReadRequest(1420, 1420, 9)) == EW.ATTRIB
    assert await native.ew(ParamRead3Request(30, 20, 0)) == EW.LENGTH
    # a range of a version-3 answer (2910 bytes) holds ten records of 32 slots
    numbers = list(front.machine.param_numbers())
    ten = ParamRead3Request(numbers[0], numbers[9], -1)
    assert [r.number for r in ScaledItemValues.decode(await native.ok(ten), most).records] == (
        numbers[:10]
    )
    assert await native.ew(ParamRead3Request(0, 9999, -1)) == EW.LENGTH


async def test_parameter_written_through_packed_reads_natively(
    front: Front, native: NativeClient
) -> None:
    from focas_net.protocol import ParamValue

    assert await front.packed_call(Command.SIM_SET_PANEL, SetPanel(0, 1, 0).encode()) is None
    write = ParamValue(1422, 0, 8000, 4).encode()
    assert await front.packed_call(Command.WRPARAM, write) is None
    (rec,) = ItemValues.decode(
        await native.ok(ParamReadRequest(1422, 1422, 0)), _most(front)
    ).records
    assert rec.values[0] == 8000


async def test_diagnostic_read(front: Front, native: NativeClient) -> None:
    (rec,) = ItemValues.decode(
        await native.ok(DiagnosticRequest(308, 308, -1)), _most(front)
    ).records
    assert (rec.number, rec.axis, rec.type) == (308, -1, 0)
    assert rec.values == (31, 31, 31) + (0,) * (_most(front) - 3)
    front.machine.set_diag(410, 0, 57)
    (rec,) = ItemValues.decode(
        await native.ok(DiagnosticRequest(410, 410, 0)), _most(front)
    ).records
    assert (rec.type, rec.values[0]) == (1, 57)
    assert await native.ew(DiagnosticRequest(1, 299, 0)) == EW.NUMBER


async def test_pmc_read(front: Front, native: NativeClient) -> None:
    write = PackedPmcData(5, 0, 100, 103, b"\x01\x02\x03\x04")  # R100..R103, packed codes
    assert await front.packed_call(Command.WRPMCRNG, write.encode()) is None
    assert await native.ok(PmcReadRequest(100, 103, NativePmcArea.R, 0)) == b"\x01\x02\x03\x04"
    words = NativePmcData(await native.ok(PmcReadRequest(100, 103, NativePmcArea.R, 1)))
    assert words.values(1) == (0x0201, 0x0403)  # PMC words are little-endian in memory
    longs = NativePmcData(await native.ok(PmcReadRequest(100, 103, NativePmcArea.R, 2)))
    assert longs.values(2) == (0x04030201,)
    # more than one packed chunk (32 bytes) in one native read
    data = await native.ok(PmcReadRequest(0, 99, NativePmcArea.R, 0))
    assert len(data) == 100
    assert data == bytes(100)
    assert (
        await native.ok(PmcReadRequest(96, 103, NativePmcArea.R, 0))
        == bytes(4) + b"\x01\x02\x03\x04"
    )
    # refusals
    assert await native.ew(PmcReadRequest(0, 1, NativePmcArea.E, 0)) == EW.NOOPT
    assert await native.ew(PmcReadRequest(0, 1, NativePmcArea.M, 0)) == EW.NOOPT
    assert await native.ew(PmcReadRequest(0, 1, 99, 0)) == EW.ATTRIB
    assert await native.ew(PmcReadRequest(0, 1, NativePmcArea.R, 7)) == EW.ATTRIB
    assert await native.ew(PmcReadRequest(0, 2, NativePmcArea.R, 1)) == EW.LENGTH
    assert await native.ew(PmcReadRequest(5, 4, NativePmcArea.R, 0)) == EW.LENGTH
    assert await native.ew(PmcReadRequest(0, 4999, NativePmcArea.D, 0)) == EW.LENGTH
    assert await native.ew(PmcReadRequest(7990, 8009, NativePmcArea.R, 0)) == EW.NUMBER


async def test_program_numbers_feed_spindle(front: Front, native: NativeClient) -> None:
    assert NativeProgramNumbers.decode(await native.ok(PrgNumRequest())) == NativeProgramNumbers(
        1, 1
    )
    front.machine.set_motion(program_running=1234, program_main=1000, feed=1500, spindle_speed=8000)
    assert NativeProgramNumbers.decode(await native.ok(PrgNumRequest())) == NativeProgramNumbers(
        1234, 1000
    )
    feed = ScaledNumber.decode(await native.ok(ActualFeedRequest()))
    spindle = ScaledNumber.decode(await native.ok(ActualSpindleSpeedRequest()))
    assert (feed.to_float(), spindle.to_float()) == (1500.0, 8000.0)


async def test_positions(front: Front, native: NativeClient) -> None:
    front.machine.set_motion(
        absolute=[1000, -2500, 300],
        machine=[11000, 7500, -300],
        relative=[1, 2, 3],
        distance_to_go=[0, 0, -50],
    )
    motion = front.machine.motion
    expected = {
        (4, 0): motion.absolute,
        (1,): motion.machine,
        (6, 2): motion.relative,
        (7, 3): motion.distance_to_go,
    }
    for kinds, values in expected.items():
        for kind in kinds:
            got = ScaledValues.decode(await native.ok(NativePositionRequest(kind, -1))).values
            assert len(got) == _most(front)  # max_axis records, the unused ones zero
            assert got[:3] == tuple(ScaledNumber(v, 3) for v in values)
            assert all(r.mantissa == 0 for r in got[3:])
            one = ScaledValues.decode(await native.ok(NativePositionRequest(kind, 2))).values
            assert one == (ScaledNumber(values[1], 3),)
    assert ScaledNumber(-2500, 3).to_float() == -2.5
    assert await native.ew(NativePositionRequest(8, -1)) == EW.NOOPT  # no skip function
    assert await native.ew(NativePositionRequest(5, -1)) == EW.ATTRIB
    assert await native.ew(NativePositionRequest(4, 4)) == EW.ATTRIB
    assert await native.ew(NativePositionRequest(4, 0)) == EW.ATTRIB


# --------------------------------------------------------------------------------------------
# Several blocks, unsupported commands


async def test_unsupported_block_answers_ew_func_others_succeed(
    front: Front, native: NativeClient
) -> None:
    front.machine.write_macro(1, 7)
    blocks = (
        SysInfoRequest().to_block(),
        RequestBlock(Device.CNC, 1, 0xE1, (0, 0, 0, 0, 0)),  # ODBST hdck
        StatInfoRequest().to_block(),
        RequestBlock(Device.PMC, 1, NativeCommand.SYSINFO),  # right command, wrong device
        MacroReadRequest(1, 1).to_block(),
        RequestBlock(Device.CNC, 1, 0x98, (1, 2, 3, 4, 5), b"extra"),
        RequestBlock(Device.CNC, 3, NativeCommand.SYSINFO),  # a path this machine lacks
    )
    answers = await native.blocks(*blocks)
    assert [a.ew for a in answers] == [0, 0, 0, EW.FUNC, 0, 0, EW.PATH]
    assert NativeSysInfo.decode(answers[0].data).max_axis == 32
    assert StatInfo.decode(answers[2].data).aut == 1
    assert ScaledValues.decode(answers[4].data).values == (ScaledNumber(7, 0),)
    assert all(a.data == b"" for a in answers if a.ew)
    # the whole answer stays within what version 3 allows, even for many blocks
    many = [MacroReadRequest(500, 520).to_block() for _ in range(20)]
    answers = await native.blocks(*many)
    assert answers[0].ew == 0 and len(answers[0].data) == 21 * 8
    assert sum(16 + len(a.data) for a in answers) + 2 <= 2910
    assert any(a.ew == EW.LENGTH for a in answers)


async def test_empty_data_request_answers_one_refused_block(native: NativeClient) -> None:
    # FANUC's library refuses an answer of no block: one EW_FUNC block instead
    _, frame_type, body = await native.exchange(encode_native_frame(FrameType.DATA_REQUEST, b""))
    assert frame_type == FrameType.DATA_RESPONSE
    (block,) = decode_response_body(body)
    assert (block.ew, block.data) == (EW.FUNC, b"")


async def test_close_handshake(front: Front) -> None:
    client = await NativeClient.connect(front)
    version, frame_type, body = await client.exchange(encode_close_request())
    assert (version, frame_type, body) == (3, FrameType.CLOSE_RESPONSE, b"")
    assert await client.closed_by_peer()
    await client.close()
    assert front.native.violations == 0


async def test_pipelined_requests_answered_in_order(front: Front, native: NativeClient) -> None:
    frames = [encode_request([MacroReadRequest(n, n).to_block()]) for n in (1, 2, 3)]
    front.machine.write_macro(2, 22)
    native.writer.write(b"".join(frames))
    await native.writer.drain()
    seen = []
    for _ in frames:
        _, _, body = await native.read_frame()
        (block,) = decode_response_body(body)
        seen.append(ScaledValues.decode(block.data).values[0])
    assert seen == [ScaledNumber(0, -1), ScaledNumber(22, 0), ScaledNumber(0, -1)]


# --------------------------------------------------------------------------------------------
# Bad input closes only that connection


_OPEN = encode_open_request()


def _many_blocks(n: int) -> bytes:
    return encode_request([SysInfoRequest().to_block()] * n)


@pytest.mark.parametrize(
    ("name", "payload", "opened"),
    [
        ("garbage", b"GET / HTTP/1.1\r\n\r\n", False),
        ("bad magic after open", b"\xa0\xa0\xa0\xa1" + bytes(6), True),
        ("oversize header only", b"\xa0\xa0\xa0\xa0\x00\x01\x21\x01\xff\xff", True),
        ("data before open", _many_blocks(1), False),
        (
            "broken block list",
            encode_native_frame(FrameType.DATA_REQUEST, b"\x00\x02\x00\x1c"),
            True,
        ),
        ("too many blocks and bytes", _many_blocks(200), True),
        ("frame type not served", encode_native_frame(0x1901, b"\x00\x01"), True),
        (
            "open body of 3 bytes",
            encode_native_frame(FrameType.OPEN_REQUEST, b"\x00\x02\x00"),
            False,
        ),
    ],
)
async def test_bad_input_closes_only_that_connection(
    front: Front,
    native: NativeClient,
    caplog: pytest.LogCaptureFixture,
    name: str,
    payload: bytes,
    opened: bool,
) -> None:
    bad = await NativeClient.connect(front, open_=opened)
    port = bad.local_port
    with caplog.at_level(logging.WARNING, logger="focas_net.server"):
        bad.writer.write(payload)
        await bad.writer.drain()
        assert await bad.closed_by_peer(), name
    await bad.close()
    warnings = [r.getMessage() for r in caplog.records if r.levelno == logging.WARNING]
    assert any(f"127.0.0.1:{port}" in w for w in warnings), warnings
    assert front.native.violations == 1
    # the other native connection and the packed side keep working, state untouched
    si = NativeSysInfo.decode(await native.ok(SysInfoRequest()))
    assert si.max_axis == 32
    assert isinstance(await front.packed_call(Command.RDCNCSTAT), StatusInfo)
    assert len(front.native.connections) == 1


async def test_oversize_is_refused_before_the_body_arrives(front: Front) -> None:
    # Only the 10-byte header announcing 60000 bytes is sent: the server closes at once.
    bad = await NativeClient.connect(front)
    bad.writer.write(b"\xa0\xa0\xa0\xa0\x00\x01\x21\x01" + struct.pack(">H", 60000))
    await bad.writer.drain()
    assert await bad.closed_by_peer()
    await bad.close()


async def test_garbage_in_small_pieces_then_other_clients_still_served(front: Front) -> None:
    bad = await NativeClient.connect(front)
    for piece in (b"\xa0", b"\xa0\xa0", b"\x00"):  # the 4th byte breaks the magic
        bad.writer.write(piece)
        await bad.writer.drain()
    assert await bad.closed_by_peer()
    await bad.close()
    stat = await with_pyfocas(front, lambda c: c.get_status_info())
    assert stat.aut == 1


async def test_connection_limit(front: Front) -> None:
    async with NativeServer(front.machine, max_connections=1) as limited:
        first_r, first_w = await asyncio.open_connection(*limited.address)
        first = NativeClient(first_r, first_w)
        _, frame_type, _ = await first.exchange(_OPEN)
        assert frame_type == FrameType.OPEN_RESPONSE
        second_r, second_w = await asyncio.open_connection(*limited.address)
        second = NativeClient(second_r, second_w)
        assert await second.closed_by_peer()
        await second.close()
        assert limited.refused == 1
        assert (await first.exchange(encode_request([SysInfoRequest().to_block()])))[1] == (
            FrameType.DATA_RESPONSE
        )
        await first.close()


async def test_start_native_and_shared_machine(front: Front) -> None:
    other = await start_native(front.machine, "127.0.0.1", 0)
    try:
        assert other.address[1] not in (0, front.port)
        front.machine.write_macro(600, Decimal("3.1416"))
        host, port = other.address

        def work() -> Any:
            client = FOCAS(host, port)
            assert client.connect()
            try:
                return client.read_macro(600)
            finally:
                assert client.socket is not None
                client.socket.close()

        assert await asyncio.to_thread(work) == {600: 3.1416}
    finally:
        await other.aclose()
    assert other.connections == set()


async def test_aclose_closes_open_connections(front: Front) -> None:
    server = await start_native(front.machine)
    reader, writer = await asyncio.open_connection(*server.address)
    client = NativeClient(reader, writer)
    await client.exchange(_OPEN)
    await server.aclose()
    assert await client.closed_by_peer()
    await client.close()
    assert server.stats()["connections"] == 0


async def test_focas_server_native_port_shares_the_machine() -> None:
    from focas_net.client import FocasClient

    machine = default_machine()
    async with FocasServer(machine, port=0, native_port=0) as server:
        listener = server.listeners[0]
        assert listener.native is not None
        host, native_port = listener.native.address
        assert "native" in server.stats()[listener.label]

        def native_work() -> Any:
            client = FOCAS(host, native_port)
            client.connect()
            try:
                client.write_macro_double(520, -7.25)
                return client.get_sys_info()
            finally:
                client.socket.close()

        info = await asyncio.to_thread(native_work)
        async with FocasClient(host, listener.port, timeout=TIMEOUT) as cnc:
            assert await cnc.read_macro(520) == Decimal("-7.25")
            await cnc.write_macro(521, Decimal("1.5"))
            sysinfo = await cnc.read_sysinfo()
        assert sysinfo.max_axis == info.max_axis

        def native_read() -> Any:
            client = FOCAS(host, native_port)
            client.connect()
            try:
                return client.read_macro(521)
            finally:
                client.socket.close()

        assert await asyncio.to_thread(native_read) == {521: 1.5}
    native = listener.native
    assert not native.accepting and not native.native_connections  # closed with the server
