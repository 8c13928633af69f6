"""Machine files: the example loads; every kind of bad file names the file and the key."""

from __future__ import annotations

from datetime import UTC, datetime
from decimal import Decimal
from pathlib import Path

import pytest

from focas_net.errors import EW
from focas_net.sim import (
    DataItem,
    Identity,
    Machine,
    MachineError,
    MachineFileError,
    ParamKind,
    default_machine,
    load_machine,
)
from focas_net.sim.default import gniu_record, mdd844_record
from focas_net.versamax import IOModuleRecord

EXAMPLE = Path(__file__).resolve().parent.parent / "examples" / "machine.toml"

MINIMAL = """
[machine]
name = "tiny"
axes = ["X", "Z"]
"""


def write(tmp_path: Path, text: str) -> Path:
    path = tmp_path / "machine.toml"
    path.write_text(text, encoding="utf-8")
    return path


def test_example_loads() -> None:
    m = load_machine(EXAMPLE)
    assert m.name == "vmc-850-b"
    assert m.axes == ["X", "Y", "Z", "B"]
    assert m.identity() == Identity(2, 32, " 0", " M", "D4F1", "32.0", "04")
    assert m.has_password and m.control_enabled and not m.read_only
    assert m.history_capacity == 250
    assert m.status().aut == 1
    assert [m.read_param(1020, a) for a in (1, 2, 3, 4)] == [88, 89, 90, 66]
    assert [m.read_param(1815, a) for a in (1, 2, 3, 4)] == [0x30] * 4
    item = m.param_item(3216)
    assert item is not None and item.width == 2
    assert m.read_diag(308, 3) == 38
    value = m.read_macro(500)
    assert value == Decimal("25.4") and str(value) == "25.4"
    assert m.read_macro(100) is None
    assert m.macro_writable(4001) is False
    assert m.read_pmc("X", 8, 1) == b"\x10"
    assert m.read_pmc("R", 99, 6) == b"\x00\x01\x02\x03\x04\x00"
    assert m.pmc_area("X") == (128, True)
    assert m.pmc_area("E") is None
    assert m.module_record(0, 1) == gniu_record()
    assert m.module_record(0, 3) == mdd844_record()
    record = m.module_record(0, 4)
    assert record is not None and record.label == "MDL6"
    assert IOModuleRecord.decode(m.config_record(0, 4)) == record
    assert m.motion.program_main == 1234
    assert m.motion.machine[2] == -150000


def test_example_password_gates_writes() -> None:
    m = load_machine(EXAMPLE)
    s = m.new_session()
    m.set_panel(0, 1, 0)
    with pytest.raises(MachineError) as exc:
        m.write_param(s, 6711, 0, 1)
    assert exc.value.ew == EW.PASSWD
    m.unlock(s, "5810")
    m.write_param(s, 6711, 0, 1)
    assert m.read_param(6711, 0) == 1


def test_overrides_and_clock() -> None:
    def fixed() -> datetime:
        return datetime(2024, 1, 2, 3, 4, 5, tzinfo=UTC)

    m = load_machine(EXAMPLE, clock=fixed, param_password="abcd", control_enabled=False)
    assert not m.control_enabled
    m.unlock(m.new_session(), b"abcd")
    m.raise_alarm(0, 3, 10, "x")
    assert m.alarm_history(1)[0].occurred_at == fixed()


def test_minimal_file(tmp_path: Path) -> None:
    m = load_machine(write(tmp_path, MINIMAL))
    assert isinstance(m, Machine)
    assert m.axes == ["X", "Z"] and m.identity().axes == "02"
    assert not m.has_password
    assert m.pmc_area("R") is None
    with pytest.raises(MachineError) as exc:
        m.read_param(1320, 1)
    assert exc.value.ew == EW.NUMBER


def test_minimal_file_with_a_bit_of_everything(tmp_path: Path) -> None:
    text = (
        MINIMAL
        + """
[panel]
mode = 0
pwe = true
[parameters.1420]
type = "i32"
axis = true
value = 5000
[macros]
ranges = [{ first = 1, last = 10 }]
values = { 3 = -12 }
[pmc.D]
size = 4
values = { 0 = [1, 2, 3, 4] }
"""
    )
    m = load_machine(write(tmp_path, text))
    s = m.new_session()
    assert m.status().aut == 0
    m.write_param(s, 1420, 2, 7000)
    assert [m.read_param(1420, a) for a in (1, 2)] == [5000, 7000]
    assert m.read_macro(3) == Decimal(-12)
    assert m.read_pmc("D", 0, 4) == b"\x01\x02\x03\x04"


