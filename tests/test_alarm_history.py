"""Counted alarm lists: the malformed-input rules of docs/protocol.md sections 2 and 3.

``cnc_rdalmhistry`` (0x0F1A) and ``cnc_rdalmmsg`` (0x0006). Decoding them never raises.
"""

from __future__ import annotations

import struct
from datetime import UTC, datetime, timedelta, timezone

import pytest
from hypothesis import given
from hypothesis import strategies as st

from focas_net.errors import EW
from focas_net.protocol import (
    ALARM_TYPE_NAMES,
    COMMANDS,
    MAX_ALARM_MSG,
    MAX_HISTORY_DEPTH,
    ActiveAlarm,
    ActiveAlarmList,
    AlarmHistory,
    AlarmHistoryEntry,
    AlarmType,
)

_HIST = struct.Struct("<10h")
_MSG = struct.Struct("<4h")


def hist_entry(
    when: tuple[int, int, int, int, int, int],
    axis: int,
    alm_type: int,
    alm_no: int,
    msg: bytes,
    msg_len: int | None = None,
) -> bytes:
    """One history entry laid out as section 3 says (built here, not by the codec)."""
    n = len(msg) if msg_len is None else msg_len
    return _HIST.pack(*when, axis, alm_type, alm_no, n) + msg + b"\x00" * (-len(msg) % 4)


def msg_entry(
    axis: int, alm_type: int, alm_no: int, msg: bytes, msg_len: int | None = None
) -> bytes:
    n = len(msg) if msg_len is None else msg_len
    return _MSG.pack(axis, alm_type, alm_no, n) + msg + b"\x00" * (-len(msg) % 4)


def count(n: int) -> bytes:
    return struct.pack("<h", n)


T1 = (2024, 5, 6, 7, 8, 9)
T2 = (2024, 5, 6, 7, 0, 0)
T3 = (2023, 1, 2, 3, 4, 5)
E1 = AlarmHistoryEntry(datetime(2024, 5, 6, 7, 8, 9, tzinfo=UTC), 1, 4, 500, "OT500")
E2 = AlarmHistoryEntry(datetime(2024, 5, 6, 7, 0, 0, tzinfo=UTC), 0, 3, 10, "")
E3 = AlarmHistoryEntry(datetime(2023, 1, 2, 3, 4, 5, tzinfo=UTC), 2, 6, 411, "SV0411 EXCESS ERR")
B1 = hist_entry(T1, 1, 4, 500, b"OT500")
B2 = hist_entry(T2, 0, 3, 10, b"")
B3 = hist_entry(T3, 2, 6, 411, b"SV0411 EXCESS ERR")
HISTORY = count(3) + B1 + B2 + B3


def decode_history(data: bytes) -> AlarmHistory:
    result = COMMANDS[0x0F1A].response.decode(data)
    assert isinstance(result, AlarmHistory)
    return result


def decode_active(data: bytes) -> ActiveAlarmList:
    result = COMMANDS[0x0006].response.decode(data)
    assert isinstance(result, ActiveAlarmList)
    return result


# -- alarm history --------------------------------------------------------------------------


def test_well_formed_history() -> None:
    history = decode_history(HISTORY)
    assert history.entries == (E1, E2, E3)
    assert history.ew == 0
    assert AlarmHistory((E1, E2, E3)).encode() == HISTORY


def test_occurrence_times_are_timezone_aware_utc() -> None:
    for entry in decode_history(HISTORY).entries:
        assert entry.occurred_at.tzinfo is not None
        assert entry.occurred_at.utcoffset() == timedelta(0)
        assert entry.occurred_at.tzinfo is UTC


@pytest.mark.parametrize(
    ("tail", "ew"),
    [
        ("0f00", 15),  # EW_ALARM
        ("0200", 2),  # EW_LENGTH
        ("ffff", -1),  # EW_BUSY: the code itself may be negative
        ("efff", -17),  # EW_PROTOCOL
    ],
)
def test_count_minus_one_carries_the_ew_code(tail: str, ew: int) -> None:
    history = decode_history(bytes.fromhex("ffff" + tail))
    assert history.entries == ()
    assert history.ew == ew
    active = decode_active(bytes.fromhex("ffff" + tail))
    assert active.entries == ()
    assert active.ew == ew


