"""Building blocks of the payload codecs: one declaration serves encode and decode."""

from __future__ import annotations

import inspect
import struct
from collections.abc import Callable
from operator import attrgetter
from typing import Any, ClassVar, Final, Generic, Self, TypeVar

from ..errors import PayloadError

__all__ = ["I16", "INT_RANGES", "Codec", "FixedPayload", "field_error"]

T = TypeVar("T")

#: One signed 16-bit word (EW codes, counts).
I16: Final = struct.Struct("<h")
#: struct code -> (least, greatest) integer it carries.
INT_RANGES: Final[dict[str, tuple[int, int]]] = {
    "b": (-128, 127),
    "B": (0, 255),
    "h": (-32_768, 32_767),
    "H": (0, 65_535),
    "i": (-(2**31), 2**31 - 1),
    "I": (0, 2**32 - 1),
}


def field_error(fields: tuple[tuple[str, object, str], ...], exc: struct.error) -> str:
    """The message of a value that does not fit: the first ``(name, value, struct code)`` out
    of its range, in the field's own words (``slot 70000 is outside 0..255``)."""
    for name, value, code in fields:
        bounds = INT_RANGES.get(code)
        if bounds is None:
            continue
        if isinstance(value, bool) or not isinstance(value, int):
            return f"{name} must be an integer, got {value!r}"
        if not bounds[0] <= value <= bounds[1]:
            return f"{name} {value!r} is outside {bounds[0]}..{bounds[1]}"
    return f"a value does not fit its field: {exc}"


class Codec(Generic[T]):
    """A payload codec: ``encode(value) -> bytes`` and ``decode(bytes) -> value``.

    ``decode`` raises :class:`PayloadError` and nothing else on bytes that do not fit;
    ``encode`` raises :class:`ValueError` on a value that cannot be put on the wire.
    ``decode_bytes`` is ``decode`` for a payload of type ``bytes`` exactly (not a bytearray or
    a view), as the client's connection hands answers over: the same values and errors, and
    for a codec that remembers what it decoded, a payload seen before is answered by a dict
    look-up alone. It is ``decode`` unless given.
    """

    __slots__ = ("decode", "decode_bytes", "encode", "name")

    def __init__(
        self,
        name: str,
        encode: Callable[[T], bytes],
        decode: Callable[[bytes], T],
        decode_bytes: Callable[[bytes], T] | None = None,
    ) -> None:
        self.name = name
        self.encode = encode
        self.decode = decode
        self.decode_bytes = decode if decode_bytes is None else decode_bytes

    def __repr__(self) -> str:
        return f"Codec({self.name})"


class FixedPayload:
    """Base of payloads with a fixed ``struct`` layout.

    A subclass is a frozen, slotted dataclass whose fields are, in order, the fields of
    ``FORMAT``; declaring the two together gives both ``encode`` and ``decode``.
    """

    FORMAT: ClassVar[str]
    STRUCT: ClassVar[struct.Struct]
    _getter: ClassVar[Callable[[Any], tuple[Any, ...]]]

    def __init_subclass__(cls, **kwargs: Any) -> None:
        super().__init_subclass__(**kwargs)
        cls.STRUCT = struct.Struct(cls.FORMAT)
        names = [n for n in inspect.get_annotations(cls) if n.isidentifier()]
        names = [n for n in names if not n.isupper() and not n.startswith("_")]
        if len(names) == 1:
            single = attrgetter(names[0])
            cls._getter = staticmethod(lambda obj: (single(obj),))
        elif names:
            cls._getter = staticmethod(attrgetter(*names))

    def encode(self) -> bytes:
        try:
            return self.STRUCT.pack(*self._getter(self))  # type: ignore[call-arg]
        except struct.error as exc:
            raise ValueError(self._explain(exc)) from None

    def _explain(self, exc: struct.error) -> str:
        """Which field does not fit, and its range, in the field's own words (``count
        100000 is outside -32768..32767``): callers check their arguments in the user's terms
        first, so this names only what they did not check."""
        codes = [c for c in self.FORMAT if c.isalpha()]
        fields = [f for f in inspect.get_annotations(type(self)) if f.islower()]
        for field, code in zip(fields, codes, strict=False):
            value = getattr(self, field)
            bounds = INT_RANGES.get(code)
            if bounds is not None and not (
                isinstance(value, int)
                and not isinstance(value, bool)
                and bounds[0] <= value <= bounds[1]
            ):
                if not isinstance(value, int):
                    return f"{field} must be an integer, got {value!r}"
                return f"{field} {value!r} is outside {bounds[0]}..{bounds[1]}"
        return f"a value does not fit its field: {exc}"

    @classmethod
    def decode(cls, data: bytes) -> Self:
        st = cls.STRUCT
        if len(data) != st.size:
            # (the client's error names the call and the peer around it)
            raise PayloadError(f"{len(data)} bytes, expected {st.size}")
        return cls(*st.unpack(data))

    @classmethod
    def codec(cls) -> Codec[Self]:
        """This payload as a :class:`Codec`."""
        return Codec(cls.__name__, cls.encode, cls.decode)
