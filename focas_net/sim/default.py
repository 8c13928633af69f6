"""The built-in default machine: a three-axis milling control of the FANUC 0i-F class.

It holds everything ``docs/protocol.md`` section 7 promises (tests may rely on that part) and
more, so that it reads like a real control. Values are in least input increments (0.001 mm).

Parameters (number: type, axis or not, range, meaning); a bit parameter holds 0..255, bits #7..#0
(:class:`~focas_net.sim.ParamKind`)::

    20    byte  -      0..35              I/O channel
    1001  bit   -      full               bit parameter (INM: inch machine)
    1005  bit   axis   full               bit parameter (ZRN, HJZ, ...)
    1006  bit   axis   full               bit parameter (ROT, DIA, ZMI, ...)
    1020  byte  axis   65..90             program axis name ('X', 'Y', 'Z')
    1320  i32   axis   -999999999..999999999  stored stroke limit 1, positive side
    1321  i32   axis   -999999999..999999999  stored stroke limit 1, negative side
    1410  i32   -      0..999999999       dry run rate
    1420  i32   axis   0..999999999       rapid traverse rate
    1422  i32   -      0..999999999       maximum cutting feedrate
    1815  bit   axis   full               bit parameter (APC, APZ, OPT, ...)
    1825  i16   axis   1..32767           servo loop gain
    1826  i32   axis   0..99999999        in-position width
    1828  i32   axis   0..99999999        positional deviation limit in movement
    3216  i16   -      0..9999            increment of automatic sequence numbers
    3401  bit   -      full               bit parameter (DPI: decimal point input)
    6711  i32   -      0..999999999       parts count
    6712  i32   -      0..999999999       total parts
    6713  i32   -      0..999999999       parts required
    8130  byte  -      1..8               number of controlled axes

Diagnostics: 0 (bit, status bits), 300 (i32 axis, position error), 301 (i32 axis, machine
position error), 308 (byte axis, servo motor temperature C), 309 (byte axis, pulse coder
temperature C), 403 (byte, spindle motor temperature C), 410 (i16, spindle load %).

Macro variables: #0 (read-only, always vacant); #1..#33 local, #100..#199 and #500..#999 common,
all writable and vacant at start; read-only system variables: #4001..#4030 modal G codes of
the last block read, #4102..#4130 its B D E F H M N O S T codes, #5001..#5003 block end
position, #5021..#5023 machine coordinates (EW_PROT on write).

PMC: X 128 and F 768 bytes (write-protected for pmc_wrpmcrng), Y 128, G 768, R 8000, D 10000,
K 100, A 250, T 500, C 400; no E area.

Macro variables #3901 (parts count, parameter 6711) and #3902 (total parts, 6712) are
writable; #5041..#5043 (current position, work coordinates) read-only.

Programs: the demo program :data:`DEMO_PROGRAM`, O0001, is the main program: a tool change,
the spindle at 3000 min^-1 and a 80 x 60 mm contour with an arc at F1200, about 25 s of
machine time per part; cycle start runs it once, M30 counts a part.

Tools: offsets 1 and 2 hold lengths and radii (64 offsets, memory C); tool life groups 1 (T1,
then T11: 500 cycles) and 2 (T2: 60 minutes of cutting); the work offsets are 0.

VersaMax rack 0: slot 1 the GNIU (IC200GBI001), slot 3 the IC200MDD844; every other slot empty.
"""

from __future__ import annotations

import struct
from collections.abc import Iterable
from decimal import Decimal
from typing import Final

from focas_net.versamax import BoardId, IOModuleRecord, RefType

from ._identity import CLASS_MAX_AXES
from ._tools import LifeTool, ToolGroup, ToolsSpec
from .machine import (
    DEFAULT_HISTORY_CAPACITY,
    Clock,
    DataItem,
    Identity,
    Machine,
    MacroRange,
    MotionData,
    Panel,
    ParamKind,
    PmcAreaSpec,
    utc_now,
)
from .nc import SimClock

__all__ = ["DEFAULT_NAME", "DEMO_PROGRAM", "default_machine", "gniu_record", "mdd844_record"]

#: The name of the built-in machine (used in the server's ready line).
DEFAULT_NAME: Final = "focas-sim-0i"

#: The built-in machine's main program.
DEMO_PROGRAM: Final = """O0001 (DEMO CONTOUR)
N10 G21 G17 G40 G49 G80 G90
N20 G54 G0 X0 Y0 Z50.
N30 T1 M6
N40 S3000 M3
N50 G0 Z5. M8
N60 G1 Z-2. F300
N70 X80. F1200
N80 Y40.
N90 G3 X60. Y60. R20.
N100 G1 X0
N110 Y0
N120 G0 Z50. M9
N130 M5
N140 M30
"""