@pytest.mark.parametrize("raw_count", [-1, -2, -250, -32768])
def test_any_negative_count_gives_no_entries(raw_count: int) -> None:
    # entries present after the count are ignored all the same
    data = count(raw_count) + b"\x05\x00" + B1 + B2
    history = decode_history(data)
    assert history.entries == ()
    assert history.ew != 0
    active = decode_active(count(raw_count) + b"\x05\x00" + msg_entry(0, 3, 10, b"X"))
    assert active.entries == ()
    assert active.ew != 0


def test_negative_count_without_a_code_is_a_protocol_error_code() -> None:
    for data in (b"\xff\xff", b"\xff\xff\x02"):
        assert decode_history(data) == AlarmHistory((), int(EW.PROTOCOL))
        assert decode_active(data) == ActiveAlarmList((), int(EW.PROTOCOL))


@pytest.mark.parametrize("data", [b"", b"\x01"])
def test_payload_too_short_for_a_count(data: bytes) -> None:
    assert decode_history(data).entries == ()
    assert decode_history(data).ew != 0
    assert decode_active(data).entries == ()
    assert decode_active(data).ew != 0


@pytest.mark.parametrize(
    "when",
    [
        (2024, 0, 1, 0, 0, 0),  # month 0
        (2024, 13, 1, 0, 0, 0),  # month 13
        (2024, 1, 32, 0, 0, 0),  # day 32
        (2024, 1, 0, 0, 0, 0),  # day 0
        (2023, 2, 29, 0, 0, 0),  # not a leap year
        (2024, 4, 31, 0, 0, 0),  # April has 30 days
        (2024, 1, 1, 24, 0, 0),  # hour 24
        (2024, 1, 1, 0, 60, 0),  # minute 60
        (2024, 1, 1, 0, 0, 60),  # second 60
        (2024, 1, 1, -1, 0, 0),  # negative hour
        (0, 1, 1, 0, 0, 0),  # year 0
        (-1, 1, 1, 0, 0, 0),  # negative year
        (-32768, -32768, -32768, -32768, -32768, -32768),
        (32767, 32767, 32767, 32767, 32767, 32767),
    ],
)
def test_impossible_timestamp_is_skipped_and_the_rest_kept(
    when: tuple[int, int, int, int, int, int],
) -> None:
    # the bad entry carries a padded message so skipping it must still step over its pad
    bad = hist_entry(when, 1, 2, 3, b"BAD")
    data = count(4) + B1 + bad + B2 + B3
    assert decode_history(data).entries == (E1, E2, E3)
    # first and last positions as well
    assert decode_history(count(3) + bad + B1 + B2).entries == (E1, E2)
    assert decode_history(count(3) + B1 + B2 + bad).entries == (E1, E2)
    assert decode_history(count(1) + bad) == AlarmHistory()


def test_leap_day_is_possible() -> None:
    data = count(1) + hist_entry((2024, 2, 29, 23, 59, 59), 0, 0, 1, b"")
    [entry] = decode_history(data).entries
    assert entry.occurred_at == datetime(2024, 2, 29, 23, 59, 59, tzinfo=UTC)


@pytest.mark.parametrize("msg_len", [-1, -4, -32768])
def test_negative_msg_len_ends_the_list_keeping_earlier_entries(msg_len: int) -> None:
    bad = hist_entry(T1, 0, 0, 1, b"ABCD", msg_len=msg_len)
    assert decode_history(count(4) + B1 + B2 + bad + B3).entries == (E1, E2)
    assert decode_history(count(2) + bad + B1).entries == ()


