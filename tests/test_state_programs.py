"""Program downloads and deletions are kept by ``serve --state`` on both protocols: the
packed ``cnc_download``, the native ``cnc_pdf_del`` (the native client) and FANUC's library
downloading through the native protocol (``cnc_dwnstart``...: skipped without the library)."""

from __future__ import annotations

from pathlib import Path

import pytest
from fwlib_support import LIBRARY, Cnc, connect, download
from support import IO_TIMEOUT, serving

from focas_net.client import FocasClient, NativeClient
from focas_net.sim import Machine, default_machine
from focas_net.sim.statefile import StateFile, decode_state

PROGRAM = "O0321 (KEPT)\nN10 G91 G1 X10. F600\nN20 M30\n"


def _kept_programs(path: Path) -> list[str]:
    programs: list[str] = decode_state(path.read_bytes())["kept"]["paths"][0]["programs"]
    return programs


def _kept(tmp_path: Path) -> tuple[StateFile, Machine]:
    state = StateFile(tmp_path / "m.state")
    machine = state.load(default_machine)
    machine.set_panel(0, 1, 0)  # MDI, parameter writes enabled
    return state, machine


async def test_a_packed_download_and_a_native_deletion_are_kept(tmp_path: Path) -> None:
    state, machine = _kept(tmp_path)
    async with serving(machine, durable=lambda: state.save(machine)) as served:
        async with FocasClient(served.host, served.port) as cnc:
            await cnc.write_program(PROGRAM + "%")
            assert any("O0321 (KEPT)" in text for text in _kept_programs(state.path))
        async with NativeClient(served.host, served.port) as native:
            await native.delete_file("//CNC_MEM/USER/PATH1/O0321")
            assert not any("O0321" in text for text in _kept_programs(state.path))
    again = StateFile(state.path).load(default_machine)
    assert 321 not in [p.number for p in again.path_programs().directory()]


@pytest.mark.skipif(
    not LIBRARY,
    reason="set FOCAS_NET_FWLIB to the path of FANUC's libfwlib32 (e.g. libfwlib32.so.1) "
    "to run FANUC's library against the simulator",
)
async def test_a_download_through_fanucs_library_is_kept(tmp_path: Path) -> None:
    state, machine = _kept(tmp_path)
    async with serving(machine, durable=lambda: state.save(machine)) as served:
        async with FocasClient(served.host, served.port, timeout=IO_TIMEOUT) as packed:
            handle = await connect(served)
            try:
                cnc = Cnc(served, packed, handle, "30i")
                assert await download(cnc, b"\n" + PROGRAM.encode() + b"%") == 0
                assert any("O0321 (KEPT)" in text for text in _kept_programs(state.path))
            finally:
                await handle.free()
    again = StateFile(state.path).load(default_machine)
    assert "O0321 (KEPT)" in again.path_programs().text(321)
