"""FANUC's library itself, when it is available: the capture, redone, gives the golden data.

Skipped unless ``FOCAS_NET_FWLIB`` points at FANUC's libfwlib32 (never part of this
repository). The capture runs in child processes (``tests/fwlib_capture.py``), so a crash of
the library cannot take the test run down.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

HERE = Path(__file__).parent
LIBRARY = os.environ.get("FOCAS_NET_FWLIB")

pytestmark = pytest.mark.skipif(
    not LIBRARY, reason="FOCAS_NET_FWLIB is not set (path of FANUC's libfwlib32)"
)


@pytest.mark.parametrize(
    "name",
    ["fwlib_v2.json", "fwlib_v3.json", "fwlib_float.json", "fwlib_probes.json", "fwlib_sim.json"],
)
def test_capture_reproduces_the_golden_data(name: str, tmp_path: Path) -> None:
    env = dict(os.environ, FOCAS_NET_FWLIB_OUT=str(tmp_path))
    subprocess.run(
        [sys.executable, str(HERE / "fwlib_capture.py"), name],
        env=env,
        check=True,
        timeout=600,
        capture_output=True,
    )
    fresh = json.loads((tmp_path / name).read_text())
    golden = json.loads((HERE / "data" / name).read_text())
    assert fresh == golden


def test_paths_capture_reproduces_the_golden_data(tmp_path: Path) -> None:
    """The 2-path capture (``tests/fwlib_capture_paths.py``): probes and the twin turret."""
    env = dict(os.environ, FOCAS_NET_FWLIB_OUT=str(tmp_path))
    subprocess.run(
        [sys.executable, str(HERE / "fwlib_capture_paths.py")],
        env=env,
        check=True,
        timeout=600,
        capture_output=True,
    )
    name = "fwlib_paths.json"
    fresh = json.loads((tmp_path / name).read_text())
    golden = json.loads((HERE / "data" / name).read_text())
    assert fresh == golden
