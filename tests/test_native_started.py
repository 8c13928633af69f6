"""The native client's started reads (``start_read_macro``, ``start_read_alarms``,
``start_read_pmc``), :meth:`StartedCall.on_done`, and :func:`alarm_changes`.

A started read gives what its plain read gives, errors included; its arguments are checked
before anything is sent; reads started together leave in one frame; ``on_done`` is told once
the answer is there, so ``result()`` then needs no wait.
"""

from __future__ import annotations

import asyncio

import pytest
from support import IO_TIMEOUT, serving, two_path_lathe

from focas_net.client import NativeClient, StartedCall, alarm_changes
from focas_net.errors import EW, CncError, FocasConnectionError
from focas_net.protocol import ActiveAlarm


async def test_started_reads_give_what_the_plain_reads_give() -> None:
    async with serving() as served:
        served.machine.raise_alarm(0, 2, 500, "OVER TRAVEL")
        served.machine.write_macro(3901, 7)
        async with NativeClient(served.host, served.port, timeout=IO_TIMEOUT) as cnc:
            frames = cnc.frames_sent
            macro = cnc.start_read_macro(3901)
            alarms = cnc.start_read_alarms()
            pmc = cnc.start_read_pmc("G", 12, 19)
            got = (await macro.result(), await alarms.result(), await pmc.result())
            assert cnc.frames_sent == frames + 1  # started together: one frame
            assert got == (
                await cnc.read_macro(3901),
                await cnc.read_alarms(),
                await cnc.read_pmc("G", 12, 19),
            )
            assert got[0] == 7 and [a.alm_no for a in got[1]] == [500]
            assert len(got[2]) == 19


async def test_started_reads_of_a_path_and_their_errors() -> None:
    lathe = two_path_lathe()
    lathe.raise_alarm(0, 2, 501, "PATH 2", path=2)
    async with serving(lathe) as served:
        async with NativeClient(served.host, served.port, timeout=IO_TIMEOUT) as cnc:
            one, two = cnc.start_read_alarms(path=1), cnc.start_read_alarms(path=2)
            assert await one.result() == ()
            assert [a.alm_no for a in await two.result()] == [501]
            with pytest.raises(CncError) as caught:
                await cnc.start_read_alarms(path=3).result()  # a path it has not
            assert caught.value.ew == EW.PATH
            with pytest.raises(CncError) as caught:
                await cnc.start_read_macro(3901).result()  # a variable it has not
            assert caught.value.ew == EW.NUMBER
            with pytest.raises(CncError) as caught:
                await cnc.start_read_pmc("R", 0, 4).result()  # no PMC: EW_NOOPT
            assert caught.value.ew == EW.NOOPT


async def test_arguments_are_checked_before_anything_is_sent() -> None:
    async with serving() as served:
        async with NativeClient(served.host, served.port, timeout=IO_TIMEOUT) as cnc:
            frames = cnc.frames_sent
            with pytest.raises(ValueError, match="macro variable number"):
                cnc.start_read_macro(40000)
            with pytest.raises(ValueError, match="unknown PMC area"):
                cnc.start_read_pmc("Q", 0, 1)
            with pytest.raises(ValueError, match="one started read"):
                cnc.start_read_pmc("D", 0, 60000)
            with pytest.raises(ValueError, match="path"):
                cnc.start_read_alarms(path=11)
            assert cnc.frames_sent == frames


async def test_a_client_not_connected_fails_as_its_plain_read() -> None:
    async with serving() as served:
        cnc = NativeClient(served.host, served.port, timeout=IO_TIMEOUT)
        call = cnc.start_read_macro(100)  # never connected: the plain read, in a task
        with pytest.raises(FocasConnectionError):
            await call.result()
        await cnc.aclose()


async def test_on_done_tells_when_the_answer_is_there() -> None:
    async with serving() as served:
        async with NativeClient(served.host, served.port, timeout=IO_TIMEOUT) as cnc:
            told: list[str] = []
            both = asyncio.Event()

            def tell(name: str) -> None:
                told.append(name)
                if len(told) == 2:
                    both.set()

            pmc, alarms = cnc.start_read_pmc("R", 0, 4), cnc.start_read_alarms()
            pmc.on_done(lambda: tell("a"))
            alarms.on_done(lambda: tell("b"))
            assert told == []
            async with asyncio.timeout(IO_TIMEOUT):
                await both.wait()
            assert sorted(told) == ["a", "b"]
            assert len(await pmc.result()) == 4
            assert await alarms.result() == ()
            failed: StartedCall[int] = StartedCall.failed(ValueError("x"))
            failed.on_done(lambda: told.append("failed"))
            await asyncio.sleep(0)
            assert told[-1] == "failed"
            with pytest.raises(ValueError):
                await failed.result()


def test_alarm_changes_are_keyed_by_axis_type_and_number() -> None:
    a, b = ActiveAlarm(0, 2, 500, "A"), ActiveAlarm(1, 2, 500, "B")
    cleared, raised, now = alarm_changes({}, [a, b])
    assert (cleared, raised) == ([], [a, b])
    renamed = ActiveAlarm(0, 2, 500, "A, new text")
    cleared, raised, later = alarm_changes(now, [renamed])
    assert (cleared, raised) == ([b], [])
    assert later == {a.key: renamed}
