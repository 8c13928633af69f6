"""FANUC's Windows library as a second verifier: the same calls through ``Fwlib32.dll`` (under
wine) and through the Linux library, against the same simulated machine, must fill the same
bytes.

``tests/fwlib_probe.c`` is built twice: with Debian's mingw-w64 (``i686-w64-mingw32-gcc``)
against ``Fwlib32.dll``, run under Debian's wine next to ``Fwlib32.dll`` and ``fwlibe1.dll``;
and with ``gcc`` against the Linux library. Both run against one served machine whose clocks
stand still (idle, and with a program stopped mid-motion), in both command sets, and every
line (a call, its return code, the bytes it filled) must be the same; so must the requests the
two libraries send, as a CNC reads them (see :func:`_request_text`).

Runs only when every piece is there, and says what is missing otherwise (CI has none of them):

* ``FOCAS_NET_FWLIB_WIN`` names a folder holding ``Fwlib32.dll`` and ``fwlibe1.dll`` (FANUC's
  Windows library, from the public repository that also holds the Linux one; never part of
  this repository);
* ``FOCAS_NET_FWLIB`` names the Linux library (x86-64);
* ``wine``, ``i686-w64-mingw32-gcc`` and ``gcc`` are on the PATH (Debian: ``dpkg
  --add-architecture i386``, ``apt-get update``, ``apt-get install wine wine32 mingw-w64``).

``WINEPREFIX`` is used when set (a fresh prefix takes wine some seconds to make). With
``FOCAS_NET_FWLIB_WIN_LOG`` naming a file, the Windows library's own byte log is switched on
(DWORD ``LogLevel`` = 3 under ``HKCU\\Software\\FANUC\\FwlibEth``) and copied there from
``C:\\ProgramData\\FANUC\\Fwlib\\FWLIBETH.LOG``; ``FOCAS_NET_FWLIB_LOG`` does the same for the
Linux library (``cnc_startupprocess(3, log)``).
"""

from __future__ import annotations

import asyncio
import os
import shutil
import subprocess
from collections.abc import Iterator
from datetime import UTC, datetime
from decimal import Decimal
from pathlib import Path

import pytest
from fwlib_support import MACHINE_16I, Recorder
from support import serving

from focas_net.sim import ExternalMessage, Machine, default_machine, load_machine
from focas_net.sim.nc import ManualClock

WINDOWS = os.environ.get("FOCAS_NET_FWLIB_WIN")
LINUX = os.environ.get("FOCAS_NET_FWLIB")
TOOLS = ("wine", "i686-w64-mingw32-gcc", "gcc")
DLLS = ("Fwlib32.dll", "fwlibe1.dll")
PROBE = Path(__file__).with_name("fwlib_probe.c")
#: Seconds a probe may take (wine's first start in a fresh prefix included).
PROBE_TIMEOUT = 180


def _missing() -> str | None:
    if not WINDOWS:
        return "set FOCAS_NET_FWLIB_WIN to a folder holding FANUC's Fwlib32.dll and fwlibe1.dll"
    absent = [d for d in DLLS if not (Path(WINDOWS) / d).is_file()]
    if absent:
        return f"FOCAS_NET_FWLIB_WIN ({WINDOWS}) lacks {', '.join(absent)}"
    if not LINUX:
        return "set FOCAS_NET_FWLIB to FANUC's Linux library to compare the Windows one with"
    tools = [t for t in TOOLS if shutil.which(t) is None]
    if tools:
        return f"{', '.join(tools)} not found (Debian: apt-get install wine wine32 mingw-w64 gcc)"
    return None


pytestmark = pytest.mark.skipif(_missing() is not None, reason=_missing() or "")

#: The machines' wall clock (the date and time the control reads out: ``cnc_gettimer``,
#: ``#3011``/``#3012``, the file system's dates), the same for both probes.
STAMP = datetime(2026, 12, 1, 8, 0, 0, tzinfo=UTC)

#: The spindle, a tool change (4 s), a cut (the running machine's clock stops in N30's motion;
#: G54 and the stroke limits of both machines keep it in bounds).
PROGRAM = """O0100 (PROBE)
N10 G90 G21 G17 G54 S1200 M3
N20 T1 M6
N30 G1 X60. Y25. F1200
N40 M30
"""