BAD_FILES = [
    # (TOML after the [machine] table or a whole file, key named, words of the problem)
    ("[machine]\nname = 'a'\naxes = ['X']\nspeed = 3\n", "machine.speed", "unknown key"),
    ("[machine]\naxes = ['X']\n", "machine.name", "missing"),
    ("[machine]\nname = 'a'\n", "machine.axes", "missing"),
    ("[machine]\nname = 5\naxes = ['X']\n", "machine.name", "must be a string"),
    ('[machine]\nname = "cell\\n7"\naxes = ["X"]\n', "machine.name", "printable characters"),
    (
        f'[machine]\nname = "{"m" * 5000}"\naxes = ["X"]\n',
        "machine.name",
        "1..64 printable characters, not 5000",
    ),
    ("[machine]\nname = 'a'\naxes = []\n", "machine.axes", "1..20 axes"),
    (
        "[machine]\nname = 'a'\naxes = [" + ", ".join(f"'A{i}'" for i in range(1, 22)) + "]\n",
        "machine.axes",
        "a path has 1..20 axes, got 21",
    ),
    ("[machine]\nname = 'a'\naxes = ['X', 'X']\n", "machine.axes[1]", "named twice"),
    ("[machine]\nname = 'a'\naxes = ['X', '']\n", "machine.axes[1]", "axis name"),
    (
        "[machine]\nname = 'a'\naxes = ['X']\nparam_password = 'toolong'\n",
        "machine.param_password",
        "1..4",
    ),
    ("[machine]\nname = 'a'\naxes = ['X']\ncontrol = 'yes'\n", "machine.control", "true or false"),
    (
        "[machine]\nname = 'a'\naxes = ['X']\nhistory_capacity = 0\n",
        "machine.history_capacity",
        "outside",
    ),
    ("[machin]\nname = 'a'\n", "machin", "unknown key"),
    ("x = 1\n", "x", "unknown key"),
    ("[sysinfo]\nseries = 'D4F'\n", "sysinfo.series", "exactly 4"),
    ("[sysinfo]\ncnc_type = 3\n", "sysinfo.cnc_type", "must be a string"),
    ("[panel]\nmode = 'AUTO'\n", "panel.mode", "unknown mode"),
    ("[panel]\nmode = 2\n", "panel.mode", "not a mode"),
    ("[panel]\npwe = 2\n", "panel.pwe", "true or false"),
    ("[panel]\nrun = 9\n", "panel.run", "outside 0..4"),
    ("[parameters.1320]\naxis = true\n", "parameters.1320.type", "missing"),
    ("[parameters.1320]\ntype = 'float'\n", "parameters.1320.type", "unknown type"),
    ("[parameters.abc]\ntype = 'i16'\n", "parameters.abc", "must be a number"),
    ("[parameters.40000]\ntype = 'i16'\n", "parameters.40000", "outside"),
    ("[parameters.-5]\ntype = 'i16'\n", "parameters.-5", "-5 is outside 0..32767"),
    ("[diagnostics.-300]\ntype = 'byte'\n", "diagnostics.-300", "outside 0..32767"),
    ("[parameters.20]\ntype = 'byte'\nvalue = 200\n", "parameters.20.value", "outside"),
    (
        "[parameters.20]\ntype = 'byte'\nrange = [0, 9]\nvalue = 10\n",
        "parameters.20.value",
        "outside 0..9",
    ),
    ("[parameters.20]\ntype = 'byte'\nrange = [0, 300]\n", "parameters.20.range[1]", "outside"),
    ("[parameters.20]\ntype = 'byte'\nrange = [5, 1]\n", "parameters.20.range", "above"),
    ("[parameters.20]\ntype = 'byte'\nrange = [5]\n", "parameters.20.range", "[low, high]"),
    ("[parameters.20]\ntype = 'byte'\nvalue = [1]\n", "parameters.20.value", "axis = true"),
    (
        "[parameters.1420]\ntype = 'i32'\naxis = true\nvalue = [1, 2, 3]\n",
        "parameters.1420.value",
        "3 values for 1 axis",
    ),
    (
        "[parameters.1420]\ntype = 'i32'\naxis = true\nvalue = ['a']\n",
        "parameters.1420.value[0]",
        "must be an integer",
    ),
    ("[parameters.20]\ntype = 'byte'\nunit = 'mm'\n", "parameters.20.unit", "unknown key"),
    (
        "[parameters]\n20 = { type = 'byte' }\n020 = { type = 'byte' }\n",
        "parameters.020",
        "given twice",
    ),
    ("[diagnostics.300]\ntype = 'i64'\n", "diagnostics.300.type", "unknown type"),
    ("[macros]\nranges = [{ first = 10, last = 1 }]\n", "macros.ranges[0]", "above last"),
    ("[macros]\nranges = [{ last = 1 }]\n", "macros.ranges[0].first", "missing"),
    (
        "[macros]\nranges = [{ first = -5, last = 1 }]\n",
        "macros.ranges[0].first",
        "-5 is outside 0..32767",
    ),
    (
        "[macros]\nranges = [{ first = 1, last = 5 }]\nvalues = { -2 = 1 }\n",
        "macros.values.-2",
        "-2 is outside 0..32767",
    ),
    (
        "[macros]\nranges = [{ first = 1, last = 50 }, { first = 40, last = 60 }]\n",
        "macros.ranges[1]",
        "overlaps",
    ),
    (
        "[macros]\nranges = [{ first = 1, last = 5, writable = 'no' }]\n",
        "macros.ranges[0].writable",
        "true or false",
    ),
    (
        "[macros]\nranges = [{ first = 1, last = 5 }]\nvalues = { 9 = 1 }\n",
        "macros.values.9",
        "no macro range",
    ),
    (
        "[macros]\nranges = [{ first = 1, last = 5 }]\nvalues = { 2 = [1, 12] }\n",
        "macros.values.2[1]",
        "outside 0..9",
    ),
    (
        "[macros]\nranges = [{ first = 1, last = 5 }]\nvalues = { 2 = [1, 2, 3] }\n",
        "macros.values.2",
        "[mcr_val, dec_val]",
    ),
    (
        "[macros]\nranges = [{ first = 1, last = 5 }]\nvalues = { 2 = 2.5 }\n",
        "macros.values.2",
        "must be an integer",
    ),
    ("[pmc.Q]\nsize = 10\n", "pmc.Q", "unknown PMC area"),
    ("[pmc.r]\nsize = 10\n[pmc.R]\nsize = 10\n", "pmc.R", "area R is given twice"),
    ("[pmc.R]\nwrite_protected = true\n", "pmc.R.size", "missing"),
    ("[pmc.R]\nsize = 0\n", "pmc.R.size", "outside"),
    ("[pmc.R]\nsize = 10\nvalues = { 9 = [1, 2] }\n", "pmc.R.values.9", "run past"),
    ("[pmc.R]\nsize = 10\nvalues = { 10 = 1 }\n", "pmc.R.values.10", "outside 0..9"),
    ("[pmc.R]\nsize = 10\nvalues = { 1 = 256 }\n", "pmc.R.values.1", "outside 0..255"),
    ("[pmc.R]\nsize = 10\nvalues = { 1 = [1, -1] }\n", "pmc.R.values.1[1]", "outside"),
    ("[[versamax]]\nrack = 0\nmodule = 'IC200GBI001'\n", "versamax[0].slot", "missing"),
    (
        "[[versamax]]\nrack = 8\nslot = 1\nmodule = 'IC200GBI001'\n",
        "versamax[0].rack",
        "outside 0..7",
    ),
    (
        "[[versamax]]\nrack = 0\nslot = 10\nmodule = 'IC200GBI001'\n",
        "versamax[0].slot",
        "outside 0..9",
    ),
    (
        "[[versamax]]\nrack = 0\nslot = 1\nmodule = 'IC200XXX'\n",
        "versamax[0].module",
        "unknown module",
    ),
    (
        "[[versamax]]\nrack = 0\nslot = 1\nmodule = 'IC200GBI001'\n[[versamax]]\nrack = 0\n"
        "slot = 1\nmodule = 'IC200MDD844'\n",
        "versamax[1].slot",
        "given twice",
    ),
    ("[[versamax]]\nrack = 0\nslot = 2\nlabel = 'ABCD'\n", "versamax[0].primary_id", "missing"),
    (
        "[[versamax]]\nrack = 0\nslot = 2\nlabel = 'ABC'\nprimary_id = 0x8008\n",
        "versamax[0].label",
        "exactly 4",
    ),
    (
        "[[versamax]]\nrack = 0\nslot = 2\nlabel = 'ABCD'\nprimary_id = 0x1008\n",
        "versamax[0].primary_id",
        "not a board id",
    ),
    (
        "[[versamax]]\nrack = 0\nslot = 2\nlabel = 'ABCD'\nprimary_id = 0x8008\n"
        "references = [{ type = 'Z', offset = 1, length = 2 }]\n",
        "versamax[0].references[0].type",
        "unknown reference type",
    ),
    (
        "[[versamax]]\nrack = 0\nslot = 2\nlabel = 'ABCD'\nprimary_id = 0x8008\n"
        "references = [{ type = 'I', length = 2 }]\n",
        "versamax[0].references[0].offset",
        "missing",
    ),
    (
        "[[versamax]]\nrack = 0\nslot = 2\nlabel = 'ABCD'\nprimary_id = 0x8008\nsetup = 1\n"
        "references = [{ type = 'I', offset = 1, length = 2 }]\n",
        "versamax[0].default_inputs",
        "defaults must be",
    ),
    (
        "[[versamax]]\nrack = 0\nslot = 2\nmodule = 'IC200GBI001'\nlabel = 'X'\n",
        "versamax[0].label",
        "unknown key",
    ),
    ("[motion]\nabsolute = [1, 2, 3]\n", "motion.absolute", "3 values for 1 axis"),
    ("[motion]\nfeed = -1\n", "motion.feed", "outside"),
    ("[motion]\nspeed = 1\n", "motion.speed", "unknown key"),
    ("[motion]\nfeed = nan\n", "motion.feed", "must be an integer, got a float (nan)"),
    ('[parameters]\n" 1420" = { value = 5 }\n', 'parameters." 1420"', "ASCII digits"),
    ('[parameters]\n"1_420" = { value = 5 }\n', "parameters.1_420", "ASCII digits"),
    ('[macros.values]\n"\u0665\u0660\u0660" = 1\n', 'macros.values."\u0665\u0660\u0660"', "ASCII"),
    (
        "[machine]\nname = 'a'\naxes = ['X']\nparam_password = 1234\n",
        "machine.param_password",
        'write it in quotes, "1234"',
    ),
    ("[run]\nphase = nan\n", "run.phase", "must be a finite number, got nan"),
    (
        '[[program]]\ntext = "O1000\\nG01 X10 F100 (\u00c4)\\nM30\\n"\n',
        "program[0].text",
        "line 2: character 'Ä' (U+00C4) in 'G01 X10 F100 (Ä)': a program is printable ASCII",
    ),
    (
        "[parameters]\n1420 = { type = 'real', decimals = 3, value = nan }\n",
        "parameters.1420.value",
        "must be a finite number, got nan",
    ),
    (
        "[parameters]\n1420 = { type = 'real', decimals = 3, value = '1e3' }\n",
        "parameters.1420.value",
        "must be a number such as 12.345: not a number: '1e3' (no exponent: write the digits)",
    ),
]
_HEAD = "[machine]\nname = 'm'\naxes = ['X']\n"


