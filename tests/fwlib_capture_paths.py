"""Capture how FANUC's FOCAS library handles several paths, as golden data for the native side.

Run with the library (it is never part of this repository)::

    FOCAS_NET_FWLIB=/opt/fwlib/libfwlib32.so.1 python tests/fwlib_capture_paths.py

It writes ``tests/data/fwlib_paths.json`` (``FOCAS_NET_FWLIB_OUT`` names another folder):

* ``probes``: the library against the small responder of ``tests/fwlib_capture.py`` answering
  a 2-path open answer (path 1 " M" with 3 axes, path 2 " T" with 2 axes and 2 spindles;
  :data:`~focas_net.native.PATH_RECORDS` records, the absent ones with no machine type), in both
  layouts: the connect exchanges, ``cnc_getpath``, ``cnc_setpath`` of paths -1..10 (its return
  code, the path ``cnc_getpath`` gives after it, the frames sent), the path word of a request
  after ``cnc_setpath(2)``, and the axis check of path 2;
* ``sets``: the library against the simulator itself serving a twin-turret machine, in both
  command sets: per call the path selected, every data request and the simulator's answer, and
  the call's return code (``tests/test_native_paths.py`` checks the adapter still answers them
  so, without the library).

Each output runs in a process of its own, as ``tests/fwlib_capture.py`` does.
"""

from __future__ import annotations

import ctypes
import json
import sys
from datetime import UTC, datetime
from typing import Any

from fwlib_capture import (
    DATA,
    LIBRARY,
    TIMEOUT_S,
    Machine,
    Responder,
    buf,
    h,
    i32,
    load_library,
    s16,
    say,
    us,
)
from fwlib_support import recorded_server
from paths_support import VALUES, twin_turret

from focas_net.native import PATH_RECORDS, PathDescription, build_open_answer

#: The paths of the probes' open answer: a machining path of 3 axes, a lathe path of 2.
PROBE_PATHS = (PathDescription(" M", 3, 1), PathDescription(" T", 2, 2))
PROBE_MAX_AXES = 4


def probe_paths(lib: Any, version: int) -> dict[str, Any]:
    """What the library does with a 2-path open answer at ``version`` (see the module
    docstring)."""
    body = build_open_answer(PROBE_PATHS, PROBE_MAX_AXES, version=version, records=PATH_RECORDS)
    responder = Responder(Machine(version), open_body=body)
    out: dict[str, Any] = {"version": version, "open_answer": h(body)}
    handle = us()
    try:
        rc = lib.cnc_allclibhndl3(
            b"127.0.0.1", us(responder.port), i32(TIMEOUT_S), ctypes.byref(handle)
        )
        out["connect"] = {
            "return": rc,
            "requests": [
                {"connection": e.connection, "request": h(e.request)} for e in responder.take()
            ],
        }
        if rc != 0:
            raise SystemExit(f"cnc_allclibhndl3 returned {rc} (version {version})")

        def getpath() -> list[int]:
            path, most = s16(0), s16(0)
            got = lib.cnc_getpath(handle, ctypes.byref(path), ctypes.byref(most))
            return [got, path.value, most.value]

        out["getpath"] = getpath()
        selections = []
        # up to 10: the entries of its table (past it, the library reads whatever the handle
        # holds there; cnc_setpath(11) was seen both refused and accepted)
        for p in range(-1, PATH_RECORDS + 1):
            lib.cnc_setpath(handle, s16(2))  # from path 2: whether a refusal keeps it
            got = lib.cnc_setpath(handle, s16(p))
            selections.append({"path": p, "return": got, "getpath": getpath()})
        out["setpath"] = selections
        out["setpath_frames"] = len(responder.take())
        lib.cnc_setpath(handle, s16(2))
        got = lib.cnc_statinfo(handle, buf(18))
        out["statinfo_on_path_2"] = {
            "return": got,
            "requests": [h(e.request) for e in responder.take()],
        }
        axis_checks = []
        for p in (1, 2):
            lib.cnc_setpath(handle, s16(p))
            got = lib.cnc_absolute(handle, s16(3), s16(8), buf(8))
            axis_checks.append(
                {"path": p, "axis": 3, "return": got, "frames": len(responder.take())}
            )
        out["cnc_absolute_axis_3"] = axis_checks
        return out
    finally:
        if handle.value:
            lib.cnc_freelibhndl(handle)
        responder.close()


#: The wall clock of the captured machine (its alarms' stamps).
SIM_TIME = datetime(2026, 12, 7, 1, 0, 0, tzinfo=UTC)
#: The command sets of the simulator capture.
SIM_SETS = ("16i", "30i")
MAX_AXES = 8


