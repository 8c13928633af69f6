"""Read a CNC through FANUC's own FOCAS library (libfwlib32), as a ctypes program.

    python examples/fwlib_client.py --library /opt/fwlib/libfwlib32.so.1 \\
        --host 127.0.0.1 --port 8193

This is the program a FOCAS user writes, pointed at ``focas-net serve``: start the library,
open a handle with ``cnc_allclibhndl3`` to the server's host and port, read the identity,
the status, one
macro variable, a PMC range and the dynamic data, free the handle, stop the library. The
library is not part of focas_net: ``--library`` (or the environment variable
``FOCAS_NET_FWLIB``) names it.

The structures follow FANUC's documented layouts for the Linux library: 4-byte packing and
FOCAS ``long`` fields of 32 bits. A call that does not answer EW_OK (0) ends the program with
its EW code as the exit status (a negative code as 256 + code, so EW_SOCKET -16 exits 240).
"""

from __future__ import annotations

import argparse
import ctypes
import os
import sys
from typing import ClassVar

#: Every axis, as FOCAS calls take it.
ALL_AXES = -1
#: ``pmc_rdpmcrng`` address types (``adr_type``) by letter.
PMC_AREAS = {"G": 0, "F": 1, "Y": 2, "X": 3, "A": 4, "R": 5, "T": 6, "K": 7, "C": 8, "D": 9}
#: Bytes the PMC data union of IODBPMC holds (five doubles).
PMC_DATA = 40

short = ctypes.c_short
ushort = ctypes.c_ushort
#: FOCAS ``long``: 32 bits in the Linux library.
long32 = ctypes.c_int32


class ODBSYS(ctypes.Structure):
    """cnc_sysinfo: the CNC's type, series, version and number of axes (ASCII fields)."""

    _pack_ = 4
    _fields_: ClassVar = [
        ("addinfo", short),
        ("max_axis", short),
        ("cnc_type", ctypes.c_char * 2),
        ("mt_type", ctypes.c_char * 2),
        ("series", ctypes.c_char * 4),
        ("version", ctypes.c_char * 4),
        ("axes", ctypes.c_char * 2),
    ]


class ODBST(ctypes.Structure):
    """cnc_statinfo: the CNC status."""

    _pack_ = 4
    _fields_: ClassVar = [
        ("hdck", short),
        ("tmmode", short),
        ("aut", short),
        ("run", short),
        ("motion", short),
        ("mstb", short),
        ("emergency", short),
        ("alarm", short),
        ("edit", short),
    ]


class ODBM(ctypes.Structure):
    """cnc_rdmacro: one macro variable, ``mcr_val`` with ``dec_val`` decimals."""

    _pack_ = 4
    _fields_: ClassVar = [
        ("datano", short),
        ("dummy", short),
        ("mcr_val", long32),
        ("dec_val", short),
    ]


