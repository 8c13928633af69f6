"""The README stays true: its opening commands, its client example, and its command-line
session, which must be what the built-in machine prints."""

from __future__ import annotations

import asyncio
import importlib
import re
import shlex
import sys
from pathlib import Path

import pytest

from focas_net import FocasServer, default_machine
from focas_net.cli import main

README = Path(__file__).resolve().parent.parent / "README.md"


def _blocks(lang: str) -> list[str]:
    return re.findall(rf"```{lang}\n(.*?)```", README.read_text(), flags=re.S)


def test_readme_opens_with_the_two_commands() -> None:
    text = README.read_text()
    first = _blocks("sh")[0].strip().splitlines()
    assert text.index("```sh") < text.index("\n## ")  # before any section
    assert len(first) == 2
    serve, tests = first
    assert "pip install -e ." in serve and serve.endswith("focas-net serve")
    assert "pip install -e '.[test]'" in tests and tests.endswith("python -m pytest")


async def test_readme_client_example_runs(tmp_path: Path) -> None:
    (example,) = [b for b in _blocks("python") if "asyncio.run(main())" in b]
    async with FocasServer(default_machine(), port=0) as server:
        host, port = server.addresses[0]
        script = tmp_path / "example.py"
        script.write_text(example.replace('"127.0.0.1", 8193', f'"{host}", {port}'))
        proc = await asyncio.create_subprocess_exec(
            sys.executable,
            str(script),
            stdout=asyncio.subprocess.PIPE,
            stderr=asyncio.subprocess.PIPE,
        )
        async with asyncio.timeout(30):
            out, err = await proc.communicate()
    assert proc.returncode == 0, err.decode()
    lines = out.decode().splitlines()
    assert lines[0] == "mode MEM run ****"
    assert "#500 = 12.345" in lines
    assert server.machines[0].read_pmc("R", 100, 1) == bytes([0b1000])


def test_every_class_the_readme_calls_is_importable_where_it_says() -> None:
    """A class the README calls (``ManualClock()``) comes from the module the README imports
    it from, or, when the README imports it nowhere, from ``focas_net`` itself."""
    text = README.read_text()
    spans = re.findall(r"`([^`\n]+)`", text) + _blocks("python")
    called = {name for span in spans for name in re.findall(r"\b([A-Z]\w+)\(", span)}
    imported = {
        name.strip(): module
        for module, names in re.findall(r"from (focas_net[\w.]*) import ([\w, ]+)", text)
        for name in names.split(",")
    }
    assert "ManualClock" in called
    for name in sorted(called):
        module = importlib.import_module(imported.get(name, "focas_net"))
        assert hasattr(module, name), f"the README calls {name}, not in {module.__name__}"


def _session() -> list[tuple[list[str], list[str]]]:
    """The commands of the README's ``console`` block and the lines each prints."""
    (block,) = _blocks("console")
    steps: list[tuple[list[str], list[str]]] = []
    for line in block.splitlines():
        if line.startswith("$ focas-net "):
            steps.append((shlex.split(line.removeprefix("$ focas-net ")), []))
        else:
            assert steps, f"output before any command: {line!r}"
            steps[-1][1].append(line)
    return steps


def test_readme_session_has_commands_and_outputs() -> None:
    steps = _session()
    assert len(steps) >= 15
    assert all(lines for _, lines in steps)


async def test_readme_cli_examples_are_what_the_built_in_machine_prints(
    capsys: pytest.CaptureFixture[str],
) -> None:
    async with FocasServer(default_machine(), host="127.0.0.1", port=0) as server:
        _host, port = server.addresses[0]
        for argv, expected in _session():
            capsys.readouterr()
            code = await asyncio.wait_for(asyncio.to_thread(main, [*argv, "--port", str(port)]), 30)
            out, err = capsys.readouterr()
            printed = (out + err).rstrip("\n").split("\n")
            assert printed == expected, f"focas-net {' '.join(argv)} (exit {code})"
            assert (code == 0) == (err == ""), f"focas-net {' '.join(argv)}: exit {code}"
