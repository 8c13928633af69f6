"""A new user's pass over machine files, part programs and the examples (pass 11): each test
names a case that was wrong or unsettled, and the behaviour FANUC's practice asks for."""

from __future__ import annotations

import tomllib
from pathlib import Path

import pytest
from support import alarm_words, started_engine

from focas_net.sim import (
    LifeTool,
    Machine,
    MachineFileError,
    ToolGroup,
    ToolsSpec,
    load_machine,
    machine_from_dict,
)
from focas_net.sim.machinefile import state_folder
from focas_net.sim.nc import CycleState, ManualClock, NcSettings

ROOT = Path(__file__).resolve().parent.parent
NC = ROOT / "focas_net" / "sim" / "nc"


@pytest.mark.parametrize("module", sorted(p.name for p in NC.glob("*.py")), ids=str)
def test_nc_modules_are_short_and_in_the_architecture(module: str) -> None:
    """Each module of the NC package stays under 800 lines (the interpreter had 804: its
    settings and its actions are modules of their own) and is named in the architecture."""
    lines = (NC / module).read_text(encoding="utf-8").count("\n")
    assert lines <= 800, f"{module} has {lines} lines"
    if module != "__init__.py":
        assert module in (ROOT / "docs" / "architecture.md").read_text(encoding="utf-8")


# -- machine files ----------------------------------------------------------------------------

_HEAD = '[machine]\nname = "m"\naxes = ["X", "Y", "Z"]\n'


def _refusal(body: str) -> str:
    """The words a machine file of ``body`` (after a minimal [machine]) is refused with."""
    with pytest.raises(MachineFileError) as caught:
        machine_from_dict(tomllib.loads(_HEAD + body))
    return str(caught.value)


@pytest.mark.parametrize(
    ("panel", "words"),
    [
        ('mode = "EDIT"\nrun = 3', "panel.run: 3 (STRT) cannot be with mode EDIT"),
        ('mode = "JOG"\nrun = 3', "panel.run: 3 (STRT) cannot be with mode JOG"),
        ("mode = 3\nrun = 3", "panel.run: 3 (STRT) cannot be with mode EDIT"),
        ("emergency = true\nrun = 3", "panel.run: 3 (STRT) cannot be with emergency = true"),
        ("emergency = true\nrun = 2", "panel.run: 2 (HOLD) cannot be with emergency = true"),
    ],
)
def test_a_panel_a_cnc_cannot_be_in_is_refused_naming_the_key(panel: str, words: str) -> None:
    """A cycle runs (STRT) only in MEM, MDI or RMT, and an emergency stop resets the CNC: a
    [panel] with a run state against its mode or its emergency stop is no panel of a CNC."""
    assert words in _refusal(f"[panel]\n{panel}\n")


@pytest.mark.parametrize(
    "panel", ['mode = "MEM"\nrun = 3', 'mode = "MDI"\nrun = 3', 'mode = "RMT"\nrun = 3',
              'mode = "EDIT"\nrun = 2', 'mode = "JOG"\nrun = 1', "emergency = true\nrun = 0"]
)  # fmt: skip
def test_a_panel_a_cnc_can_be_in_loads(panel: str) -> None:
    machine = machine_from_dict(tomllib.loads(f"{_HEAD}[panel]\n{panel}\n"))
    assert machine.status().run == int(panel[-1])


def test_one_tool_twice_in_one_group_is_refused_naming_the_group_and_tool() -> None:
    body = "[[tools]]\n[[tools.group]]\nnumber = 4\nlife = 9\ntools = [1, 1]\n"
    assert "tools[0].group[0].tools[1]: T1 is in tool group 4 twice" in _refusal(body)


def test_one_tool_twice_in_one_group_is_refused_by_the_machine_too() -> None:
    groups = [ToolGroup(4, 9, tools=[LifeTool(1), LifeTool(1)])]
    with pytest.raises(ValueError, match="T1 is in tool group 4 twice"):
        Machine("m", axes=["X"], tools={1: ToolsSpec(groups=groups, ignore=100)})


# -- part programs ----------------------------------------------------------------------------