#: What the 16i machine file lacks for the probe's calls: the G, F and A areas of a ladder
#: (the panel signals, cnc_rdspeed's G28, the external operator message of A0.0), tools.
EXTRAS_16I = """
[[operator_messages]]
address = "A0.0"
number = 2005
text = "COOLANT LOW"

[pmc.G]
size = 768
[pmc.F]
size = 768
write_protected = true
[pmc.A]
size = 16

[[tools]]
offsets = 32
work = { EXT = [0.5, 0, 0], G54 = [100.25, 50, 300.125], G55 = [1, 2, 3] }
[[tools.offset]]
number = 1
length_geometry = 150.0
length_wear = -0.02
radius_geometry = 6.0
[[tools.group]]
number = 1
life = 2
tools = [{ t = 1, h = 1, d = 1 }, { t = 6, h = 6, d = 26 }]
[[tools.group]]
number = 2
life = 20
type = "time"
tools = [7]
"""


class Probes:
    """The probe built for each library, and how to run it."""

    def __init__(self, folder: Path) -> None:
        self.folder = folder
        self.env = dict(os.environ, WINEDEBUG="-all")
        self.env.setdefault("WINEPREFIX", str(folder / "wineprefix"))
        self.linux = folder / "probe_linux"
        self.windows = folder / "probe.exe"

    def build(self) -> None:
        assert LINUX is not None and WINDOWS is not None
        self._run(
            ["gcc", "-O1", "-o", str(self.linux), str(PROBE), LINUX,
             f"-Wl,-rpath,{Path(LINUX).resolve().parent}"]
        )  # fmt: skip
        self._run(
            ["i686-w64-mingw32-gcc", "-O1", "-o", str(self.windows), str(PROBE),
             str(Path(WINDOWS) / "Fwlib32.dll"), "-Wl,--enable-stdcall-fixup"]
        )  # fmt: skip
        for dll in DLLS:
            shutil.copy(Path(WINDOWS) / dll, self.folder / dll)
        if os.environ.get("FOCAS_NET_FWLIB_WIN_LOG"):
            key = r"HKCU\Software\FANUC\FwlibEth"
            self._run(["wine", "reg", "add", key, "/v", "LogLevel", "/t", "REG_DWORD", "/d", "3",
                       "/f"])  # fmt: skip

    def _run(self, command: list[str]) -> None:
        done = subprocess.run(command, env=self.env, capture_output=True, timeout=120, check=False)
        assert done.returncode == 0, done.stderr.decode(errors="replace")

    async def run(self, windows: bool, port: int, slots: int) -> list[str]:
        """The probe's lines against 127.0.0.1:``port`` (run without blocking the loop that
        serves the machine)."""
        command = ["wine", str(self.windows)] if windows else [str(self.linux)]
        proc = await asyncio.create_subprocess_exec(
            *command, "127.0.0.1", str(port), str(slots), cwd=self.folder, env=self.env,
            stdout=asyncio.subprocess.PIPE, stderr=asyncio.subprocess.PIPE,
        )  # fmt: skip
        try:
            out, err = await asyncio.wait_for(proc.communicate(), PROBE_TIMEOUT)
        except TimeoutError:
            proc.kill()
            await proc.wait()
            raise
        assert proc.returncode == 0, err.decode(errors="replace")
        if windows:
            self._keep_windows_log()
        return out.decode().replace("\r\n", "\n").splitlines()

    def _keep_windows_log(self) -> None:
        target = os.environ.get("FOCAS_NET_FWLIB_WIN_LOG")
        log = Path(self.env["WINEPREFIX"]) / "drive_c/ProgramData/FANUC/Fwlib/FWLIBETH.LOG"
        if target and log.is_file():
            shutil.copy(log, target)


@pytest.fixture(scope="module")
def probes(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Probes]:
    built = Probes(tmp_path_factory.mktemp("fwlib_probe"))
    built.build()
    yield built