@pytest.mark.parametrize(("text", "key", "problem"), BAD_FILES)
def test_bad_file_names_file_and_key(tmp_path: Path, text: str, key: str, problem: str) -> None:
    if not text.startswith(("[machine]", "[machin]", "x =")):
        text = _HEAD + text
    path = write(tmp_path, text)
    with pytest.raises(MachineFileError) as exc:
        load_machine(path)
    err = exc.value
    assert err.path == str(path)
    assert err.key == key
    assert problem in err.problem
    assert str(err).startswith(f"{path}: {key}: ")


def test_a_pmc_area_is_named_by_its_letter_in_either_case(tmp_path: Path) -> None:
    m = load_machine(write(tmp_path, MINIMAL + "[pmc.r]\nsize = 16\nvalues = { 2 = 7 }\n"))
    assert m.pmc_area("R") == (16, False)
    assert m.read_pmc("R", 2, 1) == b"\x07"


@pytest.mark.parametrize("name", ["cell\n7", "m" * 65, ""])
def test_a_machine_refuses_the_name_a_machine_file_refuses(name: str) -> None:
    with pytest.raises(ValueError, match=r"1\.\.64 printable characters"):
        Machine(name)
    m = Machine("m")
    with pytest.raises(ValueError, match=r"1\.\.64 printable characters"):
        m.name = name
    assert m.name == "m"
    m.name = "n" * 64
    assert m.name == "n" * 64