def test_of_two_one_shot_g_codes_in_a_block_the_last_is_valid() -> None:
    """FANUC's G code list: of several G codes of one group in a block the last is valid, and
    group 00 is no exception (no alarm): `G28 G4 P100` dwells 0.1 s, `G4 G28 X10.` returns."""
    engine, clock = started_engine("O1\nG28 G4 P100\nM30\n")
    clock.advance(0.05)
    assert (engine.state, alarm_words(engine)) == (CycleState.START, None)  # dwelling
    clock.advance(0.1)
    assert (engine.state, alarm_words(engine)) == (CycleState.RESET, None)
    engine, clock = started_engine("O1\nG0 X50.\nG4 G28 X10.\nM30\n")
    clock.advance(30)
    assert (engine.state, alarm_words(engine)) == (CycleState.RESET, None)
    assert engine.absolute_position()[0] == pytest.approx(0.0)


_LATHE = NcSettings.for_axes(("X", "Z"), lathe=True)


@pytest.mark.parametrize("dwell", ["G4 U1.", "G4 U1000", "G04 U1.0", "G4 X1.", "G4 P1000"])
def test_a_lathe_dwells_by_u_in_seconds(dwell: str) -> None:
    """FANUC's T series gives G4 its time in X, U (seconds) or P (ms): `G4 U1.` dwells 1 s."""
    engine, clock = started_engine(f"O1\n{dwell}\nM30\n", _LATHE)
    clock.advance(0.9)
    assert (engine.state, alarm_words(engine)) == (CycleState.START, None)
    clock.advance(0.2)
    assert (engine.state, alarm_words(engine)) == (CycleState.RESET, None)


@pytest.mark.parametrize(
    ("block", "settings", "words"),
    [
        ("G4 U1. P100", _LATHE, "PS5074 G4 U1. P100: a dwell takes its time in X, U or P"),
        ("G4 X1. U1.", _LATHE, "PS5074 G4 X1. U1.: a dwell takes its time in X, U or P"),
        ("G4 U-1.", _LATHE, "PS0006 G4 U-1."),
        ("G4 U1.", NcSettings(), "PS0009 address U (axes are XYZ)"),
    ],
)
def test_a_dwell_s_u_is_the_lathe_s_alone(block: str, settings: NcSettings, words: str) -> None:
    engine, clock = started_engine(f"O1\n{block}\nM30\n", settings)
    clock.advance(2)
    assert (alarm_words(engine) or "").startswith(words)


def test_a_lathe_machine_dwells_by_u() -> None:
    machine = machine_from_dict(
        tomllib.loads(
            '[machine]\nname = "l"\naxes = ["X", "Z"]\n[sysinfo]\nmt_type = " T"\n'
            '[[program]]\ntext = "O1\\nG4 U1.\\nM30"\n'
        ),
        sim_clock=(clock := ManualClock()),
    )
    machine.cycle_start()
    clock.advance(0.5)
    assert machine.status().run == 3
    clock.advance(1)
    assert (machine.status().run, machine.status().alarm) == (0, 0)


@pytest.mark.parametrize(
    ("body", "words"),
    [
        ("[run]\nphase = 1e400\n", "run.phase: must be a finite number, got 1e400"),
        ("[run]\nphase = 1e10\n", "run.phase: 1e10 is outside 0..31536000"),
        ("[run]\nphase = -1E-3\n", "run.phase: -1E-3 is outside 0..31536000"),
        (
            "[[tools]]\n[[tools.offset]]\nnumber = 1\nlength_wear = 1e400\n",
            "tools[0].offset[0].length_wear: must be a finite number of millimetres, got 1e400",
        ),
        (
            "[[tools]]\n[[tools.offset]]\nnumber = 1\nlength_wear = 1.000_1\n",
            "tools[0].offset[0].length_wear: 1.000_1 has more than 3 decimals",
        ),
    ],
)
def test_a_float_of_a_machine_file_is_named_as_typed(tmp_path: Path, body: str, words: str) -> None:
    """TOML reads 1e400 as inf: the refusal named `inf`, which the file does not hold."""
    file = tmp_path / "m.toml"
    file.write_text(_HEAD + body, encoding="utf-8")
    with pytest.raises(MachineFileError) as caught:
        load_machine(file)
    assert words in str(caught.value)


