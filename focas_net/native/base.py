"""The errors of the native codec and the declarative base of its fixed records.

Every fixed-layout record of FANUC's FOCAS/2 Ethernet protocol is one frozen, slotted dataclass
deriving from :class:`NativeRecord`: its ``FORMAT`` (a big-endian :mod:`struct` format) and its
fields, declared together, give both ``encode`` and ``decode``. It is the packed protocol's
:class:`~focas_net.protocol._base.FixedPayload` with what the native records add:

* ``decode`` raises :class:`NativePayloadError` (the codec's own error) on a wrong size;
* ``TEXT`` names ``str`` fields carried as fixed-width latin-1 (``2s``, ``4s``...): encoding a
  text of another width is a :class:`ValueError`;
* ``PADDED`` names ``bytes`` fields carried NUL-padded (``36s``...): encoding pads a shorter
  value (a longer one is a :class:`ValueError`), decoding drops the trailing NULs, so the bytes
  of any record decode and encode back unchanged;
* ``WIRE`` gives the order of the fields on the wire when it differs from the order of the
  dataclass fields (kept for names that existed before, such as :class:`ScaledNumber`);
* ``decode_from`` reads one record at an offset, ``decode_many``/``encode_many`` a run of them.

:class:`RecordArray` is the base of answers that are a run of one fixed record.
"""

from __future__ import annotations

import inspect
import struct
from collections.abc import Callable, Iterable, Sequence
from operator import attrgetter
from typing import Any, ClassVar, Final, Generic, Self, TypeVar

from focas_net.errors import EW, FrameError, PayloadError, ProtocolError
from focas_net.protocol._base import INT_RANGES, FixedPayload

__all__ = [
    "NativeFrameError",
    "NativePayloadError",
    "NativeProtocolError",
    "NativeRecord",
    "RecordArray",
]


class NativeProtocolError(ProtocolError):
    """The peer sent bytes the native FOCAS/2 Ethernet protocol does not allow."""


class NativeFrameError(NativeProtocolError, FrameError):
    """Framing violation (bad magic, oversize length, broken block list): close the connection."""


class NativePayloadError(NativeProtocolError, PayloadError):
    """A block's arguments or data do not fit its command.

    On the server the block is answered with :attr:`ew` (the connection stays up).
    """

    def __init__(self, message: str, ew: int = EW.LENGTH) -> None:
        super().__init__(message)
        self.ew: int = ew


def _fields_of(cls: type) -> list[str]:
    """The dataclass fields of ``cls`` in declaration order (ClassVars are upper case)."""
    names = [n for n in inspect.get_annotations(cls) if n.isidentifier()]
    return [n for n in names if not n.isupper() and not n.startswith("_")]


def _text_to_wire(value: str, size: int, where: str) -> bytes:
    try:
        raw = value.encode("latin-1")
    except (UnicodeEncodeError, AttributeError):
        raise ValueError(f"{where} must be single-byte text, got {value!r}") from None
    if len(raw) != size:
        raise ValueError(f"{where} must be exactly {size} characters, got {value!r}")
    return raw


