"""``focas-net serve --machine`` with files in the wrong encoding: one line, exit 2."""

from __future__ import annotations

import asyncio
import sys
from pathlib import Path

import pytest

START_TIMEOUT = 30.0


async def _serve_to_exit(*args: str) -> tuple[int, str, str]:
    proc = await asyncio.create_subprocess_exec(
        sys.executable, "-m", "focas_net", "serve", "--port", "0", *args,
        stdout=asyncio.subprocess.PIPE, stderr=asyncio.subprocess.PIPE,
    )  # fmt: skip
    async with asyncio.timeout(START_TIMEOUT):
        out, err = await proc.communicate()
    assert proc.returncode is not None
    return proc.returncode, out.decode(), err.decode()


@pytest.mark.parametrize(
    ("raw", "offset"),
    [
        (b'[machine]\nname = "Fraise \xe9"\naxes = ["X"]\n', 25),  # Latin-1 text
        (bytes(range(256)), 128),  # binary
    ],
)
async def test_serve_machine_file_not_utf8(tmp_path: Path, raw: bytes, offset: int) -> None:
    path = tmp_path / "latin1.toml"
    path.write_bytes(raw)
    code, out, err = await _serve_to_exit("--machine", str(path))
    assert code == 2
    assert out == ""
    lines = err.strip().splitlines()
    assert len(lines) == 1, err
    assert str(path) in lines[0] and f"byte {offset}" in lines[0] and "UTF-8" in lines[0]


async def test_serve_machine_file_with_a_byte_order_mark_is_read_past_it(tmp_path: Path) -> None:
    path = tmp_path / "bom.toml"
    # a bad key on line 4: the message is about it, not about the mark on line 1
    path.write_bytes(b'\xef\xbb\xbf[machine]\nname = "bom"\naxes = ["X"]\nbogus = 1\n')
    code, _out, err = await _serve_to_exit("--machine", str(path))
    assert code == 2
    assert "bogus" in err and "line 1" not in err
