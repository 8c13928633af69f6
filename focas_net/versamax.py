"""GE's VersaMax I/O module configuration record: what a station holds for each rack and slot.

The station sits behind a Genius Network Interface Unit (GE Fanuc GFK-1535, chapter 5). This is
the record's own format, held in the station's memory; it is neither protocol's framing. The
packed protocol carries it in pieces in its Read Configuration datagrams
(:mod:`focas_net.protocol.versamax`, ``docs/protocol.md`` section 5), the simulated station keeps
it (:mod:`focas_net.sim`) and the client reassembles and decodes it.

Module record layout; board ids are sent most-significant byte first, every other word
little-endian, pad bytes are not sent::

    rack/slot header, 26 bytes
      >H secondary board id, >H primary board id, 4s label,
      <H additional-data length (without pad), 14 unused bytes, <H additional-data length padded
    additional data
      24 bytes of fixed I/O fields:
        >H secondary id, >H primary id, <H offset to module-specific data,
        <H counts of %I, %Q, %AI, %AQ reference descriptions, <H module setup word,
        <H reserved, <H module-specific data length, 2 reserved words
      8 bytes per reference description: <B sequence, <B type, <H offset, <H bytes,
        <H offset of its defaults
      <H input segment mode, <H output segment mode
      default input bytes, default output bytes (present when setup bit 0 is set)
      module-specific data

Offsets inside the additional data count from its first byte.
"""

from __future__ import annotations

import enum
import struct
from collections.abc import Iterable
from dataclasses import dataclass
from typing import Final, Self

from focas_net.errors import PayloadError

__all__ = [
    "BoardId",
    "IOModuleRecord",
    "ModuleType",
    "RefDesc",
    "RefType",
]

_IDS: Final = struct.Struct(">HH")
_HEAD_REST: Final = struct.Struct("<4sH14xH")
_FIXED_REST: Final = struct.Struct("<8H4x")
_REF: Final = struct.Struct("<BBHHH")
_MODES: Final = struct.Struct("<HH")
_HEADER_SIZE: Final = 26
_FIXED_SIZE: Final = 24


class ModuleType(enum.IntEnum):
    """Board id bits 12-11."""

    DISCRETE_DC = 0
    DISCRETE_AC = 1
    ANALOG = 2
    RESERVED = 3


class RefType(enum.IntEnum):
    """Reference types of a reference description."""

    I = 16  # noqa: E741 - the PLC's own name for discrete inputs
    Q = 18
    AI = 10
    AQ = 12

    @property
    def is_input(self) -> bool:
        return self in (RefType.I, RefType.AI)


@dataclass(frozen=True, slots=True)
class BoardId:
    """A 16-bit VersaMax board id and its fields.

    Bits 15-13 ``100``; 12-11 module type; 10 analog current (1) / voltage (0); 9-8 diagnostic
    bits; 7-4 output pairs (discrete) or channels (analog); 3-0 input pairs or channels.
    """

    value: int

    @classmethod
    def make(
        cls,
        module_type: ModuleType,
        *,
        inputs: int = 0,
        outputs: int = 0,
        current: bool = False,
        diagnostics: int = 0,
    ) -> Self:
        """Build an id from point counts (discrete: even counts, two points a pair)."""
        div = 1 if module_type == ModuleType.ANALOG else 2
        if inputs % div or outputs % div:
            raise ValueError("discrete points come in pairs")
        ins, outs = inputs // div, outputs // div
        if not (0 <= ins <= 15 and 0 <= outs <= 15 and 0 <= diagnostics <= 3):
            raise ValueError("board id field out of range")
        return cls(
            0x8000 | module_type << 11 | int(current) << 10 | diagnostics << 8 | outs << 4 | ins
        )

    @property
    def valid(self) -> bool:
        """Bits 15-13 are ``100``."""
        return self.value >> 13 == 0b100

    @property
    def module_type(self) -> ModuleType:
        return ModuleType((self.value >> 11) & 3)

    @property
    def analog_current(self) -> bool:
        return bool(self.value >> 10 & 1)

    @property
    def diagnostics(self) -> int:
        return (self.value >> 8) & 3

    @property
    def _points(self) -> int:
        return 1 if self.module_type == ModuleType.ANALOG else 2

    @property
    def outputs(self) -> int:
        """Output points (discrete) or channels (analog)."""
        return ((self.value >> 4) & 15) * self._points

    @property
    def inputs(self) -> int:
        """Input points (discrete) or channels (analog)."""
        return (self.value & 15) * self._points


@dataclass(frozen=True, slots=True)
class RefDesc:
    """A reference description: where the module's data lives in the PLC's memory."""

    sequence: int
    ref_type: int
    offset: int
    byte_length: int
    defaults_offset: int