def test_missing_machine_table(tmp_path: Path) -> None:
    path = write(tmp_path, "[panel]\nmode = 'MDI'\n")
    with pytest.raises(MachineFileError, match=r"machine\.toml: machine: missing"):
        load_machine(path)


def test_not_toml(tmp_path: Path) -> None:
    path = write(tmp_path, "[machine\nname = 'a'\n")
    with pytest.raises(MachineFileError) as exc:
        load_machine(path)
    assert exc.value.path == str(path)
    assert "not valid TOML" in str(exc.value) and "line 1" in str(exc.value)


def test_missing_file(tmp_path: Path) -> None:
    path = tmp_path / "nowhere.toml"
    with pytest.raises(MachineFileError) as exc:
        load_machine(path)
    assert str(path) in str(exc.value) and "cannot read" in str(exc.value)


def test_machine_file_error_is_a_value_error() -> None:
    assert issubclass(MachineFileError, ValueError)


def test_default_machine_as_file_round_trip(tmp_path: Path) -> None:
    """A file written with the default machine's section-7 content behaves like it."""
    text = """
[machine]
name = "focas-sim-0i"
axes = ["X", "Y", "Z"]
[parameters.1320]
type = "i32"
axis = true
range = [-999999999, 999999999]
value = 999999999
[pmc.F]
size = 768
write_protected = true
"""
    m = load_machine(write(tmp_path, text))
    d = default_machine()
    assert m.read_param(1320, 2) == d.read_param(1320, 2)
    assert m.pmc_area("F") == d.pmc_area("F")
    assert m.status() == d.status()


