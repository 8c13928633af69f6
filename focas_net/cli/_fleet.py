"""The machines of a ``serve`` fleet: which of them one process serves, and how each is built.

Machine ``i`` of a fleet is built from its index in the whole fleet, whichever process builds
it (``serve --workers N`` cuts the fleet into N contiguous slices, one per worker process), so
machine ``i`` is the same machine whatever N.
"""

from __future__ import annotations

import argparse
from dataclasses import replace
from typing import TYPE_CHECKING, Final

from focas_net._typed import os_reason

from ._state import Kept, load_state, state_folder_of

if TYPE_CHECKING:
    from focas_net.sim import Machine
    from focas_net.sim.nc import Scenario

__all__ = [
    "ConfigError",
    "OptionRefused",
    "build_machines",
    "fleet_indices",
    "fleet_slices",
    "machines_per_process",
]


class ConfigError(Exception):
    """A configuration problem reported as one line, exit code 2."""


class OptionRefused(ConfigError):
    """An option refused for what it says with the others (``--workers 3`` with ``--fleet
    2``): reported as the parser reports an option it refuses, ``argument --workers: why``."""

    def __init__(self, option: str, why: str) -> None:
        super().__init__(f"argument {option}: {why}")
        self.option = option
        self.why = why


def fleet_slices(fleet: int, workers: int) -> list[range]:
    """The machine indices of each of ``workers`` contiguous slices of ``fleet`` machines."""
    if not 1 <= workers <= fleet:
        raise ValueError(f"{workers} workers for {fleet} machines")
    bounds = [k * fleet // workers for k in range(workers + 1)]
    return [range(bounds[k], bounds[k + 1]) for k in range(workers)]


def fleet_indices(args: argparse.Namespace) -> range:
    """The indices in the whole fleet of the machines this process builds."""
    served: range | None = getattr(args, "fleet_slice", None)
    return served if served is not None else range(args.fleet)


def machines_per_process(args: argparse.Namespace) -> int:
    """The most machines one process of this ``serve`` serves."""
    served: range | None = getattr(args, "fleet_slice", None)
    if served is not None:
        return len(served)
    workers = getattr(args, "workers", 1)
    return -(-args.fleet // workers) if workers > 1 else int(args.fleet)


def build_machines(args: argparse.Namespace, states: list[Kept] | None = None) -> list[Machine]:
    """The machines described by the options; raises :class:`ConfigError`.

    With ``--state DIR`` (or the machine file's ``[machine] state``) each machine's kept
    data is put back from its state file once it is built and named (before it starts
    running), and the file is appended to ``states``.

    A machine runs on its own (:meth:`~focas_net.sim.Machine.start_scenario`) with
    ``--run`` (its file's ``[run]`` scenario, else the default one) or when its file has a
    ``[run]`` section; machine ``i`` gets the seed ``fleet_seed(seed, i)``, ``seed`` being
    ``--seed`` or the scenario's own."""
    from focas_net.sim import MachineError, MachineFileError, default_machine, load_machine
    from focas_net.sim.nc import RealTimeClock

    clock = RealTimeClock(getattr(args, "speed", 1.0))  # one machine time for the whole fleet
    machines: list[Machine] = []
    if args.machine is not None:
        try:  # a file that cannot be read is named by its option, as --tls-ca's is
            with open(args.machine, "rb"):
                pass
        except OSError as exc:
            raise ConfigError(f"--machine {args.machine}: {os_reason(exc)}") from None
    try:
        kept_in = state_folder_of(args)
    except MachineFileError as exc:
        raise ConfigError(str(exc)) from None
    for i in fleet_indices(args):
        if args.machine is not None:
            try:
                machine = load_machine(
                    args.machine, param_password=args.param_password, sim_clock=clock
                )
            except MachineFileError as exc:
                raise ConfigError(str(exc)) from None
            except OSError as exc:
                raise ConfigError(f"{args.machine}: {os_reason(exc)}") from None
        else:
            machine = default_machine(param_password=args.param_password, sim_clock=clock)
        if args.fleet > 1:
            try:
                machine.name = f"{machine.name}-{i + 1}"
            except ValueError as exc:  # the number makes the name too long
                raise ConfigError(f"--fleet {args.fleet}: {exc}") from None
        if args.no_control:
            machine.control_enabled = False
        try:
            machine = load_state(args, kept_in, machine, states if states is not None else [])
        except ValueError as exc:
            raise ConfigError(str(exc)) from None
        scenario = _scenario(args, machine, i)
        if scenario is not None:
            try:
                machine.start_scenario(scenario)
            except MachineError as exc:
                option = "--run" if getattr(args, "run", False) else f"{args.machine}: [run]"
                raise ConfigError(f"{option}: {machine.name}: {exc}") from None
        if args.read_only:
            machine.read_only = True
        machines.append(machine)
    return machines


#: An option of a running machine given to machines that do not run.
_NOT_RUNNING: Final = "the machines do not run (give --run, or a machine file with a [run] section)"


def _scenario(args: argparse.Namespace, machine: Machine, index: int) -> Scenario | None:
    """How machine ``index`` runs on its own (None: it does not)."""
    from focas_net.sim.nc import DEFAULT_SCENARIO, fleet_seed
    from focas_net.sim.nc.scenario import MAX_PARTS, MAX_SEED

    run = bool(getattr(args, "run", False))
    seed: int | None = getattr(args, "seed", None)
    parts: int | None = getattr(args, "run_parts", None)
    for option, value, high in (("--seed", seed, MAX_SEED), ("--run-parts", parts, MAX_PARTS)):
        if value is not None and value > high:  # as a machine file's [run] refuses it
            raise OptionRefused(option, f"must be 0..{high}, got {value}")
    downtime: float = getattr(args, "downtime", 1.0)
    base = machine.scenario
    if base is None:
        if not run:
            for option, value in (("--seed", seed), ("--run-parts", parts)):
                if value is not None:
                    raise OptionRefused(option, _NOT_RUNNING)
            if downtime != 1.0:
                raise OptionRefused("--downtime", _NOT_RUNNING)
            return None
        base = DEFAULT_SCENARIO
    fleet = base.seed if seed is None else seed
    return replace(
        base,
        seed=fleet_seed(fleet, index),
        parts=base.parts if parts is None else parts,
        pause_rate=base.pause_rate * downtime,
        tool_rate=base.tool_rate * downtime,
        alarm_rate=base.alarm_rate * downtime,
    )