_STROKE: Final = 999_999_999
_BIT: Final = ParamKind.BIT
_GNIU_DATA: Final = struct.Struct("<BBHHHH")  # bus address, baud code, %I, %Q, %AI, %AQ bytes


def mdd844_record() -> IOModuleRecord:
    """IC200MDD844: 16 outputs on the primary board, 16 inputs on the secondary, defaults
    defined and fault reporting on; the 76-byte record of GFK-1535's example."""
    return IOModuleRecord.build(
        BoardId(0x8080),
        BoardId(0x8008),
        "D844",
        [(RefType.I, 17, 2), (RefType.Q, 8, 2)],
        setup=0b11,
        default_inputs=b"\x00\x00",
        default_outputs=b"\x00\x00",
        module_data=b"\x00\x00",
    )


def gniu_record(
    *,
    bus_address: int = 1,
    inputs: int = 2,
    outputs: int = 2,
    analog_in: int = 0,
    analog_out: int = 0,
) -> IOModuleRecord:
    """IC200GBI001, the Genius Network Interface Unit in slot 1: no I/O references of its own;
    its module data carries its Genius bus address, the baud-rate code (0 = 153.6 kbaud
    standard) and the station's %I, %Q, %AI and %AQ byte lengths."""
    return IOModuleRecord.build(
        BoardId(0x8000),
        BoardId(0x8000),
        "GBI1",
        [],
        module_data=_GNIU_DATA.pack(bus_address, 0, inputs, outputs, analog_in, analog_out),
    )


def _params(n: int) -> list[DataItem]:
    names = [ord(c) for c in "XYZABCUVW"[:n]] if n <= 9 else [88] * n
    return [
        DataItem(20, 1, False, 0, 35, [4], "I/O channel"),
        DataItem(1001, 1, False, None, None, [0], "INM", _BIT),
        DataItem(1005, 1, True, None, None, [0], "ZRN HJZ", _BIT),
        DataItem(1006, 1, True, None, None, [0], "ROT DIA ZMI", _BIT),
        DataItem(1020, 1, True, 65, 90, names, "program axis name"),
        DataItem(1320, 4, True, -_STROKE, _STROKE, [_STROKE], "stroke limit +"),
        DataItem(1321, 4, True, -_STROKE, _STROKE, [-_STROKE], "stroke limit -"),
        DataItem(1410, 4, False, 0, _STROKE, [5000], "dry run rate"),
        DataItem(1420, 4, True, 0, _STROKE, [24000], "rapid traverse rate"),
        DataItem(1422, 4, False, 0, _STROKE, [10000], "maximum cutting feedrate"),
        DataItem(1815, 1, True, None, None, [0b0011_0000], "APC APZ", _BIT),
        DataItem(1825, 2, True, 1, 32767, [3000], "servo loop gain"),
        DataItem(1826, 4, True, 0, 99_999_999, [20], "in-position width"),
        DataItem(1828, 4, True, 0, 99_999_999, [7000], "deviation limit in movement"),
        DataItem(3216, 2, False, 0, 9999, [10], "sequence number increment"),
        DataItem(3401, 1, False, None, None, [1], "DPI", _BIT),
        DataItem(6711, 4, False, 0, _STROKE, [0], "parts count"),
        DataItem(6712, 4, False, 0, _STROKE, [0], "total parts"),
        DataItem(6713, 4, False, 0, _STROKE, [0], "parts required"),
        DataItem(8130, 1, False, 1, 8, [n], "controlled axes"),
    ]


def _diags() -> list[DataItem]:
    return [
        DataItem(0, 1, False, None, None, [0], "status", _BIT),
        DataItem(300, 4, True, None, None, [0], "position error"),
        DataItem(301, 4, True, None, None, [0], "machine position error"),
        DataItem(308, 1, True, 0, 127, [31], "servo motor temperature"),
        DataItem(309, 1, True, 0, 127, [29], "pulse coder temperature"),
        DataItem(403, 1, False, 0, 127, [33], "spindle motor temperature"),
        DataItem(410, 2, False, 0, 9999, [0], "spindle load"),
    ]


#: Modal G codes at power-on, group -> (digits, decimals): G00 G17 G90 G22 G94 G21 G40 G49 G80
#: G98 G50 G67 G97 G54 G64 G69 G15 G40.1 G25 G160 G13.1 G50.1.
_MODAL_G: Final[dict[int, tuple[int, int]]] = {
    1: (0, 0), 2: (17, 0), 3: (90, 0), 4: (22, 0), 5: (94, 0), 6: (21, 0), 7: (40, 0),
    8: (49, 0), 9: (80, 0), 10: (98, 0), 11: (50, 0), 12: (67, 0), 13: (97, 0), 14: (54, 0),
    15: (64, 0), 16: (69, 0), 17: (15, 0), 18: (401, 1), 19: (25, 0), 20: (160, 0),
    21: (131, 1), 22: (501, 1),
}  # fmt: skip


