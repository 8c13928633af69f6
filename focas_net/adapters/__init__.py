"""The two protocol adapters of the simulated machine, pure and synchronous.

:class:`PackedAdapter` answers the packed protocol (``docs/protocol.md``) and
:class:`NativeAdapter` FANUC's native FOCAS/2 protocol (``docs/native-protocol.md``), both from
one protocol-neutral :class:`focas_net.sim.Machine`. Each imports the machine and its own codec
only; the listeners (:mod:`focas_net.server`, :mod:`focas_net.native.server`) move the frames.
"""

from .native import (
    NativeAdapter,
    ProgramTransfer,
    command_set_of,
    macro_from_double,
    native_diag_type,
    native_param_type,
)
from .packed import PackedAdapter

__all__ = [
    "NativeAdapter",
    "PackedAdapter",
    "ProgramTransfer",
    "command_set_of",
    "macro_from_double",
    "native_diag_type",
    "native_param_type",
]
