"""The MQTT publisher's pure part: topics and payloads in golden bytes, the payloads' round
trips, the deadbands, a lost machine's Bad values, and the bounded buffer against a model."""

from __future__ import annotations

import json
import math
import subprocess
import sys
from urllib.parse import unquote

from gateway_support import machine_shape
from hypothesis import given
from hypothesis import strategies as st

from focas_net.errors import OPCUA_BAD_COMMUNICATION_ERROR, OPCUA_BAD_TIMEOUT, OPCUA_GOOD
from focas_net.gateway import AlarmChange, Sample, item
from focas_net.gateway._mqtt_messages import (
    ActiveAlarms,
    AlarmEvent,
    Availability,
    Buffer,
    DroppedCount,
    Message,
    Publication,
    ValuePayload,
    iso_time,
    topic_level,
)

SHAPE = machine_shape("lathe-2", ("X", "Z"), ("X", "Z", "C"))


def sample(name: str, value: object, *, path: int = 1, key: str = "", t: float = 0.0) -> Sample:
    return Sample("lathe-2", path, item(name), key, value, OPCUA_GOOD, t)  # type: ignore[arg-type]


def publication(**deadbands: float) -> Publication:
    return Publication("focas", "gw-1", deadbands)


# --- golden topics and payloads ---------------------------------------------------------------


def test_iso_time_is_utc_to_the_millisecond() -> None:
    assert iso_time(0.0) == "1970-01-01T00:00:00.000Z"
    assert iso_time(1_796_627_486.25) == "2026-12-07T07:11:26.250Z"


def test_topic_levels_escape_separators_wildcards_and_a_leading_dollar() -> None:
    assert topic_level("X") == "X"
    assert topic_level("a/b") == "a%2Fb"
    assert topic_level("+#%") == "%2B%23%25"
    assert topic_level("$gateway") == "%24gateway"
    assert topic_level("x$") == "x$"


def test_value_topics_and_payloads_in_golden_bytes() -> None:
    p = publication()
    messages = p.samples(
        [
            sample("absolute", 12.5, key="X", t=1.0),
            sample("feed", 1200.0, path=2, t=1.0),
            sample("mode", "MEM", t=1.0),
            sample("emergency", False, t=1.0),
            Sample("lathe-2", 1, item("parts"), "", None, OPCUA_BAD_TIMEOUT, 2.0),
        ]
    )
    assert messages == [
        Message(
            "focas/lathe-2/path1/absolute/X",
            b'{"value":12.5,"unit":"mm","status":"Good","time":"1970-01-01T00:00:01.000Z"}',
            True,
        ),
        Message(
            "focas/lathe-2/path2/feed",
            b'{"value":1200.0,"unit":"mm/min","status":"Good","time":"1970-01-01T00:00:01.000Z"}',
            True,
        ),
        Message(
            "focas/lathe-2/path1/mode",
            b'{"value":"MEM","unit":null,"status":"Good","time":"1970-01-01T00:00:01.000Z"}',
            True,
        ),
        Message(
            "focas/lathe-2/path1/emergency",
            b'{"value":false,"unit":null,"status":"Good","time":"1970-01-01T00:00:01.000Z"}',
            True,
        ),
        Message(
            "focas/lathe-2/path1/parts",
            b'{"value":null,"unit":"","status":"BadTimeout","time":"1970-01-01T00:00:02.000Z"}',
            True,
        ),
    ]


def test_a_bad_sample_carries_no_value_and_a_value_without_json_form_is_null() -> None:
    p = publication()
    bad = Sample("m", 1, item("feed"), "", 5.0, OPCUA_BAD_TIMEOUT, 0.0)
    (message,) = p.samples([bad])
    assert ValuePayload.decode(message.payload).value is None
    (message,) = p.samples([Sample("m", 1, item("feed"), "", math.nan, OPCUA_GOOD, 0.0)])
    assert ValuePayload.decode(message.payload) == ValuePayload(None, "mm/min", "Good", iso_time(0))


def test_gateway_birth_will_and_dropped_count() -> None:
    p = Publication("plant/focas", "edge/1")
    assert p.birth() == Message("plant/focas/$gateway/edge%2F1/state", b"online", True)
    assert p.will() == Message("plant/focas/$gateway/edge%2F1/state", b"offline", True)
    assert p.dropped(7, 0.0) == Message(
        "plant/focas/$gateway/edge%2F1/dropped",
        b'{"dropped":7,"time":"1970-01-01T00:00:00.000Z"}',
        True,
    )