@pytest.mark.parametrize("block", ["G2 I5. F1000", "G91 G3 J-5. F1000", "G1 F1000\nG2 I5."])
def test_a_full_circle_with_no_end_point_is_cut(block: str) -> None:
    """FANUC: an arc whose end point is left out ends where it starts; with I, J or K it is
    a full circle (`G2 I5.`: 31.4 mm at 1000 mm/min, 1.9 s). The block moved nothing."""
    engine, clock = started_engine(f"O1\n{block}\nM30\n")
    clock.advance(1.5)
    assert (engine.state, alarm_words(engine)) == (CycleState.START, None)
    clock.advance(0.5)
    assert (engine.state, alarm_words(engine)) == (CycleState.RESET, None)
    assert engine.absolute_position() == pytest.approx((0.0, 0.0, 0.0))


def test_an_arc_by_r_with_no_end_point_moves_nothing() -> None:
    """FANUC: R with the end point at the start is an arc of 0 degrees: no motion."""
    engine, clock = started_engine("O1\nG2 R5. F1000\nM30\n")
    clock.advance(0.1)
    assert (engine.state, alarm_words(engine)) == (CycleState.RESET, None)


@pytest.mark.parametrize(
    ("goto", "words"),
    [
        ("GOTO 0", "PS0128 GOTO 0: a sequence number is 1..99999"),
        ("GOTO 100000", "PS0128 GOTO 100000: a sequence number is 1..99999"),
        ("GOTO -1", "PS0128 GOTO -1: a sequence number is 1..99999"),
        ("GOTO #1", "PS0128 GOTO a vacant variable: a sequence number is 1..99999"),
        ("GOTO 7", "PS0128 GOTO 7: no block N7 in O0001"),
    ],
)
def test_a_goto_past_the_sequence_numbers_says_so(goto: str, words: str) -> None:
    """`GOTO 100000` said `no block N100000`, as if the program could hold one."""
    engine, _ = started_engine(f"O1\n{goto}\nM30\n")
    assert alarm_words(engine) == words


@pytest.mark.parametrize(
    ("blocks", "end"),
    [
        ("G0 X10. Z10.\nG28 U0 W0", (0.0, 0.0)),  # every lathe program's return
        ("G0 X10. Z10.\nG0 U10. W-5.", (20.0, 5.0)),
        ("G0 X10. Z10.\nG1 U-2. W-2. F1000", (8.0, 8.0)),
        ("G0 X20. Z0\nG2 U2. W-5. R5. F1000", (22.0, -5.0)),
        ("G0 X20. Z0\nX30. W-1.", (30.0, -1.0)),
        ("G0 X20. Z0\nU1000", (21.0, 0.0)),  # no point: least increments
    ],
)
def test_a_lathe_moves_by_u_and_w(blocks: str, end: tuple[float, float]) -> None:
    """FANUC's T series (G code system A) moves X by U and Z by W, from where the axis is;
    `G28 U0 W0` raised PS0009 (address U)."""
    engine, clock = started_engine(f"O1\n{blocks}\nM30\n", _LATHE)
    clock.advance(30)
    assert (engine.state, alarm_words(engine)) == (CycleState.RESET, None)
    assert engine.absolute_position() == pytest.approx(end)


@pytest.mark.parametrize(
    ("block", "words"),
    [
        ("G0 X10. U5.", "PS5074 X10. U5.: X given twice in one block (U moves X)"),
        ("G4 W1.", "PS0009 G4 with W1.: a dwell moves no axis"),
        ("G0 V1.", "PS0009 address V (axes are XZ)"),
    ],
)
def test_a_lathe_s_u_and_w_refusals(block: str, words: str) -> None:
    engine, clock = started_engine(f"O1\n{block}\nM30\n", _LATHE)
    clock.advance(2)
    assert (alarm_words(engine) or "").startswith(words)