class NativeRecord(FixedPayload):
    """Base of the fixed, big-endian records of the native protocol (see the module doc)."""

    __slots__ = ()
    #: ``struct`` format, big-endian (``>``); one code per field.
    FORMAT: ClassVar[str] = ">"
    #: Bytes on the wire.
    SIZE: ClassVar[int] = 0
    #: ``str`` fields (fixed-width latin-1 text).
    TEXT: ClassVar[frozenset[str]] = frozenset()
    #: ``bytes`` fields padded with NULs (trailing NULs dropped on decode).
    PADDED: ClassVar[frozenset[str]] = frozenset()
    #: Field order on the wire, when it differs from the dataclass order.
    WIRE: ClassVar[tuple[str, ...]] = ()
    #: Exception ``decode`` raises (built with one message argument).
    ERROR: ClassVar[Callable[[str], ProtocolError]] = NativePayloadError
    #: What ``decode``'s refusals call the record, in words (nothing when empty).
    WHAT: ClassVar[str] = ""

    _wire_names: ClassVar[tuple[str, ...]]
    _text_slots: ClassVar[tuple[tuple[int, int], ...]]
    _padded_slots: ClassVar[tuple[tuple[int, int], ...]]
    _order: ClassVar[tuple[int, ...] | None]

    def __init_subclass__(cls, **kwargs: Any) -> None:
        super().__init_subclass__(**kwargs)
        if not cls.FORMAT.startswith(">"):
            raise TypeError(f"{cls.__name__}.FORMAT must be big-endian ('>')")
        cls.SIZE = cls.STRUCT.size
        fields = _fields_of(cls)
        wire = cls.WIRE or tuple(fields)
        if sorted(wire) != sorted(fields):
            raise TypeError(f"{cls.__name__}.WIRE must name every field once")
        codes = _codes(cls.FORMAT)
        if len(codes) != len(wire):
            raise TypeError(f"{cls.__name__}: {len(codes)} format codes for {len(wire)} fields")
        cls._wire_names = wire
        cls._getter = staticmethod(_getter(wire))
        widths = [
            (i, name, int(code[:-1] or 1))
            for i, (name, code) in enumerate(zip(wire, codes, strict=True))
        ]
        cls._text_slots = tuple((i, size) for i, name, size in widths if name in cls.TEXT)
        cls._padded_slots = tuple((i, size) for i, name, size in widths if name in cls.PADDED)
        order = tuple(wire.index(name) for name in fields)
        cls._order = None if order == tuple(range(len(order))) else order

    @classmethod
    def layout(cls) -> tuple[tuple[str, str], ...]:
        """``(field, struct code)`` of every field, in wire order (``("mantissa", "i")``...)."""
        return tuple(zip(cls._wire_names, _codes(cls.FORMAT), strict=True))

    # -- encode --------------------------------------------------------------------------------

    def _wire_values(self) -> tuple[Any, ...]:
        values = self._getter(self)  # type: ignore[call-arg]
        if self._text_slots or self._padded_slots:
            out = list(values)
            name = type(self).__name__
            for i, size in self._text_slots:
                out[i] = _text_to_wire(out[i], size, f"{name}.{self._wire_names[i]}")
            for i, size in self._padded_slots:
                if not isinstance(out[i], bytes) or len(out[i]) > size:
                    raise ValueError(
                        f"{name}.{self._wire_names[i]} must be at most {size} bytes, got {out[i]!r}"
                    )
            return tuple(out)
        return values

    def encode(self) -> bytes:
        """The bytes of this record."""
        try:
            return self.STRUCT.pack(*self._wire_values())
        except (struct.error, TypeError) as exc:
            raise ValueError(self._explain(exc)) from None

    def _explain(self, exc: Exception) -> str:
        name = type(self).__name__
        for field, code in zip(self._wire_names, _codes(self.FORMAT), strict=True):
            value = getattr(self, field)
            bounds = INT_RANGES.get(code)
            if bounds is not None and not (
                isinstance(value, int) and bounds[0] <= value <= bounds[1]
            ):
                return f"{name}.{field} = {value!r} does not fit ({bounds[0]}..{bounds[1]})"
        return f"{name}: {exc}"

    @classmethod
    def encode_many(cls, records: Iterable[Self]) -> bytes:
        """The bytes of ``records``, one after the other."""
        return b"".join(r.encode() for r in records)

    # -- decode --------------------------------------------------------------------------------

    @classmethod
    def _from_values(cls, values: tuple[Any, ...]) -> Self:
        if cls._text_slots or cls._padded_slots:
            out = list(values)
            for i, _ in cls._text_slots:
                out[i] = out[i].decode("latin-1")
            for i, _ in cls._padded_slots:
                out[i] = out[i].rstrip(b"\0")
            values = tuple(out)
        order = cls._order
        if order is not None:
            values = tuple(values[i] for i in order)
        return cls(*values)

    @classmethod
    def _named(cls, why: str) -> str:
        """``why`` a decode is refused, after :attr:`WHAT` when the record has one (a
        client's error names the call and the peer around it; a Python class name is never
        the user's word)."""
        return f"{cls.WHAT}: {why}" if cls.WHAT else why

    @classmethod
    def decode(cls, data: bytes | bytearray | memoryview) -> Self:
        """The record in ``data``, which must be exactly :attr:`SIZE` bytes."""
        if len(data) != cls.SIZE:
            raise cls.ERROR(cls._named(f"{len(data)} bytes, expected {cls.SIZE}"))
        return cls._from_values(cls.STRUCT.unpack(data))

    @classmethod
    def decode_from(cls, data: bytes | bytearray | memoryview, offset: int = 0) -> Self:
        """The record at ``offset`` of ``data`` (more bytes may follow)."""
        if offset < 0 or len(data) - offset < cls.SIZE:
            raise cls.ERROR(cls._named(f"{cls.SIZE} bytes needed at offset {offset}"))
        return cls._from_values(cls.STRUCT.unpack_from(data, offset))

    @classmethod
    def decode_many(cls, data: bytes | bytearray | memoryview) -> tuple[Self, ...]:
        """The records of ``data``, a whole number of them."""
        size = cls.SIZE
        if size == 0:
            if data:
                raise cls.ERROR(cls._named(f"expected no data, got {len(data)} bytes"))
            return ()
        if len(data) % size:
            raise cls.ERROR(cls._named(f"{len(data)} bytes is not a multiple of {size}"))
        make = cls._from_values
        return tuple(make(values) for values in cls.STRUCT.iter_unpack(data))


