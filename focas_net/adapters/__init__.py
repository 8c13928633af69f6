"""The two protocol adapters of the simulated machine, pure and synchronous.

:class:`PackedAdapter` answers the packed protocol (``docs/protocol.md``) and
:class:`NativeAdapter` FANUC's native FOCAS/2 protocol (``docs/native-protocol.md``), both from
one protocol-neutral :class:`focas_net.sim.Machine`. Each imports the machine and its own codec
only; the listeners (:mod:`focas_net.server`, :mod:`focas_net.native.server`) move the frames.
"""

from .native import ITEM_TYPES, ITEM_TYPES_30I, NativeAdapter, macro_from_double
from .packed import PackedAdapter

__all__ = ["ITEM_TYPES", "ITEM_TYPES_30I", "NativeAdapter", "PackedAdapter", "macro_from_double"]