def test_a_lathe_cuts_arcs_in_the_zx_plane_from_power_on() -> None:
    """The T series powers on in G18 (ZX): `G2 X.. Z.. R..` raised PS0021 (plane G17)."""
    engine, clock = started_engine("O1\nG0 X20. Z0\nG3 X20. Z-10. K-5. F1000\nM30\n", _LATHE)
    clock.advance(10)
    assert (engine.state, alarm_words(engine)) == (CycleState.RESET, None)
    assert engine.modal_groups()[2] == 18


_TOOLS = "[[tools]]\n"


@pytest.mark.parametrize(
    ("body", "words"),
    [
        (
            "[[tools.offset]]\nnumber = 1\nx_wear = 1.0\n",
            "tools[0].offset[0].x_wear: tool offset 1: x_wear is a lathe's offset",
        ),
        ("work = { G54 = [1, 2] }\n", "tools[0].work.G54: work offset G54: 2 values for 3 axes"),
        (
            "work = { G54 = [100000, 2, 3] }\n",
            "tools[0].work.G54: work offset G54: 100000.000 mm is beyond 99999.999 mm",
        ),
        (
            "[[tools.group]]\nnumber = 1\nlife = 10\ncount = 11\ntools = [1]\n",
            "tools[0].group[0]: tool group 1: count 11 is outside 0..10 (the life)",
        ),
        (
            "[[tools.group]]\nnumber = 1\nlife = 9\ntools = []\n",
            "tools[0].group[0]: tool group 1 has 0 tools",
        ),
        (
            "[[tools.group]]\nnumber = 1\nlife = 9\ntools = [1]\n"
            "[[tools.group]]\nnumber = 1\nlife = 9\ntools = [2]\n",
            "tools[0].group[1]: tool group 1 is declared twice",
        ),
        (
            "max_groups = 4\n[[tools.group]]\nnumber = 5\nlife = 9\ntools = [1]\n",
            "tools[0].group[0]: tool group 5 is outside 1..4",
        ),
        (
            '[[tools.group]]\nnumber = 1\nlife = 5000\ntype = "time"\ntools = [1]\n',
            "tools[0].group[0]: tool group 1: life 5000 is outside 1..4300",
        ),
    ],
)
def test_a_tools_table_the_machine_refuses_is_refused_naming_the_key(body: str, words: str) -> None:
    """The machine's own checks of offsets, work offsets and groups were told with no key
    (`m.toml: tool group 1: count 11 ...`): each names where in the file it is."""
    assert f"<machine file>: {words}" in _refusal(_TOOLS + body)


def test_a_lathe_path_s_tools_are_checked_against_its_own_axes_and_kind() -> None:
    head = '[machine]\nname = "l"\n[sysinfo]\nmt_type = "TT"\n[[path]]\naxes = ["X1", "Z1"]\n'
    body = "[[tools]]\nwork = { G54 = [1, 2, 3] }\n"
    with pytest.raises(MachineFileError) as caught:
        machine_from_dict(tomllib.loads(head + body))
    assert "tools[0].work.G54: work offset G54: 3 values for 2 axes" in str(caught.value)


@pytest.mark.parametrize(
    "value", ["length_wear = 1000.", "length_wear = .5", "length_wear = -.5", "x = [1., 2]"]
)
def test_a_point_written_as_a_part_program_writes_it_gets_a_hint(
    tmp_path: Path, value: str
) -> None:
    """`1000.` is a number in a part program, not in TOML: the error said only `Expected
    newline or end of document after a statement`."""
    file = tmp_path / "m.toml"
    file.write_text(f"{_HEAD}[[tools]]\n[[tools.offset]]\nnumber = 1\n{value}\n", "utf-8")
    with pytest.raises(MachineFileError) as caught:
        load_machine(file)
    assert "not valid TOML: " in str(caught.value)
    assert "(TOML writes a decimal with a digit on each side of its point" in str(caught.value)


def test_another_toml_error_gets_no_point_hint(tmp_path: Path) -> None:
    file = tmp_path / "m.toml"
    file.write_text(f"{_HEAD}[run\n", "utf-8")
    with pytest.raises(MachineFileError) as caught:
        load_machine(file)
    assert "TOML writes" not in str(caught.value)


