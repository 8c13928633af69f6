"""Transports and hints, tenth pass: an answer that does not decode, named by the peer, the
call and the sizes on both transports (never a Python class), and the server's log of a TLS
or HTTP client met on a plain port.

Servers here bind 127.0.0.1 on ephemeral ports.
"""

from __future__ import annotations

import pytest
from support import IO_TIMEOUT, serving

from focas_net.adapters._native_cnc import CncHandlers
from focas_net.client import FocasClient, NativeClient
from focas_net.errors import EW, CncError, PayloadError
from focas_net.native import RequestBlock
from focas_net.sim import Machine, Session

# -- an answer that does not decode ------------------------------------------------------------


def _cut(monkeypatch: pytest.MonkeyPatch, handler: str, size: int) -> None:
    """Have the simulator's FOCAS/2 ``handler`` answer only its first ``size`` bytes."""
    whole = getattr(CncHandlers, handler)

    def cut(self: CncHandlers, block: RequestBlock, room: int, session: Session) -> bytes:
        data: bytes = whole(self, block, room, session)
        return data[:size]

    monkeypatch.setattr(CncHandlers, handler, cut)


async def test_a_status_answer_cut_short_names_the_peer_the_call_and_the_sizes(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """It read `cnc_statinfo: answer to 0x19 does not decode: StatInfo: 7 bytes, expected
    14`: no peer, and the codec's class name."""
    _cut(monkeypatch, "read_status", 7)
    async with serving() as s, NativeClient(s.host, s.port, timeout=IO_TIMEOUT) as client:
        with pytest.raises(PayloadError) as caught:
            await client.read_status()
    assert str(caught.value) == (
        f"127.0.0.1:{s.port} sent an answer to cnc_statinfo (0x19) that does not decode: "
        "7 bytes, expected 14"
    )


async def test_a_system_information_cut_short_names_the_peer_and_the_connect_call(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """The connect failed with `NativeSysInfo: 10 bytes, expected 18` alone."""
    _cut(monkeypatch, "read_sysinfo", 10)
    async with serving() as s:
        with pytest.raises(PayloadError) as caught:
            async with NativeClient(s.host, s.port, timeout=IO_TIMEOUT):
                pass
    assert str(caught.value) == (
        f"127.0.0.1:{s.port} sent an answer to cnc_allclibhndl3 (0x18) that does not decode: "
        "10 bytes, expected 18"
    )


@pytest.mark.parametrize(
    ("value", "width"), [(1, None), ("1.5", None), ("00000011", None), (1, 1), (1, 8)]
)
async def test_a_write_of_a_parameter_the_cnc_lacks_is_its_ew_number_whatever_the_value(
    both_clients: tuple[Machine, FocasClient, NativeClient], value: int | str, width: int | None
) -> None:
    """The refusal of a write by the next parameter's type or width is the CNC's EW_NUMBER,
    named by the write, on both transports."""
    _, cnc, native = both_clients
    for client in (cnc, native):
        with pytest.raises(CncError) as caught:
            await client.write_param(9999, value, width=width)
        assert (caught.value.ew, caught.value.detail) == (EW.NUMBER, "cnc_wrparam")
