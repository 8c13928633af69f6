"""A new user's pass over machine files, part programs and the examples (pass 11): each test
names a case that was wrong or unsettled, and the behaviour FANUC's practice asks for."""

from __future__ import annotations

import tomllib
from pathlib import Path

import pytest

from focas_net.sim import (
    LifeTool,
    Machine,
    MachineFileError,
    ToolGroup,
    ToolsSpec,
    machine_from_dict,
)

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
