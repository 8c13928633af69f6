"""Pure parts of the client: macro scaling, backoff, keyed locks, PMC chunk arithmetic."""

from __future__ import annotations

import asyncio
from decimal import Decimal

import pytest

from focas_net._typed import macro_to_wire
from focas_net.client import FocasClient, ReconnectPolicy
from focas_net.client._composite import chunked_write_error
from focas_net.client._locks import KeyedLocks
from focas_net.client._values import macro_from_wire, param_int
from focas_net.errors import EW, CncError, FocasConnectionError, FocasTimeoutError


@pytest.mark.parametrize(
    ("value", "wire"),
    [
        (0, (0, 0)),
        (-42, (-42, 0)),
        (2**31 - 1, (2**31 - 1, 0)),
        (Decimal("1.50"), (150, 2)),
        (Decimal("1E+3"), (1000, 0)),
        (Decimal("0.1000000000"), (1, 1)),  # ten places do not fit; the exact value does
        (0.1, (1, 1)),
        (-2.5, (-25, 1)),
        (1e9, (1000000000, 0)),
        ("12.345", (12345, 3)),
        (" -0.000000001 ", (-1, 9)),
    ],
)
def test_macro_to_wire(value: int | Decimal | float | str, wire: tuple[int, int]) -> None:
    assert macro_to_wire(value) == wire
    assert macro_from_wire(*wire) == Decimal(str(value).strip())


@pytest.mark.parametrize(
    "value", [2**31, -(2**31) - 1, 1e20, float("nan"), float("inf"), "abc", "0.0000000001"]
)
def test_macro_values_that_cannot_be_carried(value: object) -> None:
    with pytest.raises(ValueError):
        macro_to_wire(value)  # type: ignore[arg-type]


@pytest.mark.parametrize("value", [True, None, b"1", [1]])
def test_macro_values_that_are_not_numbers(value: object) -> None:
    with pytest.raises(TypeError, match="a macro value must be"):
        macro_to_wire(value)  # type: ignore[arg-type]


def test_macro_from_wire_vacant() -> None:
    assert macro_from_wire(0, -1) is None
    assert macro_from_wire(12345, 3) == Decimal("12.345")


def test_reconnect_policy_backoff_is_capped_with_jitter() -> None:
    policy = ReconnectPolicy(initial_delay=0.1, max_delay=2.0, factor=2.0, jitter=0.5)
    for attempt in range(200):
        base = min(2.0, 0.1 * 2.0**attempt)
        assert base * 0.5 <= policy.delay(attempt) <= base
    exact = ReconnectPolicy(initial_delay=0.1, max_delay=1.0, jitter=0.0)
    assert [exact.delay(n) for n in range(6)] == [0.1, 0.2, 0.4, 0.8, 1.0, 1.0]
    with pytest.raises(ValueError):
        ReconnectPolicy(jitter=2.0)
    with pytest.raises(ValueError):
        ReconnectPolicy(factor=0.5)
    with pytest.raises(ValueError):
        ReconnectPolicy(max_attempts=0)


def test_a_chunked_write_error_is_one_rule_for_both_transports() -> None:
    """Written when confirmed, uncertain when sent and unanswered, not written otherwise;
    touching ranges of one kind merged, the first failure the cause."""
    spans = [(0, 31), (32, 63), (64, 95), (96, 127), (128, 159), (160, 163)]
    refused = CncError.from_ew(EW.PROT, "pmc_wrpmcrng")
    lost = FocasConnectionError("lost after the request was sent")
    never = FocasConnectionError("lost before the request was sent")
    outcomes = [None, None, (refused, False), (lost, True), (never, False), (lost, True)]
    error = chunked_write_error("D", spans, outcomes)
    assert error is not None
    assert error.written == [(0, 63)]
    assert error.not_written == [(64, 95), (128, 159)]
    assert error.uncertain == [(96, 127), (160, 163)]
    assert error.cause is refused and error.__cause__ is refused
    assert chunked_write_error("D", spans[:2], [None, None]) is None


async def test_keyed_locks_serialise_and_are_dropped_when_idle() -> None:
    locks: KeyedLocks[str] = KeyedLocks()
    order: list[str] = []

    async def worker(key: str, name: str) -> None:
        async with locks.hold(key):
            order.append(f"{name}+")
            await asyncio.sleep(0)
            await asyncio.sleep(0)
            order.append(f"{name}-")

    await asyncio.gather(worker("a", "1"), worker("a", "2"), worker("b", "3"))
    assert order.index("1-") < order.index("2+")  # same key: one after the other
    assert order.index("3+") < order.index("1-")  # other key: in parallel
    assert len(locks) == 0


async def test_keyed_lock_wait_respects_deadline_and_cancellation() -> None:
    locks: KeyedLocks[int] = KeyedLocks()
    loop = asyncio.get_running_loop()
    release = asyncio.Event()

    async def holder() -> None:
        async with locks.hold(1):
            await release.wait()

    task = asyncio.create_task(holder())
    await asyncio.sleep(0)
    with pytest.raises(FocasTimeoutError):
        async with locks.hold(1, loop.time() + 0.01):
            pass
    waiter = asyncio.create_task(locks.hold(1).__aenter__())
    await asyncio.sleep(0)
    waiter.cancel()
    with pytest.raises(asyncio.CancelledError):
        await waiter
    assert len(locks) == 1  # only the holder remains
    release.set()
    await task
    assert len(locks) == 0


def test_max_in_flight_is_bounded_within_the_request_ids() -> None:
    with pytest.raises(ValueError, match=r"1\.\.32768"):
        FocasClient("127.0.0.1", 1, max_in_flight=0)
    with pytest.raises(ValueError, match=r"1\.\.32768"):
        FocasClient("127.0.0.1", 1, max_in_flight=40_000)
    assert FocasClient("127.0.0.1", 1, max_in_flight=32_768).max_in_flight == 32_768


@pytest.mark.parametrize("text", ["\u0661\u0662", "\uff11", "1\u0662"])
def test_digits_of_other_scripts_are_no_macro_or_parameter_value(text: str) -> None:
    with pytest.raises(ValueError, match="ASCII"):
        macro_to_wire(text)
    with pytest.raises(ValueError, match="ASCII"):
        param_int(3216, text)
