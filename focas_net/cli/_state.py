"""``serve --state DIR``: each machine's state file, loaded when it is built and saved as it
changes (:mod:`focas_net.sim.statefile`; the server holds each loop turn's answers until the
save, :mod:`focas_net.server._durable`)."""

from __future__ import annotations

import argparse
from collections.abc import AsyncIterator, Callable
from contextlib import asynccontextmanager
from typing import TYPE_CHECKING, Final

import anyio

from focas_net._typed import os_reason

if TYPE_CHECKING:
    from focas_net.server import FocasServer
    from focas_net.sim import Machine
    from focas_net.sim.statefile import StateFile

__all__ = ["SAVE_INTERVAL", "Kept", "keep_running", "load_state", "saver", "state_folder_of"]

#: Seconds between the saves of what changes without an answer waiting for it (a running
#: machine's parts counts and timers); a write a client or the web dashboard makes is saved
#: before its answer leaves.
SAVE_INTERVAL: Final = 1.0

#: A machine and its state file.
Kept = tuple["StateFile", "Machine"]


def state_folder_of(args: argparse.Namespace) -> str | None:
    """Where the machines keep their state: ``--state``, else the machine file's
    ``[machine] state`` (MachineFileError as the machine file's loading), else None."""
    given: str | None = getattr(args, "state", None)
    if given is not None or args.machine is None:
        return given
    from focas_net.sim.machinefile import state_folder

    folder = state_folder(args.machine)
    return None if folder is None else str(folder)


def _named_by(args: argparse.Namespace) -> str:
    """What named the state folder, for messages: ``--state``, or the machine file's key."""
    if getattr(args, "state", None) is not None:
        return "--state"
    return f"{args.machine}: machine.state"


def load_state(
    args: argparse.Namespace, directory: str | None, machine: Machine, states: list[Kept]
) -> Machine:
    """``machine`` (just built) with the kept data of its state file in ``directory`` put
    back, its state file appended to ``states`` (None: ``machine`` as it is); ValueError
    naming the file when it cannot be loaded (the machine is dropped then)."""
    from focas_net.sim.statefile import StateError, StateFile, check_folder, state_path

    if directory is None:
        return machine
    state = StateFile(state_path(directory, machine.name), read_only=bool(args.read_only))
    try:
        if not states and not args.read_only:
            check_folder(directory)  # once, before the first machine: writable at all?
        machine = state.load(lambda: machine)
    except StateError as exc:
        raise ValueError(f"{_named_by(args)}: {exc}") from None
    except OSError as exc:
        # the folder once; a file in it (or a path beyond it) by its own name too
        where = "" if exc.filename in (None, directory) else f"{exc.filename}: "
        raise ValueError(f"{_named_by(args)} {directory}: {where}{os_reason(exc)}") from None
    states.append((state, machine))
    return machine


def saver(states: list[Kept]) -> Callable[[], None]:
    """What the server calls at the end of a turn: every changed machine's state saved (one
    flush per changed machine, and one for the folder where a file was created or compacted)."""

    from focas_net.sim.statefile import save_all

    def save() -> None:
        save_all(states)

    return save


@asynccontextmanager
async def keep_running(
    server: FocasServer, states: list[Kept], read_only: bool
) -> AsyncIterator[None]:
    """While the machines are served, save every :data:`SAVE_INTERVAL` seconds what changed
    without an answer to wait for it: what the machines running on their own did (their
    parts and timers; nothing without ``--state``, or read-only)."""
    keeper = server.keeper
    running = [m for _, m in states if m.scenario_running]
    if keeper is None or read_only or not states:
        yield
        return

    async def tick() -> None:
        while True:
            await anyio.sleep(SAVE_INTERVAL)
            for machine in running:
                _ = machine.version  # brings the machine to the clock's time
            keeper.flush()

    async with anyio.create_task_group() as tg:
        tg.start_soon(tick)
        try:
            yield
        finally:
            tg.cancel_scope.cancel()