def test_the_model_describes_paths_axes_spindles_and_items_with_units() -> None:
    p = publication(feed=5.0)
    (message,) = p.described(SHAPE)
    assert message.topic == "focas/lathe-2/$model"
    assert message.retain
    model = json.loads(message.payload)
    assert {k: v for k, v in model.items() if k != "items"} == {
        "machine": "lathe-2",
        "gateway": "gw-1",
        "topic": "focas/lathe-2",
        "host": "127.0.0.1",
        "port": 8193,
        "protocol": "native",
        "cnc_type": "31",
        "mt_type": "T",
        "series": "G421",
        "version": "30.0",
        "paths": [
            {"number": 1, "topic": "focas/lathe-2/path1", "axes": ["X", "Z"], "spindles": ["S1"]},
            {
                "number": 2,
                "topic": "focas/lathe-2/path2",
                "axes": ["X", "Z", "C"],
                "spindles": ["S2"],
            },
        ],
    }
    assert model["items"]["feed"] == {
        "scope": "path",
        "group": "fast",
        "type": "float",
        "unit": "mm/min",
        "unit_code": "H81",
        "deadband": 5.0,
        "description": "actual feed rate",
    }
    assert model["items"]["absolute"]["scope"] == "axis"
    assert model["items"]["spindle_load"]["scope"] == "spindle"
    assert model["items"]["mode"]["unit"] is None


def test_availability_in_golden_bytes() -> None:
    p = publication()
    assert p.online("lathe-2", True, "", 0.0) == [
        Message(
            "focas/lathe-2/availability",
            b'{"state":"AVAILABLE","reason":"","time":"1970-01-01T00:00:00.000Z","gateway":"gw-1"}',
            True,
        )
    ]
    (message,) = p.online("lathe-2", False, "connection refused", 1.0)
    assert Availability.decode(message.payload) == Availability(
        "UNAVAILABLE", "connection refused", "1970-01-01T00:00:01.000Z", "gw-1"
    )


def test_alarms_are_events_and_a_retained_active_list() -> None:
    p = publication()
    raised = AlarmChange("lathe-2", 2, 0, 100, 0, "PARAMETER ENABLE", True, 3.0)
    messages = p.alarms([raised])
    assert messages == [
        Message(
            "focas/lathe-2/path2/alarms/event",
            b'{"code":"SW0100","axis_no":0,"alm_type":0,"alm_no":100,"msg":"PARAMETER ENABLE",'
            b'"active":true,"time":"1970-01-01T00:00:03.000Z"}',
            False,
        ),
        Message(
            "focas/lathe-2/path2/alarms/active",
            b'{"alarms":[{"code":"SW0100","axis_no":0,"alm_type":0,"alm_no":100,'
            b'"msg":"PARAMETER ENABLE","active":true,"time":"1970-01-01T00:00:03.000Z"}],'
            b'"status":"Good","time":"1970-01-01T00:00:03.000Z"}',
            True,
        ),
    ]
    servo = AlarmChange("lathe-2", 2, 6, 401, 1, "V-READY OFF", True, 4.0)
    cleared = AlarmChange("lathe-2", 2, 0, 100, 0, "PARAMETER ENABLE", False, 4.0)
    *events, active = p.alarms([servo, cleared])
    assert [AlarmEvent.decode(e.payload).active for e in events] == [True, False]
    listed = ActiveAlarms.decode(active.payload).alarms
    assert listed is not None and [a.key for a in listed] == [(1, 6, 401)]


def test_a_lost_machine_shows_every_value_bad_and_its_alarms_unknown() -> None:
    p = publication()
    p.samples([sample("absolute", 1.0, key="X"), sample("mode", "MEM")])
    p.alarms([AlarmChange("lathe-2", 1, 6, 401, 1, "V-READY OFF", True, 0.0)])
    availability, *rest = p.online("lathe-2", False, "timed out", 9.0)
    assert Availability.decode(availability.payload).state == "UNAVAILABLE"
    assert [(m.topic, m.retain) for m in rest] == [
        ("focas/lathe-2/path1/absolute/X", True),
        ("focas/lathe-2/path1/mode", True),
        ("focas/lathe-2/path1/alarms/active", True),
    ]
    stamp = "1970-01-01T00:00:09.000Z"
    assert ValuePayload.decode(rest[0].payload) == ValuePayload(
        None, "mm", "BadCommunicationError", stamp
    )
    assert ValuePayload.decode(rest[1].payload) == ValuePayload(
        None, None, "BadCommunicationError", stamp
    )
    assert ActiveAlarms.decode(rest[2].payload) == ActiveAlarms(
        None, "BadCommunicationError", stamp
    )
    # lost again: nothing more to mark; back: the active list again, and the same value
    # as before is published (its status changed)
    assert len(p.online("lathe-2", False, "timed out", 10.0)) == 1
    back = p.online("lathe-2", True, "", 11.0)
    assert [m.topic for m in back] == [
        "focas/lathe-2/availability",
        "focas/lathe-2/path1/alarms/active",
    ]
    assert len(p.samples([sample("mode", "MEM")])) == 1


