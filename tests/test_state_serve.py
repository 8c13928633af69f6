"""``serve --state`` as the command line builds it: one state per machine of a fleet, the
machine file's ``[machine] state``, ``--read-only``, and a running machine's parts kept."""

from __future__ import annotations

import argparse
import os
import time
from pathlib import Path

import pytest

from focas_net.cli import _fleet, serve
from focas_net.cli._fleet import ConfigError
from focas_net.cli._state import Kept, saver
from focas_net.sim import DEFAULT_NAME
from focas_net.sim.statefile import state_path


def _parse(*argv: str) -> argparse.Namespace:
    parser = argparse.ArgumentParser()
    serve.register(parser.add_subparsers())
    return parser.parse_args(["serve", *argv])


def test_a_fleet_keeps_one_state_per_machine(tmp_path: Path) -> None:
    states: list[Kept] = []
    machines = _fleet.build_machines(_parse("--fleet", "3", "--state", str(tmp_path)), states)
    for i, m in enumerate(machines):
        m.write_macro(500, i + 10)
    saver(states)()
    assert sorted(p.name for p in tmp_path.iterdir()) == [
        state_path(tmp_path, f"{DEFAULT_NAME}-{i}").name for i in (1, 2, 3)
    ]
    again = _fleet.build_machines(_parse("--fleet", "3", "--state", str(tmp_path)), [])
    assert [m.read_macro(500) for m in again] == [10, 11, 12]


def test_read_only_serves_the_state_and_keeps_it_as_it_was(tmp_path: Path) -> None:
    states: list[Kept] = []
    (m,) = _fleet.build_machines(_parse("--state", str(tmp_path)), states)
    m.write_macro(700, 7)
    saver(states)()
    (path,) = tmp_path.iterdir()
    before = path.read_bytes()
    kept: list[Kept] = []
    (ro,) = _fleet.build_machines(_parse("--state", str(tmp_path), "--read-only"), kept)
    assert ro.read_only and ro.read_macro(700) == 7
    ro.read_only = False  # even a change made behind its back is not written
    ro.write_macro(700, 8)
    saver(kept)()
    assert path.read_bytes() == before


def test_the_machine_file_names_the_state_folder(tmp_path: Path) -> None:
    machine = tmp_path / "cell.toml"
    machine.write_text(
        '[machine]\nname = "CELL"\naxes = ["X", "Z"]\nstate = "kept"\n'
        "[macros]\nranges = [{ first = 500, last = 999 }]\n"
    )
    states: list[Kept] = []
    (m,) = _fleet.build_machines(_parse("--machine", str(machine)), states)
    m.write_macro(500, 3)
    saver(states)()
    assert state_path(tmp_path / "kept", "CELL").exists()
    (again,) = _fleet.build_machines(_parse("--machine", str(machine)), [])
    assert again.read_macro(500) == 3


def test_a_running_machine_keeps_its_parts(tmp_path: Path) -> None:
    states: list[Kept] = []
    args = _parse("--state", str(tmp_path), "--run", "--speed", "1000")
    (m,) = _fleet.build_machines(args, states)
    m.write_macro(3902, 500)  # the total parts
    for _ in range(200):  # bounded: machine time runs 1000 times faster than ours
        if m.parts_counts()[1] > 500:
            break
        time.sleep(0.01)
    made = m.parts_counts()[1]
    assert made > 500
    saver(states)()
    (again,) = _fleet.build_machines(_parse("--state", str(tmp_path)), [])
    assert again.parts_counts()[1] >= made


def test_a_state_of_another_machine_is_a_config_error(tmp_path: Path) -> None:
    states: list[Kept] = []
    (m,) = _fleet.build_machines(_parse("--state", str(tmp_path)), states)
    m.write_macro(500, 1)
    saver(states)()
    machine = tmp_path / "other.toml"
    machine.write_text(f'[machine]\nname = "{DEFAULT_NAME}"\naxes = ["X"]\n')
    with pytest.raises(ConfigError, match=r"^--state: .*machine file changed"):
        _fleet.build_machines(_parse("--machine", str(machine), "--state", str(tmp_path)))


def test_a_state_folder_that_cannot_be_written_is_refused_at_the_start(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    afile = tmp_path / "afile"
    afile.write_text("")
    with pytest.raises(ConfigError, match=r"^--state .*afile: not a directory$"):
        _fleet.build_machines(_parse("--state", str(afile)))
    real_open = os.open

    def read_only_disk(path: str | os.PathLike[str], flags: int, *mode: int) -> int:
        if flags & os.O_CREAT:
            raise OSError(30, "Read-only file system", str(path))
        return real_open(path, flags, *mode)

    with monkeypatch.context() as patched:
        patched.setattr(os, "open", read_only_disk)  # root writes anywhere: a read-only disk
        with pytest.raises(ConfigError, match=r"^--state .*: read-only file system$"):
            _fleet.build_machines(_parse("--state", str(tmp_path / "kept")))
        assert _fleet.build_machines(_parse("--state", str(tmp_path), "--read-only"))
    assert _fleet.build_machines(_parse("--state", str(tmp_path / "kept")))
    assert [p.name for p in (tmp_path / "kept").iterdir()] == []  # the probe is gone


def test_a_turn_of_a_fleet_costs_one_flush_a_changed_machine(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    states: list[Kept] = []
    machines = _fleet.build_machines(_parse("--fleet", "4", "--state", str(tmp_path)), states)
    synced: list[str] = []
    fsync, fdatasync = os.fsync, os.fdatasync

    def counted_fsync(fd: int) -> None:
        synced.append("fsync")
        fsync(fd)

    def counted_fdatasync(fd: int) -> None:
        synced.append("fdatasync")
        fdatasync(fd)

    monkeypatch.setattr(os, "fsync", counted_fsync)
    monkeypatch.setattr(os, "fdatasync", counted_fdatasync)
    for m in machines[:3]:
        m.write_macro(500, 1)
    saver(states)()  # each file created (flushed), then the folder once
    assert synced == ["fsync"] * 4
    synced.clear()
    for m in machines[:3]:
        m.write_macro(500, 2)
    saver(states)()  # a record appended to each journal: one flush each, the folder alone
    assert synced == ["fdatasync"] * 3
    synced.clear()
    saver(states)()  # nothing changed: nothing written
    assert synced == []


async def test_a_change_without_an_answer_is_saved_within_a_second(tmp_path: Path) -> None:
    from support import IO_TIMEOUT, wait_until

    from focas_net.cli._state import keep_running
    from focas_net.server import FocasServer
    from focas_net.sim.statefile import decode_state

    states: list[Kept] = []
    (m,) = _fleet.build_machines(_parse("--state", str(tmp_path)), states)
    server = FocasServer(m, host="127.0.0.1", port=0, durable=saver(states))
    (path,) = [state.path for state, _ in states]
    async with server, keep_running(server, states, read_only=False):
        m.write_macro(800, 8)  # no answer waits for it (as a running machine counts)

        def kept() -> bool:
            return path.exists() and "800" in decode_state(path.read_bytes())["kept"]["macros"]

        await wait_until(kept, within=3 * IO_TIMEOUT)
