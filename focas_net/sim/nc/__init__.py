"""Part programs and their execution in time, for the simulated machine (standard library
only, pure and synchronous, no protocol).

Modules: :mod:`.program` (parsing, the program store), :mod:`.macro` (custom macro B
expressions and the variable interface), :mod:`.interpreter` (blocks to actions),
:mod:`.motion` (segments), :mod:`.engine` (actions in time), :mod:`.clock`, :mod:`.alarms`,
:mod:`.scenario` (a machine at work on its own: seeded pauses, tool changes and alarms; the
loads of cutting).

Wiring into a machine
---------------------
Build one :class:`Engine` per machine with a shared clock (``RealTimeClock(speed)``, or a
:class:`ManualClock` in tests), its :class:`NcSettings` from the machine's parameters (rapid
rates 1420, stroke limits 1320/1321, reference 1240), a :class:`ProgramStore` and an object
implementing :class:`NcVariables` (``read_variable``/``write_variable`` over the machine's
#500-#999 and system variables, raising :class:`VariableRefused` with 115 or 116). Then:

- programs: ``store.directory()``, ``store.text(n)``, ``store.store(text)``,
  ``store.delete(n)``, ``store.select(n)`` (``select_program(n)``: a program search, which
  also sets the sequence number to 0); refusals are :class:`ProgramError` with a
  ``reason`` (and FANUC's PS number in ``alarm``) for the front ends to map to EW codes;
- control: ``cycle_start()`` (raises :class:`NcStateError`), ``feed_hold()`` (also pauses
  a dwell or an M function's wait), ``reset()``, ``alarm_stop(alarm)`` (emergency stop or
  any alarm of the machine's own),
  ``set_feed_override``/``set_rapid_override``/``set_spindle_override``,
  ``set_single_block``, ``set_optional_stop``, ``set_block_delete``;
- reads (each advances lazily to the clock's time, O(1) when nothing is due): ``state``
  (:class:`CycleState`), ``motion`` (:class:`MotionKind`), ``absolute_position()``,
  ``machine_position()``, ``relative_position()``, ``distance_to_go()`` (mm),
  ``actual_feed`` (mm/min), ``actual_spindle_speed``, ``program_number``,
  ``sequence_number``, ``modal_groups()`` (#4001-#4030), ``alarm``, ``parts_count``,
  ``parts_total``, ``operating_time``, ``cutting_time``, ``cycle_time`` (s);
- ``take_events()``: alarms, parts, tool changes and program ends with their machine time,
  for the alarm history and the part-count parameters.

What the interpreter supports
-----------------------------
- Program text: O-number (O1-O9999 by default) and name, ``%`` tape marks, EOB as new line
  or ``;``, ``N`` sequence numbers (N1-N99999), comments in parentheses (a tab in one
  disregarded, as FANUC's ISO code disregards HT), block delete ``/``
  (with the switch), lower case read as upper case. Axis words (and the R, I, J, K of arcs, X of a
  dwell) without a decimal point are in least input increments: 0.001 mm (G21), 0.0001 inch
  (G20), at most 9 digits of them (999999.999 mm; more raises PS0003, written or a macro
  variable's value); F and S are taken as written. Positions, feeds and offsets are kept in mm.
- G0 (non-linear positioning, each axis at its rapid rate times the rapid override), G1, G2,
  G3 with I/J/K or R (negative R: more than 180 degrees) in G17/G18/G19, helical with the
  third axis, full circles with I/J/K (the end point left out too: ``G2 I5.``); G4 (P in
  ms, X in s or increments, on a lathe U as X; in a block of its own: another axis word
  raises PS0009, two time words PS5074); G20/G21; on a lathe (``NcSettings.lathe``) U and
  W moving X and Z incrementally (G code system A) and G18 at power-on; G28 through the
  intermediate point to the reference position; G53; G54-G59 and the external offset
  (#5201-#5326); G90/G91; G43/G44/G49 with H (tool length on Z); the cancel and default
  codes G15 G22 G23 G40 G40.1 G50 G50.1 G61-G64 G67 G69 G80 G94 G97 G98 G99 are accepted
  as modal states without effect. F (clamped to the maximum cutting feed), S, T, (M and T
  codes of up to 8 digits, S of up to 5: FANUC's defaults of parameters 3030-3032;
  more raises PS0003), M6 (tool change time), M3/M4/M5, M8/M9, M0, M1 (optional stop
  switch), M2/M30 (part count, rewind, spindle and coolant off), M98 P L (also P with the
  count in front of four digits: P of up to 8 digits, L of up to 4; more raises PS0003),
  M99 (P n: return to sequence n; in a main program: back to its head), any other M code
  as an M function taking its time.
- Custom macro B: ``#i = expr``, locals #1-#33, commons #100-#199 (vacant after a reset and
  a program's end; the interpreter's own only where :class:`NcVariables` refuses them with
  PS0115), #500-#999 and other system variables through :class:`NcVariables`,
  #4001-#4030, #4107-#4120, #5001+, #5021+, #5041+ read from the interpreter, ``#3000 = n
  (MESSAGE)`` raising MC alarm 3000+n (0..200); vacant ``#0`` as FANUC defines it;
  ``+ - * / OR XOR AND MOD``, ``EQ NE GT GE LT LE``, brackets (5 levels), ``SIN COS TAN
  ASIN ACOS ATAN (ATAN[a]/[b] or ATAN[a,b]) SQRT ABS ROUND BIN BCD FIX FUP LN EXP`` in
  degrees (BIN and BCD on 0..99999999 in BCD, PS0119 beyond); ``GOTO n``, ``IF [c] GOTO
  n``, ``IF [c] THEN #i = e``, ``WHILE [c] DO m ... END m`` and ``DO m`` (m = 1..3, nested
  up to 3).
- Alarms (block's program and last sequence number): PS0003, 0004, 0005, 0006, 0007, 0009,
  0010 improper G code, 0011 no feed, 0020 radius tolerance (also R less than half the
  chord: inferred), 0021, 0022, 0030, 0076, 0077, 0078, 0111, 0112, 0114, 0115, 0116,
  0118, 0119, 0124, 0126, 0127, 0128, 5074 (an address but G given twice in a block; M too:
  one M code a block); OT0500/OT0501 when a motion would pass a stroke limit:
  the axis stops on the limit. MC numbering of ``#3000`` and PS0009 for an axis the machine
  lacks are inferred.

What it does not support
------------------------
Cutter compensation G41/G42, canned cycles G73-G89, G92 and G52 coordinate settings, G10,
G65/G66 macro calls and their argument locals, G95 feed per revolution, G96 constant surface
speed, polar and scaling and rotation, inch machines (positions are reported in mm whatever
G20 says), acceleration (feeds and rapids are reached at once), several M codes in a block
(FANUC's option; PS5074 here), the ``/1``..``/9`` block delete switches (all are one
switch), program protection of O8000/O9000, chamfering and corner R (``,C`` ``,R``:
PS0009 naming the word) and external data output (``POPEN`` ``BPRNT`` ``DPRNT`` ``PCLOS``:
PS0114 naming the command, *inferred*). The others raise PS0010 (G codes) or PS0114 (syntax).
"""