@pytest.mark.parametrize(
    ("expression", "value"),
    [("BIN[16]", 10.0), ("BCD[10]", 16.0), ("BIN[BCD[12345678]]", 12345678.0), ("BCD[0]", 0.0)],
)
def test_bin_and_bcd_convert_as_fanuc_s_macro_functions(expression: str, value: float) -> None:
    """BIN (BCD to binary) and BCD (binary to BCD) are functions of FANUC's custom macro B;
    `#1 = BIN[16]` raised PS0114 (expected a value)."""
    engine, _ = started_engine(f"O1\n#1 = {expression}\nM0\nM30\n")
    assert (engine.state, alarm_words(engine)) == (CycleState.STOP, None)
    assert engine.interpreter.read(1) == value


@pytest.mark.parametrize(
    ("expression", "words"),
    [
        ("BIN[10]", "PS0119 BIN[10]: 10 (0xA) is no BCD value"),
        ("BIN[-16]", "PS0119 BIN[-16]: 0..2576980377 (BCD 0..99999999)"),
        ("BCD[100000000]", "PS0119 BCD[100000000]: 0..99999999"),
        ("BCD[1.5]", "PS0119 BCD[1.5]: 0..99999999"),
    ],
)
def test_bin_and_bcd_refuse_what_they_cannot_convert(expression: str, words: str) -> None:
    engine, _ = started_engine(f"O1\n#1 = {expression}\nM30\n")
    assert alarm_words(engine) == words


@pytest.mark.parametrize("block", ["POPEN", "DPRNT[X#5001[44]]", "BPRNT[#100[3]]", "PCLOS"])
def test_external_data_output_says_it_is_not_modelled(block: str) -> None:
    """`DPRNT[...]` raised `PS0005 D has no value`, read as an address D."""
    engine, _ = started_engine(f"O1\n{block}\nM30\n")
    assert alarm_words(engine) == (
        f"PS0114 {block[:5]}: external data output (POPEN, BPRNT, DPRNT, PCLOS) is not modelled"
    )


@pytest.mark.parametrize(
    ("block", "words"),
    [
        ("G90 X50. Z-20. F100", "PS0010 G90: on a lathe the outer and inner diameter cutting"),
        ("G91 G0 X1.", "PS0010 G91: no code of a lathe's G code system A"),
        ("G94 X50. Z-2. F100", "PS0010 G94: on a lathe the end face turning cycle"),
    ],
)
def test_a_lathe_refuses_the_milling_meaning_of_its_own_codes(block: str, words: str) -> None:
    """On FANUC's T series G90 and G94 are cutting cycles (not modelled): a lathe's `G90 X50.
    Z-20. F100` ran as absolute mode and a move."""
    engine, _ = started_engine(f"O1\n{block}\nM30\n", _LATHE)
    assert (alarm_words(engine) or "").startswith(words)


def test_a_lathe_feeds_per_minute_with_g98() -> None:
    engine, clock = started_engine("O1\nG98 G1 Z-10. F600\nM30\n", _LATHE)
    clock.advance(1.5)
    assert (engine.state, alarm_words(engine)) == (CycleState.RESET, None)


def test_a_real_parameter_with_too_many_decimals_says_which_key_sets_them() -> None:
    """It said `1000.5 does not have 0 decimals or fewer`."""
    body = '[parameters.1420]\ntype = "real"\naxis = true\nvalue = [1000.5, 2, 3]\n'
    assert (
        "parameters.1420.value[0]: 1000.5 has more than 0 decimals (the item's decimals key)"
        in _refusal(body)
    )


def test_serve_s_first_read_of_a_machine_file_gives_the_point_hint_too(tmp_path: Path) -> None:
    """`serve --machine` reads the file's state folder first: its TOML error had no hint."""
    file = tmp_path / "m.toml"
    file.write_text(f"{_HEAD}[run]\nphase = 1.\n", "utf-8")
    with pytest.raises(MachineFileError) as caught:
        state_folder(file)
    assert "(TOML writes a decimal with a digit on each side of its point" in str(caught.value)