def test_the_retained_state_is_the_latest_message_of_every_topic() -> None:
    p = publication()
    (model,) = p.described(SHAPE)
    p.samples([sample("feed", 1.0)])
    (feed,) = p.samples([sample("feed", 2.0)])
    event, active = p.alarms([AlarmChange("lathe-2", 1, 6, 401, 1, "V-READY OFF", True, 0.0)])
    assert p.retained() == [model, feed, active]
    assert not event.retain


def test_discarding_the_waiting_retained_messages_keeps_the_events() -> None:
    buffer = Buffer(10)
    event = Message("e", b"", False)
    buffer.extend([Message("a", b"1", True), event, Message("b", b"2", True)])
    buffer.discard_retained()
    assert buffer.take(10) == [event]
    assert (buffer.dropped, buffer.coalesced) == (0, 0)


def test_machine_items_sit_under_the_machine() -> None:
    assert publication().value_topic("m", 0, "x", "") == "focas/m/x"


# --- properties -------------------------------------------------------------------------------

_texts = st.text(max_size=12)
_values = st.one_of(
    st.none(),
    st.booleans(),
    st.integers(-(2**53), 2**53),
    st.floats(allow_nan=False, allow_infinity=False),
    _texts,
)


@given(st.text(max_size=20))
def test_a_topic_level_is_one_level_without_wildcards_and_reads_back(name: str) -> None:
    level = topic_level(name)
    assert not any(c in level for c in "/+#\0")
    assert not level.startswith("$")
    assert unquote(level) == name


@given(_values, st.one_of(st.none(), _texts), _texts, _texts)
def test_value_payload_round_trip(value: object, unit: str | None, status: str, t: str) -> None:
    payload = ValuePayload(value, unit, status, t)  # type: ignore[arg-type]
    assert ValuePayload.decode(payload.encode()) == payload


_events = st.builds(
    AlarmEvent,
    st.integers(0, 31),
    st.integers(0, 32767),
    st.integers(0, 32),
    _texts,
    st.booleans(),
    _texts,
)


@given(_events)
def test_alarm_event_round_trip(event: AlarmEvent) -> None:
    assert AlarmEvent.decode(event.encode()) == event


@given(st.one_of(st.none(), st.lists(_events, max_size=4).map(tuple)), _texts, _texts)
def test_active_alarms_round_trip(alarms: tuple[AlarmEvent, ...] | None, s: str, t: str) -> None:
    payload = ActiveAlarms(alarms, s, t)
    assert ActiveAlarms.decode(payload.encode()) == payload


@given(st.sampled_from(["AVAILABLE", "UNAVAILABLE"]), _texts, _texts, _texts)
def test_availability_and_dropped_round_trip(state: str, reason: str, t: str, gw: str) -> None:
    availability = Availability(state, reason, t, gw)  # type: ignore[arg-type]
    assert Availability.decode(availability.encode()) == availability
    dropped = DroppedCount(len(reason), t)
    assert DroppedCount.decode(dropped.encode()) == dropped


@given(
    st.floats(0, 10),
    st.lists(st.floats(-1000, 1000), min_size=1, max_size=40),
    st.lists(st.booleans(), min_size=40, max_size=40),
)
def test_a_value_is_published_when_it_moved_past_the_deadband_or_its_status_changed(
    band: float, values: list[float], good: list[bool]
) -> None:
    p = Publication("focas", "gw", {"feed": band})
    last: tuple[float | None, str] | None = None
    for value, ok in zip(values, good, strict=False):
        status = OPCUA_GOOD if ok else OPCUA_BAD_COMMUNICATION_ERROR
        published = p.samples([Sample("m", 1, item("feed"), "", value, status, 0.0)])
        shown = value if ok else None
        if last is None or last[1] != status.name:
            expected = True
        elif shown is None or last[0] is None:
            expected = shown != last[0]
        else:
            expected = abs(shown - last[0]) > band
        assert bool(published) == expected
        if published:
            last = (shown, status.name)
            assert ValuePayload.decode(published[0].payload).value == shown


@given(st.lists(st.one_of(st.integers(0, 50), st.text(max_size=3)), max_size=60))
def test_without_a_deadband_every_change_is_published_and_only_a_change(
    values: list[object],
) -> None:
    p = publication()
    last: object = object()
    for value in values:
        published = p.samples([sample("message", value)])
        changed = value != last or type(value) is not type(last)
        assert bool(published) == changed
        if changed:
            last = value


