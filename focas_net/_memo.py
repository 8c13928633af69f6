"""A bounded memo of pure results, shared by the native client and the native front end."""

from __future__ import annotations

from typing import Any

__all__ = ["Memo"]


class Memo(dict[Any, Any]):
    """A dict of pure results that empties itself when full.

    Its keys and values are immutable (bytes, frozen records, tuples of them), so a value handed
    out twice is safe to share. A poll that repeats the same call and gets the same answer then
    encodes and decodes nothing again. A dict, so that a look-up (``get``) is the dict's own.
    """

    __slots__ = ("_size",)

    def __init__(self, size: int) -> None:
        super().__init__()
        self._size = size

    def put(self, key: Any, value: Any) -> None:
        """Keep ``value`` under ``key``, after emptying the memo when it holds ``size`` entries."""
        if len(self) >= self._size:
            self.clear()
        self[key] = value