def _decimal(digits: int, decimals: int) -> Decimal:
    """``digits`` with ``decimals`` decimal places (``(0, 3)`` is ``0.000``)."""
    return Decimal(f"{digits}E-{decimals}")


def _macros() -> tuple[list[MacroRange], dict[int, Decimal]]:
    ranges = [
        MacroRange(0, 0, writable=False),
        MacroRange(1, 33),
        MacroRange(100, 199),
        MacroRange(500, 999),
        MacroRange(3901, 3902),
        MacroRange(4001, 4030, writable=False),
        MacroRange(4102, 4130, writable=False),
        MacroRange(5001, 5003, writable=False),
        MacroRange(5021, 5023, writable=False),
        MacroRange(5041, 5043, writable=False),
    ]
    values = {4000 + group: _decimal(*v) for group, v in _MODAL_G.items()}
    values |= {
        4107: Decimal(0),  # D
        4109: Decimal(0),  # F
        4111: Decimal(0),  # H
        4113: Decimal(0),  # M
        4114: Decimal(0),  # N
        4115: Decimal(1),  # O
        4119: Decimal(0),  # S
        4120: Decimal(0),  # T
    }
    values |= {n: _decimal(0, 3) for n in (5001, 5002, 5003, 5021, 5022, 5023, 5041, 5042, 5043)}
    return ranges, values


def _pmc() -> list[PmcAreaSpec]:
    return [
        PmcAreaSpec("X", 128, write_protected=True),
        PmcAreaSpec("Y", 128),
        PmcAreaSpec("F", 768, write_protected=True),
        PmcAreaSpec("G", 768),
        PmcAreaSpec("R", 8000),
        PmcAreaSpec("D", 10000),
        PmcAreaSpec("K", 100),
        PmcAreaSpec("A", 250),
        PmcAreaSpec("T", 500),
        PmcAreaSpec("C", 400),
    ]


def default_machine(
    name: str = DEFAULT_NAME,
    param_password: str | bytes | None = None,
    *,
    clock: Clock = utc_now,
    control_enabled: bool = True,
    read_only: bool = False,
    history_capacity: int = DEFAULT_HISTORY_CAPACITY,
    sim_clock: SimClock | None = None,
    programs: Iterable[str] = (DEMO_PROGRAM,),
) -> Machine:
    """A fresh default machine (each call returns independent state). ``sim_clock`` drives
    the execution of its programs (a :class:`~focas_net.sim.nc.ManualClock` in tests);
    ``programs`` replace the demo program (the first is the main program)."""
    axes = ("X", "Y", "Z")
    ranges, values = _macros()
    return Machine(
        name,
        axes=axes,
        identity=Identity(2, CLASS_MAX_AXES["0i-F"], " 0", " M", "D4F1", "32.0", "03"),
        params=_params(len(axes)),
        diags=_diags(),
        macro_ranges=ranges,
        macro_values=values,
        pmc=_pmc(),
        panel=Panel(mode=1, pwe=0, emergency=0),
        param_password=param_password,
        station={(0, 1): gniu_record(), (0, 3): mdd844_record()},
        motion=MotionData(
            [0, 0, 0], [0, 0, 0], [0, 0, 0], [0, 0, 0], program_main=1, program_running=1
        ),
        history_capacity=history_capacity,
        clock=clock,
        control_enabled=control_enabled,
        read_only=read_only,
        programs=programs,
        sim_clock=sim_clock,
        tools={1: _tools()},
    )


def _tools() -> ToolsSpec:
    """Tool offsets 1 and 2 (lengths and radii of the demo's T1 and a spare), and two tool
    life groups: T1 then T11 counted by cycles, T2 by minutes of cutting."""
    return ToolsSpec(
        offsets=64,
        offset_values={
            (1, "radius_geometry"): 5000,
            (1, "length_geometry"): 125_000,
            (1, "length_wear"): -15,
            (2, "radius_geometry"): 3000,
            (2, "length_geometry"): 98_500,
        },
        groups=(
            ToolGroup(1, 500, "count", 0, [LifeTool(1, 1, 1), LifeTool(11, 11, 11)]),
            ToolGroup(2, 60, "time", 0, [LifeTool(2, 2, 2)]),
        ),
    )