# The buffer against a list model: ops are ("put", topic or None for an event), ("take", n)
# and ("fail", n): take n and restore them, as a broken connection does.
_ops = st.lists(
    st.one_of(
        st.tuples(st.just("put"), st.one_of(st.none(), st.sampled_from("abcdef"))),
        st.tuples(st.just("take"), st.integers(0, 4)),
        st.tuples(st.just("fail"), st.integers(0, 4)),
    ),
    max_size=60,
)


@given(st.integers(1, 6), _ops)
def test_buffer_is_bounded_coalesces_retained_and_drops_the_oldest(
    bound: int, ops: list[tuple[str, str | int | None]]
) -> None:
    buffer = Buffer(bound)
    model: list[Message] = []
    dropped = coalesced = 0
    for n, (op, arg) in enumerate(ops):
        if op == "put":
            message = Message(f"t/{arg or 'event'}", str(n).encode(), arg is not None)
            if message.retain and any(m.topic == message.topic and m.retain for m in model):
                model = [m for m in model if not (m.retain and m.topic == message.topic)]
                coalesced += 1
            model.append(message)
            buffer.put(message)
        else:
            assert isinstance(arg, int)
            taken = buffer.take(arg)
            assert taken == model[:arg]
            if op == "take":
                model = model[arg:]
            else:
                buffer.restore(taken)
        while len(model) > bound:
            model.pop(0)
            dropped += 1
        assert len(buffer) == len(model) <= bound
        assert (buffer.dropped, buffer.coalesced) == (dropped, coalesced)
    assert buffer.take(bound) == model


def test_restore_leaves_out_a_retained_message_superseded_meanwhile() -> None:
    buffer = Buffer(10)
    old, new, event = Message("a", b"1", True), Message("a", b"2", True), Message("e", b"", False)
    buffer.extend([old, event])
    taken = buffer.take(2)
    buffer.put(new)
    buffer.restore(taken)
    assert buffer.take(10) == [event, new]
    assert buffer.coalesced == 1


def test_the_gateway_package_and_the_messages_import_without_aiomqtt() -> None:
    """Only :mod:`focas_net.gateway.mqtt` needs the ``mqtt`` extra."""
    code = (
        "import sys; sys.modules['aiomqtt'] = None\n"
        "import focas_net.gateway, focas_net.gateway._mqtt_messages\n"
        "try:\n"
        "    import focas_net.gateway.mqtt\n"
        "except ImportError:\n"
        "    print('needs aiomqtt')\n"
    )
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert done.stdout == "needs aiomqtt\n"


# Calls a poller could make for one machine of one path, two axes: a sample of an item and
# axis (a value, or None for a Bad read), the machine lost, the machine back.
_calls = st.lists(
    st.one_of(
        st.tuples(
            st.just("sample"),
            st.sampled_from(["absolute", "feed", "mode"]),
            st.sampled_from(["X", "Z"]),
            st.one_of(st.none(), st.integers(0, 3).map(float)),
        ),
        st.tuples(st.just("lost"), st.just(""), st.just(""), st.none()),
        st.tuples(st.just("back"), st.just(""), st.just(""), st.none()),
    ),
    max_size=40,
)


@given(_calls, st.floats(0, 2))
def test_a_lost_machine_never_keeps_a_good_value_on_the_broker(
    calls: list[tuple[str, str, str, float | None]], band: float
) -> None:
    """The retained store a broker keeps, after any sequence of calls: a value topic the
    machine's loss marked (and no read since) is Bad with no value; every other shows the last
    read's status, and a Good one a value within the deadband of the last read."""
    p = Publication("focas", "gw", {"absolute": band, "feed": band})
    store: dict[str, bytes] = {}
    last: dict[str, tuple[float | str | None, str]] = {}
    marked: set[str] = set()
    for n, (call, name, axis, value) in enumerate(calls):
        if call == "sample":
            key = axis if item(name).scope.value == "axis" else ""
            status = OPCUA_GOOD if value is not None else OPCUA_BAD_TIMEOUT
            read = value if name != "mode" or value is None else str(value)
            s = Sample("m", 1, item(name), key, read, status, float(n))
            messages = p.samples([s])
            topic = p.value_topic("m", 1, name, key)
            last[topic] = (read, status.name)
            marked.discard(topic)
        else:
            messages = p.online("m", call == "back", "gone", float(n))
            if call == "lost":
                marked = set(last)
        store.update((m.topic, m.payload) for m in messages if m.retain)
        for topic, (read_value, read_status) in last.items():
            shown = ValuePayload.decode(store[topic])
            if topic in marked:
                assert (shown.value, shown.status) == (None, "BadCommunicationError")
                continue
            assert shown.status == read_status
            if isinstance(read_value, float):
                assert isinstance(shown.value, float) and abs(shown.value - read_value) <= band
            else:
                assert shown.value == read_value