@dataclass(frozen=True, slots=True)
class IOModuleRecord:
    """The configuration record of an I/O module."""

    secondary_id: BoardId
    primary_id: BoardId
    label: str
    references: tuple[RefDesc, ...] = ()
    setup: int = 0
    input_segment_mode: int = 0
    output_segment_mode: int = 0
    default_inputs: bytes = b""
    default_outputs: bytes = b""
    module_data: bytes = b""

    @classmethod
    def build(
        cls,
        primary_id: BoardId,
        secondary_id: BoardId,
        label: str,
        refs: Iterable[tuple[RefType, int, int]],
        *,
        setup: int = 0,
        default_inputs: bytes = b"",
        default_outputs: bytes = b"",
        module_data: bytes = b"",
        input_segment_mode: int = 0,
        output_segment_mode: int = 0,
    ) -> Self:
        """A record from ``(type, offset, byte length)`` references; sequence numbers and
        offsets of defaults are computed (defaults are laid out when ``setup`` bit 0 is set)."""
        refs = list(refs)
        region = _FIXED_SIZE + 8 * len(refs) + 4
        in_at, out_at = region, region + sum(n for t, _, n in refs if RefType(t).is_input)
        descs = []
        for seq, (kind, offset, length) in enumerate(refs, 1):
            at = 0
            if setup & 1:
                if RefType(kind).is_input:
                    at, in_at = in_at, in_at + length
                else:
                    at, out_at = out_at, out_at + length
            descs.append(RefDesc(seq, int(kind), offset, length, at))
        return cls(
            secondary_id,
            primary_id,
            label,
            tuple(descs),
            setup,
            input_segment_mode,
            output_segment_mode,
            default_inputs,
            default_outputs,
            module_data,
        )

    # -- derived views -------------------------------------------------------------------
    @property
    def inputs(self) -> int:
        """Input points or channels of both boards."""
        return self.primary_id.inputs + self.secondary_id.inputs

    @property
    def outputs(self) -> int:
        """Output points or channels of both boards."""
        return self.primary_id.outputs + self.secondary_id.outputs

    def reference(self, ref_type: RefType) -> RefDesc | None:
        """The first reference description of ``ref_type``, if any."""
        return next((r for r in self.references if r.ref_type == ref_type), None)

    def _defaults_sizes(self) -> tuple[int, int]:
        if not self.setup & 1:
            return 0, 0
        ins = sum(r.byte_length for r in self.references if r.ref_type in _INPUT_TYPES)
        outs = sum(r.byte_length for r in self.references if r.ref_type not in _INPUT_TYPES)
        return ins, outs

    # -- codec ---------------------------------------------------------------------------
    def encode(self) -> bytes:
        ins, outs = self._defaults_sizes()
        if (len(self.default_inputs), len(self.default_outputs)) != (ins, outs):
            raise ValueError(
                f"defaults must be {ins} input and {outs} output bytes "
                "(the byte lengths of the references when setup bit 0 is set, else none)"
            )
        counts = [sum(r.ref_type == t for r in self.references) for t in _COUNT_ORDER]
        md_offset = _FIXED_SIZE + 8 * len(self.references) + 4 + ins + outs
        additional_len = md_offset + len(self.module_data)
        label = self.label.encode("latin-1")
        if len(label) != 4:
            raise ValueError(f"label must be 4 characters: {self.label!r}")
        unknown = [r.ref_type for r in self.references if r.ref_type not in _KNOWN_TYPES]
        if unknown:
            raise ValueError(f"unknown reference type(s) {unknown}: expected 16, 18, 10 or 12")
        try:
            ids = _IDS.pack(self.secondary_id.value, self.primary_id.value)
            parts = [
                ids,
                _HEAD_REST.pack(label, additional_len, -additional_len % 26 + additional_len),
                ids,
                _FIXED_REST.pack(md_offset, *counts, self.setup, 0, len(self.module_data)),
            ]
            parts += [_REF.pack(*_ref_fields(r)) for r in self.references]
            parts.append(_MODES.pack(self.input_segment_mode, self.output_segment_mode))
        except struct.error as exc:
            raise ValueError(f"VersaMax record: {exc}") from None
        parts += [self.default_inputs, self.default_outputs, self.module_data]
        return b"".join(parts)

    @classmethod
    def decode(cls, data: bytes) -> Self:
        if len(data) < _HEADER_SIZE + _FIXED_SIZE:
            raise PayloadError(f"VersaMax record of {len(data)} bytes is too short")
        sec, prim = _IDS.unpack_from(data, 0)
        label, additional_len, _padded = _HEAD_REST.unpack_from(data, 4)
        if len(data) != _HEADER_SIZE + additional_len:
            raise PayloadError(
                f"VersaMax record: additional data length {additional_len} does not match "
                f"the {len(data) - _HEADER_SIZE} bytes carried"
            )
        add = data[_HEADER_SIZE:]
        md_offset, n_i, n_q, n_ai, n_aq, setup, _res, md_len = _FIXED_REST.unpack_from(add, 4)
        n_refs = n_i + n_q + n_ai + n_aq
        pos = _FIXED_SIZE + 8 * n_refs
        if pos + 4 > len(add):
            raise PayloadError("VersaMax record: reference descriptions run past the record")
        refs = tuple(RefDesc(*_REF.unpack_from(add, _FIXED_SIZE + 8 * i)) for i in range(n_refs))
        in_mode, out_mode = _MODES.unpack_from(add, pos)
        record = cls(
            BoardId(sec), BoardId(prim), label.decode("latin-1"), refs, setup, in_mode, out_mode
        )
        ins, outs = record._defaults_sizes()
        pos += 4
        if pos + ins + outs > len(add) or md_offset + md_len > len(add) or md_offset < pos:
            raise PayloadError("VersaMax record: defaults or module data run past the record")
        return cls(
            record.secondary_id,
            record.primary_id,
            record.label,
            refs,
            setup,
            in_mode,
            out_mode,
            add[pos : pos + ins],
            add[pos + ins : pos + ins + outs],
            add[md_offset : md_offset + md_len],
        )


_INPUT_TYPES: Final = frozenset({RefType.I.value, RefType.AI.value})
_COUNT_ORDER: Final = (RefType.I, RefType.Q, RefType.AI, RefType.AQ)
_KNOWN_TYPES: Final = frozenset(t.value for t in RefType)


def _ref_fields(r: RefDesc) -> tuple[int, int, int, int, int]:
    return (r.sequence, r.ref_type, r.offset, r.byte_length, r.defaults_offset)