from .alarms import ALARM_MESSAGES, AlarmKind, NcAlarm, ProgramError, ProgramErrorReason
from .clock import ManualClock, RealTimeClock, SimClock, check_sim_clock
from .engine import CycleState, Engine, EngineEvent, MotionKind, NcStateError
from .macro import MACRO_FUNCTIONS, MemoryVariables, NcVariables, VariableRefused
from .modal import (
    FANUC_GROUPS,
    ModalAddress,
    ModalG,
    ModalState,
    ProgramPointer,
    g_code_text,
    modal_state,
    program_pointer,
)
from .motion import ArcMove, LinearMove, Motion, RapidMove
from .program import Block, Program, ProgramInfo, ProgramStore, Word, no_program, parse_program
from .scenario import (
    DEFAULT_SCENARIO,
    SCENARIO_ALARMS,
    Scenario,
    ScenarioAlarm,
    ScenarioEvent,
    Schedule,
    fleet_seed,
)
from .settings import DEFAULT_MODAL, G_CODE_GROUPS, NcSettings

__all__ = [
    "ALARM_MESSAGES",
    "DEFAULT_MODAL",
    "DEFAULT_SCENARIO",
    "FANUC_GROUPS",
    "G_CODE_GROUPS",
    "MACRO_FUNCTIONS",
    "SCENARIO_ALARMS",
    "AlarmKind",
    "ArcMove",
    "Block",
    "CycleState",
    "Engine",
    "EngineEvent",
    "LinearMove",
    "ManualClock",
    "MemoryVariables",
    "ModalAddress",
    "ModalG",
    "ModalState",
    "Motion",
    "MotionKind",
    "NcAlarm",
    "NcSettings",
    "NcStateError",
    "NcVariables",
    "Program",
    "ProgramError",
    "ProgramErrorReason",
    "ProgramInfo",
    "ProgramPointer",
    "ProgramStore",
    "RapidMove",
    "RealTimeClock",
    "Scenario",
    "ScenarioAlarm",
    "ScenarioEvent",
    "Schedule",
    "SimClock",
    "VariableRefused",
    "Word",
    "check_sim_clock",
    "fleet_seed",
    "g_code_text",
    "modal_state",
    "no_program",
    "parse_program",
    "program_pointer",
]
