"""The two protocol adapters of the simulated machine, pure and synchronous.

:class:`PackedAdapter` answers the packed protocol (``docs/protocol.md``) and
:class:`NativeAdapter` FANUC's native FOCAS/2 protocol (``docs/native-protocol.md``), both from
one protocol-neutral :class:`focas_net.sim.Machine`. Each imports the machine and its own codec
only, and both keep the answers of reads and turn refusals into EW codes the same way
(:mod:`._common`); the listeners (:mod:`focas_net.server`) move the frames.

Modules: :mod:`.packed`; :mod:`.native` (the native adapter's answer loop, open and close) and
its handlers by area, :mod:`._native_cnc`, :mod:`._native_data` and :mod:`._native_programs`.
"""

from ._native_data import macro_from_double, native_diag_type, native_param_type
from ._native_programs import ProgramTransfer
from .native import PATH_INDEPENDENT, NativeAdapter, command_set_of
from .packed import PackedAdapter

__all__ = [
    "PATH_INDEPENDENT",
    "NativeAdapter",
    "PackedAdapter",
    "ProgramTransfer",
    "command_set_of",
    "macro_from_double",
    "native_diag_type",
    "native_param_type",
]
