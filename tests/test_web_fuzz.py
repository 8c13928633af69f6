"""Fuzzing the dashboard's actions as the wire protocols are fuzzed.

A real :class:`FocasServer` and its :class:`Dashboard` run in this process on 127.0.0.1 (port
0 each), with a packed and a native client connected to the machine. Each example POSTs a run
of page actions with generated arguments (valid ones, and huge, negative, wrongly typed, text,
nested JSON), lets machine time pass (a :class:`ManualClock` the test steps) and then reads the
machine through both protocols. The properties:

* the page answers every action with 200, or 400 (an argument it cannot use), 403 or 409 (a
  refusal with its EW code); never a server error;
* whatever the actions left in the machine, every read of both protocols (status, alarms,
  history, macro variables, PMC, parameters, positions, program numbers) succeeds or answers
  an EW code: no connection is dropped;
* nothing is logged at ERROR, no answer was one a wire could not carry (the adapters' warning),
  and the machine's page view is still served.

The default run posts about 1,300 actions; the ``slow`` variant many more
(``pytest -m slow tests/test_web_fuzz.py``).
"""

from __future__ import annotations

import logging
from collections.abc import AsyncIterator, Awaitable, Callable, Iterator
from dataclasses import dataclass
from typing import Any, Final

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from support import IO_TIMEOUT

from focas_net.client import CncClient, FocasClient, NativeClient
from focas_net.errors import CncError
from focas_net.protocol import FaultKind
from focas_net.server import FocasServer
from focas_net.sim import default_machine
from focas_net.sim.nc import ManualClock
from focas_net.web import ACTION_KEYS, ACTIONS, Dashboard, stations_of

aiohttp = pytest.importorskip("aiohttp", reason="the web dashboard tests need aiohttp")

_NO_FIXTURE_RESET = [HealthCheck.function_scoped_fixture, HealthCheck.too_slow]
CI: Final = settings(max_examples=200, deadline=None, suppress_health_check=_NO_FIXTURE_RESET)
SLOW: Final = settings(max_examples=5_000, deadline=None, suppress_health_check=_NO_FIXTURE_RESET)

#: What the page answers an action: done, a bad argument, a refusal (read-only, an EW code).
ANSWERED: Final = frozenset({200, 400, 403, 409})


# -- strategies ------------------------------------------------------------------------------

#: Integers at the edges of what the machine and the wires hold, and far beyond.
EDGES: Final = (
    -(2**63), -(2**31) - 1, -(2**31), -32769, -32768, -129, -2, -1, 0, 1, 2, 7, 8, 31, 32, 127,
    128, 255, 256, 9999, 10000, 32767, 32768, 65535, 65536, 2**31 - 1, 2**31, 99999999999,
    2**63, 10**30,
)  # fmt: skip
#: Text a number field may be given.
NUMBER_TEXTS: Final = (
    "", " ", "abc", "0x7FFF", "0x8000", "0b101", "-0", "1.5", "1e3", "1E+999999999",
    "1E-999999999", "NaN", "Infinity", "99999999999", " 12 ", "\u00e9", "\u20ac", "0" * 50,
)  # fmt: skip

json_leaf = st.one_of(
    st.none(),
    st.booleans(),
    st.integers(),
    st.sampled_from(EDGES),
    st.floats(),
    st.text(max_size=40),
    st.sampled_from(NUMBER_TEXTS),
)
wild = st.recursive(
    json_leaf,
    lambda inner: (
        st.lists(inner, max_size=3) | st.dictionaries(st.text(max_size=6), inner, max_size=3)
    ),
    max_leaves=8,
)

#: Parameter, macro variable and program numbers the default machine has (and a few more).
NUMBERS: Final = (1, 20, 100, 500, 999, 1000, 1001, 1005, 1320, 1420, 3115, 3901, 3902, 4001,
                  5001, 6711, 6712, 6713, 9999)  # fmt: skip

#: Arguments an action takes, each with values that make sense for it.
GOOD: Final[dict[str, st.SearchStrategy[Any]]] = {
    "action": st.sampled_from(["start", "hold", "reset"]),
    "mode": st.sampled_from([0, 1, 3, 5, 9, "1"]),
    "pwe": st.sampled_from([0, 1]),
    "emergency": st.sampled_from([0, 1]),
    "feed": st.integers(0, 260),
    "rapid": st.integers(0, 110),
    "spindle": st.integers(0, 260),
    "axis_no": st.integers(0, 4),
    "alm_type": st.integers(-1, 32),
    "alm_no": st.one_of(st.integers(-1, 40000), st.sampled_from(EDGES)),
    "msg": st.text(max_size=40),
    "area": st.sampled_from([*"XYFGRDKACTEx", "", "XX"]),
    "address": st.one_of(st.integers(0, 12), st.sampled_from([767, 7999, 9999, 10000])),
    "bit": st.integers(-1, 8),
    "value": st.one_of(st.integers(-3, 300), st.sampled_from(["1.5", "0.001", "-7", "12345678"])),
    "number": st.sampled_from(NUMBERS),
    "axis": st.integers(-1, 4),
    "password": st.text(max_size=6),
    "kind": st.sampled_from([k.name for k in FaultKind] + ["2", "foo", ""]),
    "count": st.integers(0, 3),
    "arg": st.integers(-1, 50),
}
#: The arguments of each action but ``path``, which every one takes (an unknown action gets a
#: few of all), as the page's actions declare them.
ARGS_OF: Final[dict[str, tuple[str, ...]]] = {
    action: tuple(sorted(keys - {"path"})) for action, keys in ACTION_KEYS.items()
}


