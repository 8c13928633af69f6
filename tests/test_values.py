"""The named ODBST values: every member's number, screen label and meaning."""

from __future__ import annotations

import pickle

import pytest

from focas_net.protocol.values import (
    AlarmState,
    AutMode,
    EditState,
    EmergencyState,
    HdckState,
    MotionState,
    MstbState,
    RunState,
    TmMode,
)

ODBST_ENUMS = [
    AutMode,
    RunState,
    MotionState,
    MstbState,
    EmergencyState,
    AlarmState,
    EditState,
    TmMode,
    HdckState,
]
Labelled = (
    type[AutMode]
    | type[RunState]
    | type[MotionState]
    | type[MstbState]
    | type[EmergencyState]
    | type[AlarmState]
    | type[EditState]
    | type[TmMode]
    | type[HdckState]
)


@pytest.mark.parametrize("enum_type", ODBST_ENUMS, ids=lambda e: e.__name__)
def test_every_member_has_a_label_and_a_meaning(enum_type: Labelled) -> None:
    for member in enum_type:
        assert isinstance(member.label, str) and member.label.strip() == member.label != ""
        assert isinstance(member.meaning, str) and member.meaning.strip() == member.meaning != ""
        assert member.label.isascii() and len(member.label) <= 7


@pytest.mark.parametrize("enum_type", ODBST_ENUMS, ids=lambda e: e.__name__)
def test_labels_and_meanings_are_distinct(enum_type: Labelled) -> None:
    members = list(enum_type)
    assert len({m.label for m in members}) == len(members)
    assert len({m.meaning for m in members}) == len(members)


@pytest.mark.parametrize("enum_type", ODBST_ENUMS, ids=lambda e: e.__name__)
def test_members_are_the_numbers_from_zero(enum_type: Labelled) -> None:
    numbers = [int(m) for m in enum_type]
    assert numbers == list(range(len(numbers)))
    for member in enum_type:
        assert type(member.value) is int
        assert enum_type(member.value) is member
        assert pickle.loads(pickle.dumps(member)) is member


def test_labels_follow_the_screen() -> None:
    """Asterisks fill the field: four in the mode, run and edit fields, three in the motion
    and M/S/T/B fields; an inactive emergency or alarm field reads ``****``."""
    assert AutMode.NOSEL.label == "****"
    assert RunState.RESET.label == "****"
    assert EditState.NONE.label == "****"
    assert MotionState.NONE.label == "***"
    assert MstbState.NONE.label == "***"
    assert EmergencyState.NONE.label == "****"
    assert AlarmState.NONE.label == "****"
    assert HdckState.NONE.label == "****"
    assert [m.label for m in AutMode] == [
        "MDI", "MEM", "****", "EDIT", "HND", "JOG", "TJOG", "THND", "INC", "REF", "RMT",
    ]  # fmt: skip
    assert [m.label for m in RunState] == ["****", "STOP", "HOLD", "STRT", "MSTR"]
    assert [m.label for m in MotionState] == ["***", "MTN", "DWL", "WAIT"]
    assert [m.label for m in MstbState] == ["***", "FIN"]
    assert [m.label for m in EmergencyState] == ["****", "EMG", "RESET"]
    assert [m.label for m in EditState] == ["****", "EDIT", "SEARCH", "OUTPUT", "INPUT", "COMPARE"]
    assert [m.label for m in TmMode] == ["T", "M"]
    assert [m.label for m in HdckState] == ["****", "HDCK"]


def test_meanings() -> None:
    assert AutMode.MEM.meaning == "memory (automatic operation)"
    assert RunState.RESET.meaning == "reset"
    assert TmMode.T.meaning == "T mode"
    assert EmergencyState.NONE.meaning == "not in emergency stop"
    assert AlarmState.BAT.meaning == "battery low"


def test_parse_takes_a_name_a_label_or_a_number() -> None:
    assert AutMode.parse("mdi") is AutMode.MDI
    assert AutMode.parse(" MEM ") is AutMode.MEM
    assert AutMode.parse("****") is AutMode.NOSEL
    assert AutMode.parse("10") is AutMode.RMT
    assert AutMode.parse(3) is AutMode.EDIT
    assert MotionState.parse("***") is MotionState.NONE
    assert RunState.parse("****") is RunState.RESET
    assert HdckState.parse("hdck") is HdckState.HDCK
    with pytest.raises(ValueError, match=r"unknown AutMode 'TURBO' \(one of MDI, MEM, NOSEL"):
        AutMode.parse("TURBO")
    for bad in ("11", "-1", 11):
        with pytest.raises(ValueError, match="unknown AutMode"):
            AutMode.parse(bad)
    with pytest.raises(ValueError, match="unknown TmMode"):
        TmMode.parse("0x1")


def test_members_are_integers() -> None:
    assert isinstance(AutMode.MEM, int) and int(AutMode.RMT) == 10
    assert f"{MotionState.DWL:d}" == "2" and sorted([AutMode.RMT, AutMode.MDI]) == [0, 10]
