"""Reads of the native client started now and finished later, for a poller that reads many
machines from one task: :class:`NativeStarted` (a part of
:class:`~focas_net.client.NativeClient`).

Each ``start_*`` method checks its arguments and encodes its call in the caller's frame as its
plain read does, queues the call at once when the client is connected (the link packs what is
queued into frames of ``max_blocks`` blocks) and returns a
:class:`~focas_net.client._started.StartedCall`; while the client is not connected it runs the
plain read in a task of its own, as ``start_read_status`` does. Results and errors are the
plain read's.
"""

from __future__ import annotations

from collections.abc import Callable, Coroutine
from decimal import Decimal
from typing import Any, TypeVar

from focas_net.errors import CncError, PayloadError

from ..native import (
    AlarmMessages,
    LibraryCall,
    NativePmcArea,
    NativePmcData,
    ResponseBlock,
    calls,
    max_response_body,
)
from ..protocol import ActiveAlarm, PmcArea
from ._native_items import made_once, only_answer, text
from ._native_link import Handle, NativeLink, check_path_of
from ._started import StartedCall
from ._values import (
    I16_MAX,
    AreaLike,
    alarm_type_number,
    check_int,
    check_macro,
    check_pmc_range,
    macro_from_wire,
)

__all__: list[str] = []

_T = TypeVar("_T")
#: Most active alarms one ``cnc_rdalmmsg2`` asks for (the client's default).
_ACTIVE_ALARMS = 32
_ANSWER_HEAD = 16


def _macro(
    handle: Handle, call: LibraryCall, blocks: tuple[ResponseBlock, ...], _path: int
) -> Decimal | None:
    values = only_answer(handle, call, blocks)
    if not values.values:
        raise PayloadError("cnc_rdmacro: the answer carries no value")
    value: Decimal | None = macro_from_wire(*values.values[0].to_macro())
    return value


def _alarms(
    handle: Handle, call: LibraryCall, blocks: tuple[ResponseBlock, ...], _path: int
) -> tuple[ActiveAlarm, ...]:
    value: AlarmMessages = only_answer(handle, call, blocks)
    return tuple(ActiveAlarm(a.axis, a.alarm_type, a.number, text(a.message)) for a in value.alarms)


class NativeStarted(NativeLink):
    """The started reads of the native client (see the module docstring)."""

    def _start(
        self,
        build: Callable[[Handle], LibraryCall],
        path: int,
        timeout: float | None,
        make: Callable[[Handle, LibraryCall, tuple[ResponseBlock, ...], int], _T],
        plain: Callable[[], Coroutine[Any, Any, _T]],
    ) -> StartedCall[_T]:
        """The call ``build(handle)`` of one frame on ``path``, its result ``make``'s (made
        once per answer), queued now; ``plain()`` in a task while there is no handle."""
        deadline = self._deadline(timeout)
        handle = self._handle
        if handle is None or handle.closed:
            return StartedCall.running(plain())
        try:
            call = build(handle)
            if path != 1:
                check_path_of(handle, path, call.function)
        except CncError as exc:
            return StartedCall.failed(exc)
        job = self._submit(call.part(0, path), handle.command_set, deadline)

        async def finish() -> _T:
            return made_once(handle, call, await job.token, make, path)

        return StartedCall(finish, lambda: self._session.abandon(job), job.token)

    def start_read_macro(
        self, number: int, *, path: int | None = None, timeout: float | None = None
    ) -> StartedCall[Decimal | None]:
        """``read_macro`` (``cnc_rdmacro``) started now."""
        p = self._path_of(path)
        check_macro(number)
        return self._start(
            lambda h: calls.cnc_rdmacro(h.command_set, number),
            p,
            timeout,
            _macro,
            lambda: self._plain("read_macro", number, path=p, timeout=timeout),
        )

    def start_read_alarms(
        self, *, path: int | None = None, timeout: float | None = None
    ) -> StartedCall[tuple[ActiveAlarm, ...]]:
        """``read_alarms()`` (``cnc_rdalmmsg2`` of every type, up to 32 alarms) started
        now."""
        p = self._path_of(path)
        every = alarm_type_number(-1, every=True)
        return self._start(
            lambda h: calls.cnc_rdalmmsg2(h.command_set, every, _ACTIVE_ALARMS),
            p,
            timeout,
            _alarms,
            lambda: self._plain("read_alarms", path=p, timeout=timeout),
        )

    def start_read_pmc(
        self, area: AreaLike, start: int, count: int, *, timeout: float | None = None
    ) -> StartedCall[bytes]:
        """``read_pmc`` (``pmc_rdpmcrng``) of a range one answer carries, started now; a
        longer range raises :class:`ValueError` (read it with ``read_pmc``)."""
        a: PmcArea = self._pmc_area(area)
        first, size = check_pmc_range(start, count)
        check_int("PMC byte count of one started read", size, 1, self._started_pmc_chunk())
        code = NativePmcArea[a.name].value

        def make(
            handle: Handle, call: LibraryCall, blocks: tuple[ResponseBlock, ...], _path: int
        ) -> bytes:
            data: NativePmcData = only_answer(handle, call, blocks)
            if len(data.raw) != size:
                raise PayloadError(f"pmc_rdpmcrng answer: {len(data.raw)} bytes, asked {size}")
            return data.raw

        return self._start(
            lambda h: calls.pmc_rdpmcrng(h.command_set, code, 0, first, first + size - 1),
            1,
            timeout,
            make,
            lambda: self._plain("read_pmc", a, first, size, timeout=timeout),
        )

    def _started_pmc_chunk(self) -> int:
        """Most PMC bytes one started read carries (within the smallest answer body)."""
        handle = self._handle
        version = handle.version if handle is not None else 1
        return min(I16_MAX, max_response_body(version) - 2 - _ANSWER_HEAD)

    async def _plain(self, method: str, *args: Any, **kwargs: Any) -> Any:
        """The plain read ``method`` of this client (a started read while not connected)."""
        return await getattr(self, method)(*args, **kwargs)