def _path_calls(set_name: str, path: int) -> list[tuple[str, dict[str, Any], tuple[Any, ...]]]:
    """The calls made on ``path`` of the twin turret: name, arguments, ctypes arguments."""
    axes = len(VALUES[path - 1].axes)
    slots = axes if set_name == "16i" else MAX_AXES
    return [
        ("cnc_sysinfo", {}, (buf(18),)),
        ("cnc_statinfo", {}, (buf(18),)),
        ("cnc_absolute", {"axis": -1, "length": 4 + 4 * slots},
         (s16(-1), s16(4 + 4 * slots), buf(4 + 4 * 32))),
        ("cnc_rdposition", {"type": -1, "data_num": MAX_AXES},
         (s16(-1), ctypes.byref(s16(MAX_AXES)), buf(48 * MAX_AXES))),
        ("cnc_rddynamic2", {"axis": -1, "length": 28 + 16 * MAX_AXES},
         (s16(-1), s16(28 + 16 * MAX_AXES), buf(28 + 16 * 32))),
        ("cnc_rdprgnum", {}, (buf(8),)),
        ("cnc_exeprgname", {}, (buf(40),)),
        ("cnc_rdseqnum", {}, (buf(8),)),
        ("cnc_rdparam", {"number": 6711, "axis": 0, "length": 8},
         (s16(6711), s16(0), s16(8), buf(4 + 8 * 32))),
        ("cnc_rdmacro", {"number": 100}, (s16(100), s16(10), buf(12))),
        ("cnc_rdmacro", {"number": 500}, (s16(500), s16(10), buf(12))),
        ("cnc_rdalmmsg", {"type": -1, "count": 10},
         (s16(-1), ctypes.byref(s16(10)), buf(44 * 10))),
        ("cnc_alarm2", {}, (ctypes.byref(ctypes.c_int64(0)),)),
    ]  # fmt: skip


def simulate_paths(lib: Any, set_name: str) -> dict[str, Any]:
    """FANUC's library against the simulator serving the twin turret of ``set_name``: the
    selection of each path and its reads, every data request and the simulator's answer."""
    machine = twin_turret(set_name, clock=lambda: SIM_TIME)
    machine.set_panel(0, 1, 0)  # path 1 in MDI, as the live tests have it
    entries: list[dict[str, Any]] = []
    with recorded_server(machine) as recorded:

        def entry(name: str, path: int, arguments: dict[str, Any], rc: int) -> None:
            exchanges = [{"request": h(q), "answer": h(a)} for q, a in recorded.take()]
            entries.append(
                {"function": name, "path": path, "arguments": arguments, "return": rc,
                 "exchanges": exchanges}
            )  # fmt: skip

        handle = us()
        rc = lib.cnc_allclibhndl3(
            b"127.0.0.1", us(recorded.port), i32(TIMEOUT_S), ctypes.byref(handle)
        )
        if rc != 0:
            raise SystemExit(f"cnc_allclibhndl3 returned {rc} ({set_name})")
        entry("cnc_allclibhndl3", 1, {}, rc)
        path, most = s16(0), s16(0)
        rc = lib.cnc_getpath(handle, ctypes.byref(path), ctypes.byref(most))
        entry("cnc_getpath", 1, {"path": path.value, "max": most.value}, rc)
        for p in (1, 2):
            entry("cnc_setpath", p, {"path": p}, lib.cnc_setpath(handle, s16(p)))
            for name, arguments, args in _path_calls(set_name, p):
                entry(name, p, arguments, getattr(lib, name)(handle, *args))
        entry("cnc_setpath", 2, {"path": 3}, lib.cnc_setpath(handle, s16(3)))
        entry("cnc_freelibhndl", 2, {}, lib.cnc_freelibhndl(handle))
        open_response = recorded.open_response
    return {"command_set": set_name, "open_response": h(open_response), "calls": entries}


def run_paths(lib: Any) -> dict[str, Any]:
    return {
        "library": LIBRARY,
        "time": SIM_TIME.isoformat(),
        "probes": [probe_paths(lib, version) for version in (2, 3)],
        "sets": [simulate_paths(lib, set_name) for set_name in SIM_SETS],
    }


def main() -> None:
    lib = load_library()
    DATA.mkdir(exist_ok=True)
    name = "fwlib_paths.json"
    if sys.argv[1:] not in ([], [name]):
        raise SystemExit(f"usage: {sys.argv[0]} [{name}]")
    say(f"capturing {name}")
    (DATA / name).write_text(json.dumps(run_paths(lib), indent=1) + "\n")


if __name__ == "__main__":
    main()
