"""What the native front end needs of a :class:`~focas_net.sim.Machine` beyond its typed
operations: the sorted numbers of its parameters and diagnostics (for range reads) and making a
macro variable vacant (a NaN written with 0xA8).

These read the machine's own tables; they change nothing but what the typed operations would
change, and keep the machine's ``version`` counter honest.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from focas_net.protocol import EW

if TYPE_CHECKING:
    from focas_net.sim import Machine

__all__ = ["check_macro_writable", "clear_macro", "diag_numbers", "param_numbers"]


def param_numbers(machine: Machine) -> tuple[int, ...]:
    """The numbers of every parameter the machine has, ascending."""
    return tuple(sorted(machine._params))


def diag_numbers(machine: Machine) -> tuple[int, ...]:
    """The numbers of every diagnostic the machine has, ascending."""
    return tuple(sorted(machine._diags))


def check_macro_writable(machine: Machine, number: int) -> None:
    """Raise the :class:`~focas_net.sim.MachineError` a write of macro ``number`` gets before
    its value is looked at: EW_PROT (read-only machine), EW_NUMBER, EW_PROT (read-only
    variable) -- the order of ``Machine.write_macro``."""
    from focas_net.sim import MachineError

    if machine.read_only:
        raise MachineError(EW.PROT, "read-only machine")
    writable = machine.macro_writable(number)
    if writable is None:
        raise MachineError(EW.NUMBER, f"no macro variable #{number}")
    if not writable:
        raise MachineError(EW.PROT, f"macro variable #{number} is read-only")


def clear_macro(machine: Machine, number: int) -> None:
    """Make macro ``number`` vacant, with the checks of :func:`check_macro_writable`."""
    check_macro_writable(machine, number)
    if machine._macros.pop(number, None) is not None:
        machine._changed()