# -- encoding ---------------------------------------------------------------------------------


def test_utf8_byte_order_mark_is_accepted(tmp_path: Path) -> None:
    """Windows Notepad saves UTF-8 with a byte-order mark: the file loads as without one."""
    path = tmp_path / "bom.toml"
    path.write_bytes(b"\xef\xbb\xbf" + MINIMAL.lstrip().encode())
    assert load_machine(path).name == "tiny"


@pytest.mark.parametrize(
    ("raw", "offset"),
    [
        # Latin-1 text: the e-acute of "Fraise" is the byte 0xE9
        (b'[machine]\nname = "Fraise \xe9"\naxes = ["X"]\n', 25),
        # binary junk
        (b"\x00\x01\xff\xfe\x80", 2),
    ],
)
def test_not_utf8_names_the_file_and_the_offset(tmp_path: Path, raw: bytes, offset: int) -> None:
    path = tmp_path / "latin1.toml"
    path.write_bytes(raw)
    with pytest.raises(MachineFileError) as exc:
        load_machine(path)
    message = str(exc.value)
    assert message.startswith(f"{path}: ")
    assert f"byte {offset}" in message and "UTF-8" in message
    assert "\n" not in message


@pytest.mark.parametrize(("main_flag", "shown"), [("", 2000), ("main = true\n", 1000)])
def test_programs_without_motion_show_the_main_program(
    tmp_path: Path, main_flag: str, shown: int
) -> None:
    text = (
        '[machine]\nname = "m"\naxes = ["X"]\n'
        '[[program]]\ntext = "O2000\\nG01 X10 F100\\nM30\\n"\n'
        f'[[program]]\ntext = "O1000\\nG01 X20 F100\\nM30\\n"\n{main_flag}'
    )
    path = tmp_path / "m.toml"
    path.write_text(text)
    motion = load_machine(path).motion
    assert (motion.program_running, motion.program_main) == (shown, shown)
    path.write_text(text + "[motion]\nprogram_main = 7\n")
    motion = load_machine(path).motion
    assert (motion.program_running, motion.program_main) == (0, 7)


@pytest.mark.parametrize("number", [6711, 6712, 6713])
@pytest.mark.parametrize(
    ("spec", "got"),
    [
        ('type = "real"\ndecimals = 2\nvalue = 5', "a real parameter"),
        ('type = "bit"\nvalue = 255', "a bit parameter"),
        ('type = "byte"\nvalue = 127', "a byte parameter"),
        ('type = "word"\naxis = true', "an axis word parameter"),
    ],
)
def test_the_parts_count_parameters_are_whole_numbers(
    tmp_path: Path, number: int, spec: str, got: str
) -> None:
    """M2/M30 count parts in 6711/6712 (6713 says how many are required): a real, bit, byte or
    axis parameter would count in a mantissa or saturate, so the file and the machine refuse it."""
    path = tmp_path / "m.toml"
    path.write_text(f'[machine]\nname = "m"\naxes = ["X"]\n[parameters.{number}]\n{spec}\n')
    with pytest.raises(ValueError, match=rf"parameters\.{number}\.type") as exc:
        load_machine(path)
    assert "the machine counts parts in it" in str(exc.value) and got in str(exc.value)
    kind = ParamKind.WORD if "axis" in spec else ParamKind.BIT
    item = DataItem(number, kind=kind, axis="axis" in spec, values=[0])
    with pytest.raises(ValueError, match=f"parameter {number}: the machine counts parts"):
        Machine("m", axes=["X"], params=[item])