_NO_FIELDS: Final[tuple[Any, ...]] = ()


def _getter(names: Sequence[str]) -> Callable[[Any], tuple[Any, ...]]:
    if not names:
        return lambda obj: _NO_FIELDS
    if len(names) == 1:
        single = attrgetter(names[0])
        return lambda obj: (single(obj),)
    return attrgetter(*names)


def _codes(fmt: str) -> list[str]:
    """The codes of a struct format with their counts (``"2s"``, ``"i"``), one per field."""
    codes: list[str] = []
    count = ""
    for ch in fmt.lstrip("<>!=@"):
        if ch.isdigit():
            count += ch
        elif ch.isspace():
            continue
        elif ch in "sp":
            codes.append(count + ch)
            count = ""
        else:
            repeat = int(count or 1)
            codes.extend([ch] * repeat)
            count = ""
    return codes


R = TypeVar("R", bound=NativeRecord)


class RecordArray(Generic[R]):
    """Base of answers that are a run of one fixed record (``ITEM``), held in ``records``.

    A subclass is a frozen dataclass with the single field ``records: tuple[ITEM, ...]``.
    """

    __slots__ = ()
    ITEM: ClassVar[type[NativeRecord]]
    records: tuple[R, ...]

    def __init__(self, records: tuple[R, ...]) -> None:  # replaced by the dataclass
        raise NotImplementedError

    def encode(self) -> bytes:
        """The bytes of every record, in order."""
        return b"".join(r.encode() for r in self.records)

    @classmethod
    def decode(cls, data: bytes | bytearray | memoryview) -> Self:
        """The records of ``data`` (a whole number of ``ITEM`` records)."""
        return cls(cls.ITEM.decode_many(data))  # type: ignore[arg-type]

    def __len__(self) -> int:
        return len(self.records)


def check_multiple(data: bytes | bytearray | memoryview, size: int, what: str) -> None:
    """Raise :class:`NativePayloadError` (EW_LENGTH) unless ``data`` is whole ``size`` records."""
    if size <= 0 or len(data) % size:
        raise NativePayloadError(
            f"{what}: {len(data)} bytes is not a multiple of {size}", EW.LENGTH
        )