@pytest.mark.parametrize("extra", [1, 4, 100, 32767])
def test_overrunning_msg_len_ends_the_list_keeping_earlier_entries(extra: int) -> None:
    # the last entry claims more message bytes than the payload has
    msg = b"WXYZ"
    overrun = hist_entry(T1, 0, 0, 1, msg, msg_len=min(len(msg) + extra, 32767))
    assert decode_history(count(3) + B1 + B2 + overrun).entries == (E1, E2)
    # a claim that swallows the following entries ends the list too, and nothing after it is read
    swallow = hist_entry(T1, 0, 0, 1, b"", msg_len=len(B3) + 1)
    assert decode_history(count(4) + B1 + swallow + B3).entries == (E1,)


def test_a_msg_len_reaching_exactly_the_end_is_kept() -> None:
    last = _HIST.pack(*T3, 2, 6, 411, 5) + b"HELLO"  # no pad after the very last message
    [e1, e] = decode_history(count(2) + B1 + last).entries
    assert e1 == E1
    assert e.msg == "HELLO"


def test_truncated_history_keeps_every_whole_entry() -> None:
    full = decode_history(HISTORY).entries
    for cut in range(2, len(HISTORY) + 1):
        entries = decode_history(HISTORY[:cut]).entries
        assert entries == full[: len(entries)], cut
    # cut right after each whole entry (its pad included) keeps exactly the entries before
    assert decode_history(count(3) + B1).entries == (E1,)
    assert decode_history(count(3) + B1 + B2).entries == (E1, E2)
    assert decode_history(count(3) + B1 + B2 + B3[:36]).entries == (E1, E2)  # msg cut short
    # a missing pad after the last message does not lose it
    assert decode_history(count(3) + B1 + B2 + B3[:-1]).entries == (E1, E2, E3)


def test_count_larger_than_the_entries_sent() -> None:
    assert decode_history(count(250) + B1 + B2).entries == (E1, E2)


def test_count_smaller_than_the_entries_sent_reads_count_entries() -> None:
    assert decode_history(count(1) + B1 + B2 + B3).entries == (E1,)
    assert decode_history(count(0) + B1).entries == ()


def test_encode_converts_aware_times_to_utc() -> None:
    plus_two = timezone(timedelta(hours=2))
    entry = AlarmHistoryEntry(datetime(2024, 5, 6, 9, 8, 9, tzinfo=plus_two), 1, 4, 500, "OT500")
    assert AlarmHistory((entry,)).encode() == count(1) + B1
    assert decode_history(count(1) + B1).entries == (entry,)  # the same instant


def test_error_answers_carry_no_entries() -> None:
    assert AlarmHistory((), 2).encode() == bytes.fromhex("ffff 0200")
    with pytest.raises(ValueError):
        AlarmHistory((E1,), 2).encode()
    with pytest.raises(ValueError):
        ActiveAlarmList((ActiveAlarm(0, 0, 1, ""),), 2).encode()


def test_non_latin1_message_cannot_be_encoded() -> None:
    entry = AlarmHistoryEntry(E1.occurred_at, 0, 0, 1, "\u20ac")
    with pytest.raises(ValueError):
        AlarmHistory((entry,)).encode()
    with pytest.raises(ValueError):
        ActiveAlarmList((ActiveAlarm(0, 0, 1, "\u20ac"),)).encode()


def test_entry_key_and_alarm_types() -> None:
    assert E1.key == (E1.occurred_at, 500, 4, E1.axis_no)
    assert ActiveAlarm(1, 4, 500, "x").key == (1, 4, 500)
    assert ALARM_TYPE_NAMES[3] == "PS"
    assert ALARM_TYPE_NAMES[19] == "PC"
    assert 14 not in ALARM_TYPE_NAMES
    assert [t.value for t in AlarmType] == [0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 15, 19]
    assert MAX_ALARM_MSG == 32
    assert MAX_HISTORY_DEPTH == 250


# -- active alarms (cnc_rdalmmsg) ---------------------------------------------------------------

A1 = ActiveAlarm(0, 3, 10, "PARITY")
A2 = ActiveAlarm(1, 4, 500, "")
A3 = ActiveAlarm(2, 6, 411, "SV41")
M1 = msg_entry(0, 3, 10, b"PARITY")
M2 = msg_entry(1, 4, 500, b"")
M3 = msg_entry(2, 6, 411, b"SV41")
ACTIVE = count(3) + M1 + M2 + M3


