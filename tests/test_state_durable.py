"""``FocasServer(durable=...)``: an answer leaves only once the write it acknowledges is in
the state file, and the writes of one loop turn share one save."""

from __future__ import annotations

import asyncio
from decimal import Decimal
from pathlib import Path

import pytest
from support import serving

from focas_net.client import FocasClient, NativeClient
from focas_net.errors import FocasError
from focas_net.sim import default_machine
from focas_net.sim.statefile import StateFile, decode_state


def _kept_macro(path: Path, number: int) -> str | None:
    doc = decode_state(path.read_bytes())
    value: str | None = doc["kept"]["macros"].get(str(number))
    return value


async def test_an_answer_leaves_once_its_write_is_on_the_disk(tmp_path: Path) -> None:
    state = StateFile(tmp_path / "m.state")
    machine = state.load(default_machine)
    async with serving(machine, durable=lambda: state.save(machine)) as served:
        async with FocasClient(served.host, served.port) as cnc:
            for n in range(5):
                await cnc.write_macro(510, n)
                assert _kept_macro(state.path, 510) == str(n)
            await cnc.write_pmc("D", 4, b"\x09")
            doc = decode_state(state.path.read_bytes())
            assert bytes.fromhex(doc["kept"]["pmc"]["D"])[4] == 9
        async with NativeClient(served.host, served.port) as native:
            await native.write_macro(511, Decimal("2.5"))
            assert _kept_macro(state.path, 511) == "2.5"


async def test_the_writes_of_one_turn_share_one_save(tmp_path: Path) -> None:
    state = StateFile(tmp_path / "m.state")
    machine = state.load(default_machine)
    async with serving(machine, durable=lambda: state.save(machine)) as served:
        keeper = served.server.keeper
        assert keeper is not None
        async with FocasClient(served.host, served.port, max_in_flight=64) as cnc:
            await asyncio.gather(*(cnc.write_macro(520 + i, i) for i in range(60)))
        assert state.writes < 60  # the pipelined writes came in fewer turns than writes
        for i in range(60):
            assert _kept_macro(state.path, 520 + i) == str(i)


async def test_without_durable_answers_leave_at_once() -> None:
    async with serving() as served:
        assert served.server.keeper is None
        async with FocasClient(served.host, served.port) as cnc:
            await cnc.write_macro(530, 1)
            assert await cnc.read_macro(530) == 1


async def test_a_failed_save_sends_no_answer(tmp_path: Path) -> None:
    def fail() -> None:
        raise OSError(28, "No space left on device")

    async with serving(durable=fail) as served:
        async with FocasClient(served.host, served.port, timeout=2.0) as cnc:
            with pytest.raises((FocasError, OSError)):  # aborted: never acknowledged
                await cnc.write_macro(540, 1)


@pytest.mark.parametrize("error", [OSError(5, "Input/output error"), RuntimeError("broken")])
async def test_a_save_failing_in_any_way_sends_no_answer_and_holds_none(
    tmp_path: Path, error: Exception
) -> None:
    def fail() -> None:
        raise error

    async with serving(durable=fail) as served:
        with pytest.raises((FocasError, OSError)):  # aborted at once (the open's answer too)
            async with NativeClient(served.host, served.port, timeout=2.0) as cnc:
                await cnc.write_macro(541, 1)


async def test_a_half_closed_connection_gets_every_held_answer(tmp_path: Path) -> None:
    from focas_net.protocol import Command, encode_frame

    state = StateFile(tmp_path / "m.state")
    machine = state.load(default_machine)
    async with serving(machine, durable=lambda: state.save(machine)) as served:
        async with await served.connect() as wire:
            count = 50
            wire.send_raw(b"".join(encode_frame(Command.RDCNCSTAT, i) for i in range(count)))
            wire.writer.write_eof()
            ids = []
            with pytest.raises(EOFError):
                for _ in range(count + 1):
                    ids.append((await wire.recv()).request_id)
        assert ids == list(range(count))
