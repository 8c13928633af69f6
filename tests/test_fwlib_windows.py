"""FANUC's Windows library as a second verifier: the same calls through ``Fwlib32.dll`` (under
wine) and through the Linux library, against the same simulated machine, must fill the same
bytes.

``tests/fwlib_probe.c`` is built twice: with Debian's mingw-w64 (``i686-w64-mingw32-gcc``)
against ``Fwlib32.dll``, run under Debian's wine next to ``Fwlib32.dll`` and ``fwlibe1.dll``;
and with ``gcc`` against the Linux library. Both run against one served machine whose clocks
stand still (a program stopped mid-motion at 30i class, set figures at 16i class), and every
line (a call, its return code, the bytes it filled) must be the same.

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
from fwlib_support import MACHINE_16I
from support import serving

from focas_net.sim import Machine, default_machine, load_machine
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

STAMP = datetime(2026, 12, 1, 8, 0, 0, tzinfo=UTC)

PROGRAM = """O0100 (PROBE)
N10 G90 G21 G17 G54 S1200 M3
N20 G1 X60. Y-25. F1200
N30 M30
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

    async def run(self, windows: bool, port: int) -> list[str]:
        """The probe's lines against 127.0.0.1:``port`` (run without blocking the loop that
        serves the machine)."""
        command = ["wine", str(self.windows)] if windows else [str(self.linux)]
        proc = await asyncio.create_subprocess_exec(
            *command, "127.0.0.1", str(port), cwd=self.folder, env=self.env,
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


def _machine(set_name: str) -> Machine:
    """A machine whose clocks stand still, so both probes read the same state: at 30i class
    the built-in 0i-F stopped in the middle of a program's motion, at 16i class the 16i
    machine file with set figures; both with an alarm and macro values."""
    clock = ManualClock()
    if set_name == "30i":
        m = default_machine(sim_clock=clock, clock=lambda: STAMP, programs=(PROGRAM,))
        m.cycle_start()
        clock.advance(1.75)  # X and Y on their way
    else:
        m = load_machine(MACHINE_16I, sim_clock=clock, clock=lambda: STAMP)
        m.set_motion(
            absolute=[12345, -2500, 100000], machine=[22345, -12500, 90000],
            relative=[345, 500, -1000], distance_to_go=[10, 0, -20], feed=1500,
            spindle_speed=3000, program_running=1234, program_main=1000, sequence=56,
        )  # fmt: skip
    m.write_macro(100, 7)
    m.write_macro(500, Decimal("-12.5"))
    m.write_pmc("R", 100, bytes(range(1, 17)))
    m.raise_alarm(1, 4, 500, "OVER TRAVEL +X")
    return m


@pytest.mark.parametrize("set_name", ["30i", "16i"])
async def test_the_windows_library_fills_what_the_linux_library_fills(
    probes: Probes, set_name: str
) -> None:
    async with serving(_machine(set_name)) as served:
        linux = await probes.run(False, served.port)
        windows = await probes.run(True, served.port)
    assert linux[0] == "cnc_allclibhndl3 0"
    assert len(linux) > 40
    calls = {line.split(" ")[0]: line.split(" ")[1] for line in linux}
    # what the machine serves comes back EW_OK (the probe reads no alarm history: EW_NUMBER)
    served_ok = [name for name, rc in calls.items() if rc == "0"]
    assert len(served_ok) > 35, linux
    assert [w for w, lin in zip(windows, linux, strict=True) if w != lin] == []
    assert windows == linux
