"""A machine reports the max axes a CNC of its control class reports (ODBSYS ``max_axis`` and
the FOCAS/2 open answer): 32 for the 30i family and the 0i-D/0i-F, 8 for the 16i family and
the 0i-C; a machine file may say otherwise."""

from __future__ import annotations

import pytest

from focas_net.adapters import NativeAdapter
from focas_net.native import decode_frame, decode_open_answer
from focas_net.sim import (
    CLASS_MAX_AXES,
    CONTROL_CLASSES,
    Machine,
    MachineFileError,
    default_machine,
    machine_from_dict,
)


def test_every_class_has_its_max_axes() -> None:
    assert set(CLASS_MAX_AXES) == set(CONTROL_CLASSES)
    assert {c for c, n in CLASS_MAX_AXES.items() if n == 8} == {"16i", "18i", "21i", "0i-C"}
    assert {c for c, n in CLASS_MAX_AXES.items() if n == 32} == {
        "0i-D", "0i-F", "30i", "31i", "32i"
    }  # fmt: skip


@pytest.mark.parametrize("control_class", CONTROL_CLASSES)
def test_a_machine_reports_its_class_max_axes(control_class: str) -> None:
    want = CLASS_MAX_AXES[control_class]
    built = Machine("m", axes="XYZ", control_class=control_class)
    loaded = machine_from_dict(
        {"machine": {"name": "m", "axes": ["X", "Y", "Z"], "control_class": control_class}}
    )
    for machine in (built, loaded):
        assert machine.identity().max_axis == want
        adapter = NativeAdapter(machine)
        frame = decode_frame(adapter.open_response())
        assert decode_open_answer(frame.body, frame.version).max_axes == want == adapter.max_axis


def test_the_built_in_machine_is_a_0i_f_of_32_axes() -> None:
    assert default_machine().identity().max_axis == 32


def test_a_machine_file_says_otherwise() -> None:
    machine = machine_from_dict(
        {"machine": {"name": "m", "axes": ["X", "Y"], "control_class": "30i"},
         "sysinfo": {"max_axis": 8}}
    )  # fmt: skip
    assert machine.identity().max_axis == 8
    assert NativeAdapter(machine).max_axis == 8
    with pytest.raises(MachineFileError, match="max_axis"):
        machine_from_dict(
            {"machine": {"name": "m", "axes": ["X", "Y"]}, "sysinfo": {"max_axis": 33}}
        )


def test_more_axes_than_the_class_has_raise_the_max() -> None:
    axes = [f"A{i}" for i in range(10)]
    machine = machine_from_dict({"machine": {"name": "m", "axes": axes, "control_class": "16i"}})
    assert machine.identity().max_axis == 10
