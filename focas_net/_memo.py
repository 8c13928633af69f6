"""A bounded memo of pure results, shared by the native client and the native front end."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

__all__ = ["Memo", "Memoized"]


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


class Memoized(Memo):
    """A :class:`Memo` of ``compute(key)`` that fills itself: ``memo[key]`` is the value kept,
    or ``compute(key)`` kept now (what ``compute`` raises is raised, nothing kept). A hit is
    the dict's own look-up, no Python code: ``memo.__getitem__`` is the memoized function."""

    __slots__ = ("_compute",)

    def __init__(self, size: int, compute: Callable[[Any], Any]) -> None:
        super().__init__(size)
        self._compute = compute

    def __missing__(self, key: Any) -> Any:
        value = self._compute(key)
        self.put(key, value)
        return value