class PmcData(ctypes.Union):
    """The data of IODBPMC: bytes, words or longs, as many as the length passed allows."""

    _pack_ = 4
    _fields_: ClassVar = [
        ("cdata", ctypes.c_ubyte * PMC_DATA),
        ("idata", short * (PMC_DATA // 2)),
        ("ldata", long32 * (PMC_DATA // 4)),
    ]


class IODBPMC(ctypes.Structure):
    """pmc_rdpmcrng: a PMC range, its address type, data type and inclusive addresses."""

    _pack_ = 4
    _fields_: ClassVar = [
        ("type_a", short),
        ("type_d", short),
        ("datano_s", ushort),
        ("datano_e", ushort),
        ("u", PmcData),
    ]


class ODBDY2Head(ctypes.Structure):
    """cnc_rddynamic2: the head of ODBDY2, before its four position arrays."""

    _pack_ = 4
    _fields_: ClassVar = [
        ("dummy", short),
        ("axis", short),
        ("alarm", long32),
        ("prgnum", long32),
        ("prgmnum", long32),
        ("seqnum", long32),
        ("actf", long32),
        ("acts", long32),
    ]


def odbdy2(max_axis: int) -> type[ctypes.Structure]:
    """ODBDY2 with ``max_axis`` slots per position array.

    The header sizes the arrays with its ``MAX_AXIS``, but the library fills them with a
    stride of the CNC's own maximum number of axes (``ODBSYS.max_axis``), so the structure is
    declared for that CNC.
    """
    slots = long32 * max_axis
    positions = type(
        "ODBDY2Positions",
        (ctypes.Structure,),
        {
            "_pack_": 4,
            "_fields_": [
                ("absolute", slots),
                ("machine", slots),
                ("relative", slots),
                ("distance", slots),
            ],
        },
    )
    return type(
        "ODBDY2",
        (ctypes.Structure,),
        {"_pack_": 4, "_fields_": [("head", ODBDY2Head), ("pos", positions)]},
    )


class FocasFailure(Exception):
    """A library call that did not answer EW_OK."""

    def __init__(self, function: str, ew: int, what: str = "") -> None:
        super().__init__(f"{function}{f' of {what}' if what else ''} returned EW {ew}")
        self.function = function
        self.ew = ew


class Fwlib:
    """The few functions of FANUC's library this program calls, with their C signatures."""

    def __init__(self, path: str) -> None:
        lib = ctypes.cdll.LoadLibrary(path)
        handle_p = ctypes.POINTER(ushort)
        signatures: dict[str, list[type]] = {
            "cnc_startupprocess": [long32, ctypes.c_char_p],
            "cnc_exitprocess": [],
            "cnc_allclibhndl3": [ctypes.c_char_p, ushort, long32, handle_p],
            "cnc_freelibhndl": [ushort],
            "cnc_sysinfo": [ushort, ctypes.POINTER(ODBSYS)],
            "cnc_statinfo": [ushort, ctypes.POINTER(ODBST)],
            "cnc_rdmacro": [ushort, short, short, ctypes.POINTER(ODBM)],
            "pmc_rdpmcrng": [
                ushort,
                short,
                short,
                ushort,
                ushort,
                ushort,
                ctypes.POINTER(IODBPMC),
            ],
            "cnc_rddynamic2": [ushort, short, short, ctypes.c_void_p],
        }
        for name, argtypes in signatures.items():
            function = getattr(lib, name)
            function.argtypes = argtypes
            function.restype = short
        self._lib = lib

    def raw(self, name: str, *args: object) -> int:
        """``name(*args)``; its EW code."""
        return int(getattr(self._lib, name)(*args))

    def call(self, name: str, *args: object, what: str = "") -> None:
        """``name(*args)``; raises :class:`FocasFailure` (naming ``what`` it asked for, when
        given) unless it answers EW_OK."""
        ew = self.raw(name, *args)
        if ew != 0:
            raise FocasFailure(name, ew, what)


def decimal_text(mantissa: int, decimals: int) -> str:
    """A macro value as the CNC shows it: ``mantissa`` with ``decimals`` digits after the point
    (-1 decimals: vacant)."""
    if decimals < 0:
        return "<vacant>"
    if decimals == 0:
        return str(mantissa)
    sign = "-" if mantissa < 0 else ""
    digits = str(abs(mantissa)).rjust(decimals + 1, "0")
    return f"{sign}{digits[:-decimals]}.{digits[-decimals:]}"


def read_cnc(lib: Fwlib, host: str, port: int, timeout: int, macro: int, pmc: str) -> None:
    """Open a handle to ``host:port``, print what it reads, free it."""
    area, first, count = parse_pmc(pmc)
    handle = ushort()
    lib.call("cnc_allclibhndl3", host.encode(), port, timeout, ctypes.byref(handle))
    try:
        read_handle(lib, handle, host, port, macro, (area, first, count))
    except FocasFailure:
        lib.raw("cnc_freelibhndl", handle)  # the first failure is the one to report
        raise
    lib.call("cnc_freelibhndl", handle)


def read_handle(
    lib: Fwlib, handle: ushort, host: str, port: int, macro: int, pmc: tuple[str, int, int]
) -> None:
    """Print the status, the macro variable, the PMC range and the dynamic data."""
    area, first, count = pmc
    print(f"handle {handle.value} to {host}:{port}")
    info = ODBSYS()
    lib.call("cnc_sysinfo", handle, ctypes.byref(info))
    axes = int(info.axes.decode("ascii").strip() or "0")
    print(
        f"cnc: type {info.cnc_type.decode('ascii').strip()}{info.mt_type.decode('ascii').strip()}"
        f" series {info.series.decode('ascii')} version {info.version.decode('ascii')}, "
        f"{axes} axes"
    )
    st = ODBST()
    lib.call("cnc_statinfo", handle, ctypes.byref(st))
    print(
        f"status: mode={st.aut} run={st.run} motion={st.motion} mstb={st.mstb} "
        f"emergency={st.emergency} alarm={st.alarm} edit={st.edit}"
    )
    m = ODBM()
    lib.call("cnc_rdmacro", handle, macro, ctypes.sizeof(ODBM), ctypes.byref(m))
    print(f"macro #{m.datano}: {decimal_text(m.mcr_val, m.dec_val)}")
    p = IODBPMC()
    last = first + count - 1
    length = 8 + count
    span = f"{area}{first}..{area}{last}"
    lib.call(
        "pmc_rdpmcrng", handle, PMC_AREAS[area], 0, first, last, length, ctypes.byref(p), what=span
    )
    data = bytes(p.u.cdata[:count])
    print(f"pmc {span}: {data.hex(' ')}")
    dy = odbdy2(info.max_axis)()
    lib.call("cnc_rddynamic2", handle, ALL_AXES, ctypes.sizeof(dy), ctypes.byref(dy))
    h = dy.head
    print(
        f"dynamic: alarm={h.alarm} program=O{h.prgnum} main=O{h.prgmnum} "
        f"sequence=N{h.seqnum} feed={h.actf} spindle={h.acts}"
    )
    for name in ("absolute", "machine", "relative", "distance"):
        values = list(getattr(dy.pos, name))[:axes]
        print(f"{name}: {' '.join(str(v) for v in values)}")


def parse_pmc(text: str) -> tuple[str, int, int]:
    """``D0:4`` (area letter, first byte address, byte count) as its three parts."""
    try:
        head, _, count_text = text.partition(":")
        area, first = head[0].upper(), int(head[1:])
        count = int(count_text or "1")
    except (IndexError, ValueError):
        raise ValueError(f"--pmc {text!r}: expected AREA FIRST[:COUNT], e.g. D0:4") from None
    if area not in PMC_AREAS:
        raise ValueError(f"--pmc {text!r}: area {area!r} is not one of {''.join(PMC_AREAS)}")
    if not 1 <= count <= PMC_DATA or not 0 <= first <= 0xFFFF - count:
        raise ValueError(f"--pmc {text!r}: 1..{PMC_DATA} bytes from an address 0..65535")
    return area, first, count


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument(
        "--library",
        default=os.environ.get("FOCAS_NET_FWLIB"),
        help="path of FANUC's libfwlib32 (default: $FOCAS_NET_FWLIB)",
    )
    parser.add_argument("--host", default="127.0.0.1")
    parser.add_argument("--port", type=int, default=8193)
    parser.add_argument("--timeout", type=int, default=3, help="seconds per call")
    parser.add_argument("--macro", type=int, default=500, help="macro variable to read")
    parser.add_argument("--pmc", default="D0:4", help="PMC bytes to read: AREA FIRST[:COUNT]")
    parser.add_argument("--log", help="file for the library's own log of every byte")
    args = parser.parse_args()
    if not args.library:
        parser.error("name FANUC's library with --library or FOCAS_NET_FWLIB")
    try:
        parse_pmc(args.pmc)
    except ValueError as exc:
        parser.error(str(exc))
    try:
        lib = Fwlib(args.library)
    except (OSError, AttributeError) as exc:
        print(f"fwlib_client: cannot load {args.library!r}: {exc}", file=sys.stderr)
        return 1
    lib.call("cnc_startupprocess", 3 if args.log else 0, (args.log or "/dev/null").encode())
    try:
        read_cnc(lib, args.host, args.port, args.timeout, args.macro, args.pmc)
    except FocasFailure as exc:
        print(f"fwlib_client: {exc}", file=sys.stderr)
        return exc.ew & 0xFF or 1
    finally:
        lib.raw("cnc_exitprocess")
    return 0


if __name__ == "__main__":
    sys.exit(main())
