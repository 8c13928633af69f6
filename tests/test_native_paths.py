"""Several paths on the native wire: the open answer of a multi-path machine (golden bytes of 2
and 4 paths in both layouts) and the adapter answering each block for the path in its path
word. FANUC's library itself drives a twin-turret machine in ``tests/test_fwlib_paths.py``;
the frames it exchanged are checked here without it (``tests/data/fwlib_paths.json``)."""

from __future__ import annotations

import pytest

from focas_net.native import (
    NO_PATH,
    PATH_RECORDS,
    OpenHeadV2,
    OpenHeadV3,
    PathDescription,
    build_open_answer,
    decode_open_answer,
    open_answer_size,
)

TURRET = PathDescription(" T", 2, 1)
MILL = PathDescription(" M", 3, 2)
#: A path record of no path, in each layout.
ABSENT_V2 = "0000 0000 0000 0000"
ABSENT_V3 = "0000" * 16


def _hex(*parts: str) -> bytes:
    return bytes.fromhex(" ".join(parts))


# ---------------------------------------------------------------------------------------------
# The open answer of 2 and 4 paths


def test_two_paths_version_2() -> None:
    body = build_open_answer([TURRET, TURRET], 4, version=2, records=PATH_RECORDS)
    assert body == _hex(
        # kind 0, max axes 4, 10 path records, the path count cnc_getpath reports: 2
        "0000 0000 0004 0000 000a 0002 0000 0000",
        "2054 0000 0002 0001",  # " T", 2 axes, 1 spindle
        "2054 0000 0002 0001",
        *[ABSENT_V2] * 8,
    )
    assert open_answer_size(body, 2) == len(body) == 16 + 8 * 10
    answer = decode_open_answer(body, 2)
    assert isinstance(answer.head, OpenHeadV2)
    assert (answer.head.paths, answer.head.max_paths) == (10, 2)
    assert answer.present() == (TURRET, TURRET)
    assert answer.encode() == body


def test_two_paths_version_3() -> None:
    body = build_open_answer([TURRET, TURRET], 4, version=3, records=PATH_RECORDS)
    turret = "2054 0002 0000 0002 0000 0001" + " 0000" * 10  # " T", lathe, 2 axes, 1 spindle
    assert body == _hex(
        # record format 1, max axes 4, max spindles 1, 10 path records
        "0000 0000 0001 0004 0001 000a",
        "0000 0000 0000 0000 0000",
        "0002",  # the path count cnc_getpath reports
        "0000 0000",
        "0001",  # option bits
        "0000 0000 0000 0000 0000",
        turret,
        turret,
        *[ABSENT_V3] * 8,
    )
    assert open_answer_size(body, 3) == len(body) == 40 + 32 * 10
    answer = decode_open_answer(body, 3)
    assert isinstance(answer.head, OpenHeadV3)
    assert (answer.head.paths, answer.head.max_paths) == (10, 2)
    assert answer.present() == (TURRET, TURRET)
    assert answer.encode() == body


def test_four_paths_version_2() -> None:
    paths = [TURRET, MILL, TURRET, MILL]
    body = build_open_answer(paths, 4, version=2, records=PATH_RECORDS)
    assert body == _hex(
        "0000 0000 0004 0000 000a 0004 0000 0000",
        "2054 0000 0002 0001",
        "204d 0000 0003 0002",  # " M", 3 axes, 2 spindles
        "2054 0000 0002 0001",
        "204d 0000 0003 0002",
        *[ABSENT_V2] * 6,
    )
    assert decode_open_answer(body, 2).present() == tuple(paths)


def test_four_paths_version_3() -> None:
    paths = [TURRET, MILL, TURRET, MILL]
    body = build_open_answer(paths, 4, version=3, records=PATH_RECORDS)
    turret = "2054 0002 0000 0002 0000 0001" + " 0000" * 10
    mill = "204d 0001 0000 0003 0000 0002" + " 0000" * 10  # " M", machining, 3 axes, 2 sp.
    assert body == _hex(
        "0000 0000 0001 0004 0002 000a",  # max spindles: the most of a path, 2
        "0000 0000 0000 0000 0000 0004 0000 0000 0001",
        "0000 0000 0000 0000 0000",
        turret,
        mill,
        turret,
        mill,
        *[ABSENT_V3] * 6,
    )
    answer = decode_open_answer(body, 3)
    assert answer.present() == tuple(paths)
    assert [r.machine_type for r in answer.paths].count(NO_PATH) == 6


@pytest.mark.parametrize("version", [2, 3])
def test_one_record_per_path_unless_asked(version: int) -> None:
    """Without ``records`` an answer has one record per path (a single-path machine's answer is
    what it always was)."""
    body = build_open_answer([TURRET, MILL], 4, version=version)
    answer = decode_open_answer(body, version)
    assert len(answer.paths) == 2
    assert answer.head.paths == 2


@pytest.mark.parametrize("records", [1, PATH_RECORDS + 1])
def test_records_between_the_paths_and_ten(records: int) -> None:
    with pytest.raises(ValueError, match=f"{records} path records for 2 paths"):
        build_open_answer([TURRET, TURRET], 4, records=records)
