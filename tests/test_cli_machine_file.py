"""``focas-net serve --machine`` with files it cannot use (the wrong encoding, a name no machine
can have): one line, exit 2."""

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


@pytest.mark.parametrize(
    ("name", "fleet", "words"),
    [
        ("cell\\n7", "1", "machine.name: a machine's name is 1..64 printable characters: '\\n'"),
        ("m" * 5000, "1", "machine.name: a machine's name is 1..64 printable characters, not 5000"),
        ("m" * 64, "2", "--fleet 2: a machine's name is 1..64 printable characters, not 66"),
    ],
)
async def test_serve_refuses_a_name_a_machine_cannot_have(
    tmp_path: Path, name: str, fleet: str, words: str
) -> None:
    path = tmp_path / "named.toml"
    path.write_text(f'[machine]\nname = "{name}"\naxes = ["X"]\n', encoding="utf-8")
    code, out, err = await _serve_to_exit("--machine", str(path), "--fleet", fleet)
    assert (code, out) == (2, "")
    lines = err.strip().splitlines()
    assert len(lines) == 1 and words in lines[0], err