def test_well_formed_active_list() -> None:
    assert decode_active(ACTIVE) == ActiveAlarmList((A1, A2, A3))
    assert ActiveAlarmList((A1, A2, A3)).encode() == ACTIVE


@pytest.mark.parametrize("msg_len", [-1, -32768])
def test_active_negative_msg_len_ends_the_list(msg_len: int) -> None:
    bad = msg_entry(0, 0, 1, b"ABCD", msg_len=msg_len)
    assert decode_active(count(4) + M1 + M2 + bad + M3).entries == (A1, A2)


def test_active_overrunning_msg_len_ends_the_list() -> None:
    over = msg_entry(0, 0, 1, b"ABCD", msg_len=5)
    assert decode_active(count(3) + M1 + M2 + over).entries == (A1, A2)
    swallow = msg_entry(0, 0, 1, b"", msg_len=len(M3) + 1)
    assert decode_active(count(3) + M1 + swallow + M3).entries == (A1,)


def test_truncated_active_list_keeps_every_whole_entry() -> None:
    full = decode_active(ACTIVE).entries
    for cut in range(2, len(ACTIVE) + 1):
        entries = decode_active(ACTIVE[:cut]).entries
        assert entries == full[: len(entries)], cut
        assert decode_active(ACTIVE[:cut]).ew == 0
    assert decode_active(count(3) + M1).entries == (A1,)


# -- never raises ---------------------------------------------------------------------------


@given(st.binary(max_size=400))
def test_arbitrary_bytes_never_raise(blob: bytes) -> None:
    history = decode_history(blob)
    active = decode_active(blob)
    for entry in history.entries:
        assert entry.occurred_at.tzinfo is UTC
    assert len(history.entries) <= max(0, (len(blob) - 2) // 20)
    assert len(active.entries) <= max(0, (len(blob) - 2) // 8)


raw_i16 = st.integers(-32768, 32767)
small = st.integers(-3, 40)


@st.composite
def structured_history(draw: st.DrawFn) -> bytes:
    """Entry-shaped bytes with hostile fields: odd dates, lying msg_len, random truncation."""
    n = draw(st.integers(0, 6))
    parts = [count(draw(st.one_of(st.integers(-2, 8), raw_i16)))]
    for _ in range(n):
        when = draw(
            st.tuples(
                st.one_of(st.integers(1990, 2100), raw_i16),
                st.one_of(st.integers(0, 13), raw_i16),
                st.integers(-1, 33),
                st.integers(-1, 25),
                st.integers(-1, 61),
                st.integers(-1, 61),
            )
        )
        msg = draw(st.binary(max_size=36))
        msg_len = draw(st.one_of(st.just(len(msg)), small, raw_i16))
        parts.append(hist_entry(when, draw(small), draw(small), draw(raw_i16), msg, msg_len))
    data = b"".join(parts)
    return data[: draw(st.integers(0, len(data)))]


@st.composite
def structured_active(draw: st.DrawFn) -> bytes:
    n = draw(st.integers(0, 6))
    parts = [count(draw(st.one_of(st.integers(-2, 8), raw_i16)))]
    for _ in range(n):
        msg = draw(st.binary(max_size=36))
        msg_len = draw(st.one_of(st.just(len(msg)), small, raw_i16))
        parts.append(msg_entry(draw(small), draw(small), draw(raw_i16), msg, msg_len))
    data = b"".join(parts)
    return data[: draw(st.integers(0, len(data)))]


@given(structured_history())
def test_hostile_history_never_raises(data: bytes) -> None:
    history = decode_history(data)
    assert isinstance(history.entries, tuple)
    for entry in history.entries:
        assert entry.occurred_at.tzinfo is UTC
        assert entry.occurred_at.microsecond == 0
    if history.ew:
        assert history.entries == ()


@given(structured_active())
def test_hostile_active_list_never_raises(data: bytes) -> None:
    active = decode_active(data)
    assert isinstance(active.entries, tuple)
    if active.ew:
        assert active.entries == ()
