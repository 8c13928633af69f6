"""After the connect, both clients word a dropped connection and a call left unanswered the
same way (``focas_net.client._failures``): no request number on one transport alone, no
wrapping of the connection's words on the other. The CLI prints these words as they are."""

from __future__ import annotations

import re
from typing import Final

import pytest
from support import serving

from focas_net.client import FocasClient, NativeClient
from focas_net.errors import FocasConnectionError, FocasError, FocasTimeoutError
from focas_net.protocol import FaultScope

CLIENTS: Final = (FocasClient, NativeClient)
#: A call's FOCAS name, with the packed command's id where it has one.
_CALL: Final = re.compile(r"cnc_\w+(?: \(0x[0-9A-F]{4}\))?")


async def _failure(cls: type[FocasClient] | type[NativeClient], kind: str, arg: int) -> FocasError:
    async with serving() as served:
        async with FocasClient(served.host, served.port) as control:
            async with cls(served.host, served.port, timeout=0.5) as client:
                await client.read_status()
                await control.sim.inject_fault(kind, arg=arg, scope="machine")
                with pytest.raises(FocasError) as caught:
                    await client.read_status()
                await control.sim.clear_faults(FaultScope.MACHINE)
    return caught.value


async def test_a_dropped_connection_reads_the_same_on_both_clients() -> None:
    words = set()
    for cls in CLIENTS:
        err = await _failure(cls, "drop", 0)
        assert type(err) is FocasConnectionError, err
        words.add(re.sub(r":\d+", ":PORT", str(err)))
    assert words == {"connection closed by 127.0.0.1:PORT"}, words


async def test_an_unanswered_call_reads_the_same_on_both_clients() -> None:
    words = []
    for cls in CLIENTS:
        err = await _failure(cls, "delay", 3000)
        assert type(err) is FocasTimeoutError, err
        words.append(str(err))
    assert words[0] == "no answer to cnc_rdcncstat (0x0001)", words
    assert words[1] == "no answer to cnc_statinfo", words
    assert {_CALL.sub("CALL", w) for w in words} == {"no answer to CALL"}
