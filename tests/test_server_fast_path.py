"""The packed server's fast path (the whole requests of a read, found in the receive buffer by
``scan_frames``) answers exactly as its general path (the decoder's frames, ``data_received``)
does.

Connections serve one machine through one adapter, on a transport that keeps what is written;
each request is read alone (the fast path's one request), behind a status request in the same
read (the fast path's many) and through ``data_received`` behind that status request (the
general path). Only commands that change nothing are generated, and the machine's clocks stand
still, so the answers must be the same bytes. What the fast path leaves to the decoder (a
length out of bounds, a partial request) goes on in order, and so do a fault command and answers
past the write budget.
"""

from __future__ import annotations

from datetime import UTC, datetime
from typing import Final

from hypothesis import given, settings
from hypothesis import strategies as st
from peers import Sink

from focas_net._receive import receive_buffer
from focas_net.adapters import PackedAdapter
from focas_net.protocol import COMMANDS, HEADER, Command, encode_frame
from focas_net.server._base import Limits
from focas_net.server._packed import PackedConnection
from focas_net.server.faults import FaultQueue
from focas_net.sim import default_machine
from focas_net.sim.nc import ManualClock

STATUS: Final = int(Command.RDCNCSTAT)
_NOON: Final = datetime(2026, 1, 1, 12, tzinfo=UTC)
#: Reads only: no write, program change, simulator control or fault command.
READS: Final = sorted(
    int(c) for c in COMMANDS if not Command(c).name.startswith(("WR", "DEL", "SEL", "SIM_"))
)


def _connection(adapter: PackedAdapter) -> tuple[PackedConnection, Sink]:
    conn = PackedConnection(adapter, FaultQueue(), Limits(), lambda _: None)
    sink = Sink()
    conn.connection_made(sink)  # type: ignore[arg-type]
    return conn, sink


def _read(conn: PackedConnection, data: bytes) -> None:
    """What the transport does with a read of ``data``."""
    buf = conn.get_buffer(len(data))
    assert len(buf) >= len(data) and buf is receive_buffer()
    buf[: len(data)] = data
    conn.buffer_updated(len(data))


def _frames(data: bytes) -> list[tuple[int, int, bytes]]:
    out = []
    pos = 0
    while pos < len(data):
        length, command, request_id = HEADER.unpack_from(data, pos)
        out.append((command, request_id, bytes(data[pos + 8 : pos + 4 + length])))
        pos += 4 + length
    return out


#: One machine for both connections, on clocks that do not move: its reads answer the same
#: bytes each time.
ADAPTER: Final = PackedAdapter(default_machine(clock=lambda: _NOON, sim_clock=ManualClock()))


@settings(max_examples=300, deadline=None)
@given(
    command=st.sampled_from([*READS, 0x0BAD]),  # 0x0BAD: an id nobody answers (EW_FUNC)
    payload=st.one_of(st.just(b""), st.binary(max_size=24)),
    request_id=st.integers(0, 0xFFFF),
)
def test_a_request_alone_in_a_read_is_answered_as_one_among_others(
    command: int, payload: bytes, request_id: int
) -> None:
    alone, alone_out = _connection(ADAPTER)
    among, among_out = _connection(ADAPTER)
    general, general_out = _connection(ADAPTER)
    request = encode_frame(command, request_id, payload)
    behind_status = encode_frame(STATUS, request_id ^ 1, b"") + request

    _read(alone, request)
    _read(among, behind_status)
    general.data_received(behind_status)

    (fast,) = _frames(b"".join(alone_out.frames))
    status, fast_among = _frames(b"".join(among_out.frames))
    assert _frames(b"".join(general_out.frames)) == [status, fast_among]
    assert status[0] == STATUS and status[1] == request_id ^ 1
    assert fast == fast_among
    assert fast[:2] == (command, request_id)


def test_a_request_split_over_reads_and_one_behind_it_are_answered_in_order() -> None:
    conn, out = _connection(ADAPTER)
    first = encode_frame(STATUS, 1, b"")
    second = encode_frame(STATUS, 2, b"")
    _read(conn, first[:5])  # a partial frame, held by the decoder (the general path) ...
    _read(conn, first[5:])  # ... and completed by the rest
    _read(conn, second)  # nothing held any more: the fast path
    assert [(c, r) for c, r, _ in _frames(b"".join(out.frames))] == [(STATUS, 1), (STATUS, 2)]


def _ids(out: Sink) -> list[tuple[int, int]]:
    return [(c, r) for c, r, _ in _frames(b"".join(out.frames))]


def test_many_requests_in_a_read_are_answered_in_order_in_one_write() -> None:
    class FastOnly(PackedConnection):
        __slots__ = ()

        def data_received(self, data: bytes) -> None:
            raise AssertionError(f"{len(data)} bytes left to the general path")

    conn = FastOnly(ADAPTER, FaultQueue(), Limits(), lambda _: None)
    out = Sink()
    conn.connection_made(out)  # type: ignore[arg-type]
    requests = [encode_frame(STATUS, n, b"") for n in range(64)]
    _read(conn, b"".join(requests))
    assert _ids(out) == [(STATUS, n) for n in range(64)]
    assert len(out.frames) == 1  # one write: the 64 answers joined


def test_requests_then_a_partial_one_the_rest_completes_it() -> None:
    conn, out = _connection(ADAPTER)
    third = encode_frame(STATUS, 3, b"")
    _read(conn, encode_frame(STATUS, 1, b"") + encode_frame(STATUS, 2, b"") + third[:6])
    assert _ids(out) == [(STATUS, 1), (STATUS, 2)]
    _read(conn, third[6:] + encode_frame(STATUS, 4, b""))
    assert _ids(out) == [(STATUS, n) for n in (1, 2, 3, 4)]


def test_a_fault_command_among_requests_keeps_their_order() -> None:
    conn, out = _connection(ADAPTER)
    listing = int(Command.SIM_LIST_FAULTS)
    scope = bytes(2)  # the connection's own faults
    data = (
        encode_frame(STATUS, 1, b"")
        + encode_frame(listing, 2, scope)
        + encode_frame(STATUS, 3, b"")
    )
    _read(conn, data)
    assert _ids(out) == [(STATUS, 1), (listing, 2), (STATUS, 3)]


def test_a_length_out_of_bounds_after_requests_closes_after_their_answers() -> None:
    conn, out = _connection(ADAPTER)
    closed: list[bool] = []
    out.close = lambda: closed.append(True)  # type: ignore[method-assign]
    bad = HEADER.pack(3, STATUS, 9)  # a length below 4
    _read(conn, encode_frame(STATUS, 1, b"") + encode_frame(STATUS, 2, b"") + bad)
    assert _ids(out) == [(STATUS, 1), (STATUS, 2)]  # written before the close, still sent
    assert conn.violated and closed == [True]


def test_answers_past_the_write_budget_go_on_in_order() -> None:
    conn = PackedConnection(ADAPTER, FaultQueue(), Limits(write_buffer_high=64), lambda _: None)
    out = Sink()
    conn.connection_made(out)  # type: ignore[arg-type]
    _read(conn, b"".join(encode_frame(STATUS, n, b"") for n in range(40)))
    assert _ids(out) == [(STATUS, n) for n in range(40)]