@st.composite
def page_action(draw: st.DrawFn) -> tuple[str, dict[str, Any]]:
    """An action name (now and then an unknown one) and its arguments: each one it takes,
    mostly a sensible value, else an integer at an edge or anything JSON carries; now and then
    a stray key."""
    if draw(st.integers(0, 19)):
        name = draw(st.sampled_from(sorted(ARGS_OF)))
    else:
        name = draw(st.from_regex(r"[a-z_]{1,10}", fullmatch=True))
    keys = ARGS_OF.get(name, tuple(sorted(GOOD))[:4])
    args: dict[str, Any] = {}
    for key in keys:
        choice = draw(st.integers(0, 19))
        if choice == 0:
            continue  # left out
        if choice <= 3:
            args[key] = draw(wild)
        elif choice <= 7:
            args[key] = draw(st.sampled_from(EDGES))
        else:
            args[key] = draw(GOOD[key])
    if draw(st.integers(0, 9)) == 0:
        args[draw(st.text(max_size=6))] = draw(wild)
    return name, args


# -- the served machine ------------------------------------------------------------------------


class ErrorLog(logging.Handler):
    """Collects records at ERROR and above from any logger, and the adapters' warnings (an
    answer a wire could not carry: a value the machine should have refused)."""

    def __init__(self) -> None:
        super().__init__(logging.WARNING)
        self.records: list[logging.LogRecord] = []

    def emit(self, record: logging.LogRecord) -> None:
        if record.levelno >= logging.ERROR or record.name.startswith("focas_net.adapters"):
            self.records.append(record)


@pytest.fixture
def errors() -> Iterator[ErrorLog]:
    handler = ErrorLog()
    root = logging.getLogger()
    root.addHandler(handler)
    try:
        yield handler
    finally:
        root.removeHandler(handler)


@dataclass
class Served:
    clock: ManualClock
    web: Dashboard
    session: Any
    clients: tuple[CncClient, CncClient]

    async def post(self, action: str, args: dict[str, Any]) -> tuple[int, Any]:
        url = f"{self.web.url}api/machines/0/actions/{action}"
        async with self.session.post(url, json=args) as response:
            return response.status, await response.json()


@pytest.fixture
async def served() -> AsyncIterator[Served]:
    clock = ManualClock()
    machine = default_machine(sim_clock=clock)
    async with FocasServer([machine], host="127.0.0.1", port=0, grace_period=1.0) as server:
        host, port = server.listeners[0].address
        async with (
            Dashboard(stations_of(server), port=0) as web,
            aiohttp.ClientSession() as session,
            FocasClient(host, port, timeout=IO_TIMEOUT) as packed,
            NativeClient(host, port, timeout=IO_TIMEOUT) as native,
        ):
            yield Served(clock, web, session, (packed, native))


#: The reads made through each protocol after every run of actions.
READS: Final[tuple[Callable[[CncClient], Awaitable[object]], ...]] = (
    lambda c: c.read_status(),
    lambda c: c.read_alarms(),
    lambda c: c.read_alarm_history(),
    lambda c: c.read_alarm_history(250),
    lambda c: c.read_macro(100),
    lambda c: c.read_macro(500),
    lambda c: c.read_macro(3901),
    lambda c: c.read_macro(4001),
    lambda c: c.read_macro(5001),
    lambda c: c.read_pmc("X", 0, 8),
    lambda c: c.read_pmc("G", 0, 8),
    lambda c: c.read_pmc("F", 0, 8),
    lambda c: c.read_pmc("R", 0, 8),
    lambda c: c.read_param(6711),
    lambda c: c.read_param(1320, axis=1),
    lambda c: c.read_positions(),
    lambda c: c.read_positions("machine"),
    lambda c: c.read_program_numbers(),
    lambda c: c.read_feed(),
)


async def read_everything(client: CncClient) -> None:
    """Every read answers, with data or an EW code (a CncError); anything else fails."""
    for read in READS:
        try:
            await read(client)
        except CncError:
            pass


async def actions_property(
    served: Served, errors: ErrorLog, actions: list[tuple[str, dict[str, Any]]], seconds: float
) -> None:
    for name, args in actions:
        status, body = await served.post(name, args)
        assert status in ANSWERED, (name, args, body)
        assert body["ok"] is (status == 200), (name, args, body)
    assert (await served.post("clear_faults", {}))[0] == 200  # armed faults would drop reads
    served.clock.advance(seconds)
    for client in served.clients:
        await read_everything(client)
    async with served.session.get(f"{served.web.url}api/machines/0") as response:
        assert response.status == 200
    assert errors.records == []


#: The property over generated runs of actions and a time step, once per test below.
generated = given(
    actions=st.lists(page_action(), min_size=1, max_size=12), seconds=st.floats(0, 900)
)

test_no_page_action_leaves_a_machine_a_protocol_cannot_read = CI(generated(actions_property))
test_no_page_action_leaves_a_machine_a_protocol_cannot_read_long = pytest.mark.slow(
    SLOW(generated(actions_property))
)


def test_the_fuzz_knows_every_action() -> None:
    assert set(ARGS_OF) == set(ACTIONS)