def _machine(set_name: str, running: bool, folder: Path) -> Machine:
    """A machine whose clocks stand still, so both probes read the same state: the built-in
    0i-F at 30i class, the 16i machine file with a ladder's areas and tools at 16i class; with
    an alarm (active when idle, in the history when running), macro values and the external
    operator message of A0.0. Idle, it holds set figures at 16i class; running, :data:`PROGRAM`
    is stopped in the middle of its motion."""
    clock = ManualClock()
    if set_name == "30i":
        m = default_machine(sim_clock=clock, clock=lambda: STAMP, programs=(PROGRAM,))
        m.set_external_messages([ExternalMessage(0, 0, 2005, "COOLANT LOW")])
    else:
        file = folder / "16i.toml"
        file.write_text(MACHINE_16I.read_text(encoding="utf-8") + EXTRAS_16I, encoding="utf-8")
        m = load_machine(file, sim_clock=clock, clock=lambda: STAMP)
        m.store_program(PROGRAM)
        if not running:
            m.set_motion(
                absolute=[12345, -2500, 100000], machine=[22345, -12500, 90000],
                relative=[345, 500, -1000], distance_to_go=[10, 0, -20], feed=1500,
                spindle_speed=3000, program_running=1234, program_main=1000, sequence=56,
            )  # fmt: skip
    clock.advance(3725.0)  # powered on an hour ago
    m.raise_alarm(1, 4, 500, "OVER TRAVEL +X")
    if running:  # the alarm, which stops a cycle, cleared: in the history only
        m.clear_alarms()
        m.set_panel(1)  # MEM
        m.select_program(100)
        m.cycle_start()
        clock.advance(5.5)  # past the tool change (4 s), X and Y on their way
    m.write_macro(100, 7)
    m.write_macro(500, Decimal("-12.5"))
    m.write_pmc("R", 100, bytes(range(1, 17)))
    m.write_pmc("A", 0, b"\x01")
    return m


def _slots(machine: Machine, set_name: str) -> int:
    """Values an all-axes offset read makes room for: the path's axes at 16i class, the open
    answer's max axes at 30i class."""
    return len(machine.axes) if set_name == "16i" else machine.identity().max_axis


#: Where a request's data after its five arguments begins (a one-request body: count, length,
#: two words, the command, five 4-byte arguments; the fifth is the data's length).
DATA_AT = 30


def _request_text(body: bytes) -> bytes:
    """A request as the CNC reads it when its data is a path: the head, then the path up to
    its NUL and at most the field's size less one byte.

    The two libraries fill a path field differently, and only past what a CNC reads:
    ``Fwlib32.dll`` copies the path with its NUL into a scratch buffer it does not clear, so
    the bytes after the NUL are those of an earlier request (``cnc_rdpdf_subdir``,
    ``cnc_rdpdf_alldir``: 256 bytes), and it keeps the last byte of a field for the NUL
    (``cnc_rdpdf_inf`` sends 12 bytes: ``//CNC_MEM/U`` and a NUL for ``//CNC_MEM/USER/``,
    where the Linux library sends the 12 characters ``//CNC_MEM/US``). Any other difference
    stays."""
    if body[:2] != b"\x00\x01" or len(body) <= DATA_AT or b"//" not in body[DATA_AT:]:
        return body
    data = body[DATA_AT:]
    return body[:DATA_AT] + data.split(b"\x00", 1)[0][: len(data) - 1]


@pytest.mark.parametrize("running", [False, True], ids=["idle", "running"])
@pytest.mark.parametrize("set_name", ["30i", "16i"])
async def test_the_windows_library_fills_what_the_linux_library_fills(
    probes: Probes, recorder: Recorder, set_name: str, running: bool, tmp_path: Path
) -> None:
    machine = _machine(set_name, running, tmp_path)
    status = machine.status()
    assert (status.run, status.motion) == ((3, 1) if running else (0, 0))  # STaRT, MoTioN
    slots = _slots(machine, set_name)
    async with serving(machine) as served:
        linux = await probes.run(False, served.port, slots)
        linux_requests = recorder.take()
        windows = await probes.run(True, served.port, slots)
        windows_requests = recorder.take()
    assert linux[0] == "cnc_allclibhndl3 0"
    assert linux[-1] == "cnc_freelibhndl 0"
    # "name code bytes" lines (the others give a count or a value returned through a pointer)
    words = [line.split(" ")[:2] for line in linux]
    calls = [(name, rc) for name, rc in words if rc.lstrip("-").isdigit()]
    assert len(calls) > 160
    # most of what the probe asks the machine serves (the rest are refusals of the library
    # or of the control, which both builds must give alike)
    served_ok = [name for name, rc in calls if rc == "0"]
    assert len(served_ok) > 130, linux
    assert [(w, lin) for w, lin in zip(windows, linux, strict=True) if w != lin] == []
    # and the two libraries sent the same requests, in the same order
    assert len(linux_requests) > 100
    assert len(windows_requests) == len(linux_requests)
    differ = [
        (i, lin.hex(), win.hex())
        for i, (lin, win) in enumerate(zip(linux_requests, windows_requests, strict=True))
        if _request_text(lin) != _request_text(win)
    ]
    assert differ == []
