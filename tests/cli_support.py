"""Running ``focas-net`` in tests: in-process against one server (:class:`Cli`), or as a
subprocess (:func:`run_focas_net`). Shared by the CLI test modules."""

from __future__ import annotations

import asyncio
import json
import os
import signal
import subprocess
import sys
import weakref
from collections.abc import AsyncIterator
from contextlib import asynccontextmanager
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Protocol

import pytest
from support import IO_TIMEOUT, Served
from support import killed_at_exit as killed_at_exit  # the CLI tests import it from here

from focas_net.cli import EXIT_OK, main

#: Upper bound of one in-process command.
CLI_TIMEOUT = 4 * IO_TIMEOUT
#: Upper bound of one subprocess run (it starts an interpreter).
SUBPROCESS_TIMEOUT = 6 * IO_TIMEOUT


class Cli:
    """Runs ``focas-net`` commands against one server and captures what they print."""

    def __init__(self, served: Served, capsys: pytest.CaptureFixture[str]) -> None:
        self.served = served
        self.capsys = capsys

    async def run(self, *argv: str, port: int | None = None) -> tuple[int, str, str]:
        args = [*argv, "--host", self.served.host, "--port", str(port or self.served.port)]
        self.capsys.readouterr()
        code = await asyncio.wait_for(asyncio.to_thread(main, args), CLI_TIMEOUT)
        out, err = self.capsys.readouterr()
        return code, out, err

    async def ok(self, *argv: str) -> str:
        code, out, err = await self.run(*argv)
        assert code == EXIT_OK, f"{argv}: exit {code}, stderr {err!r}"
        assert err == ""
        return out

    async def json(self, *argv: str) -> Any:
        return json.loads(await self.ok(*argv, "--json"))

    async def fails(self, expected_code: int, *argv: str, prefix: str = "focas-net: ") -> str:
        """Run a failing command; its stderr must be one line starting with ``prefix``
        (``"focas-net"`` lets a usage error's ``focas-net sim fault: error: ...`` pass too),
        stdout empty."""
        code, out, err = await self.run(*argv)
        assert code == expected_code, f"{argv}: exit {code}, stderr {err!r}"
        assert out == ""
        assert err.startswith(prefix) and err.endswith("\n")
        assert err.count("\n") == 1
        return err.strip()


#: Subprocesses at once per event loop: a test that starts many waits for a free slot
#: before it starts the next one, so each run's time bound holds on a busy machine too.
_SLOTS: weakref.WeakKeyDictionary[asyncio.AbstractEventLoop, asyncio.Semaphore] = (
    weakref.WeakKeyDictionary()
)


def _slots() -> asyncio.Semaphore:
    loop = asyncio.get_running_loop()
    if loop not in _SLOTS:
        _SLOTS[loop] = asyncio.Semaphore(os.cpu_count() or 1)
    return _SLOTS[loop]


async def focas_net_process(
    *argv: str, stdout: Any = asyncio.subprocess.PIPE, **kwargs: Any
) -> asyncio.subprocess.Process:
    """``python -m focas_net ARGV`` started (stderr piped; ``stdout`` and the other keywords
    as :func:`asyncio.create_subprocess_exec` takes them); end it with
    :func:`killed_at_exit`."""
    return await asyncio.create_subprocess_exec(
        sys.executable, "-m", "focas_net", *argv,
        stdout=stdout, stderr=asyncio.subprocess.PIPE, **kwargs,
    )  # fmt: skip


async def run_focas_net(*argv: str, seconds: float = SUBPROCESS_TIMEOUT) -> tuple[int, str, str]:
    """``python -m focas_net ARGV``: exit code, stdout, stderr (killed after ``seconds``)."""
    async with _slots():
        async with killed_at_exit(await focas_net_process(*argv)) as proc:
            async with asyncio.timeout(seconds):
                out, err = await proc.communicate()
    assert proc.returncode is not None
    return proc.returncode, out.decode(), err.decode()


class _Listening(Protocol):
    @property
    def port(self) -> int: ...


def at(server: _Listening) -> list[str]:
    """The command line's address of a server listening on 127.0.0.1."""
    return ["--host", "127.0.0.1", "--port", str(server.port)]


def one_line(err: str, prefix: str = "focas-net: ") -> str:
    """The one line of a failure, which starts with ``prefix`` (``"focas-net"`` lets a usage
    error's ``focas-net watch: error: ...`` pass too)."""
    assert err.startswith(prefix) and err.count("\n") == 1, err
    return err.strip()


async def fails(code: int, *argv: str, prefix: str = "focas-net: ") -> str:
    """The one line (:func:`one_line`) a subprocess run that exits with ``code`` prints (it
    prints nothing on standard output)."""
    got, out, err = await run_focas_net(*argv)
    assert got == code, (argv, got, err)
    assert out == ""
    return one_line(err, prefix)


async def ok(*argv: str) -> str:
    """What a subprocess run that succeeds prints (nothing on standard error)."""
    got, out, err = await run_focas_net(*argv)
    assert got == EXIT_OK, (argv, got, err)
    assert err == ""
    return out


@dataclass
class Gateway:
    """A ``focas-net gateway`` process of :func:`gateway_process`: its ready line, and after
    :meth:`stop` its standard output and error."""

    proc: asyncio.subprocess.Process
    ready: str
    out: bytes = b""
    err: bytes = b""

    async def stop(self, signum: signal.Signals = signal.SIGTERM) -> int:
        """Send ``signum``; the exit code once the process ended (within the bound)."""
        self.proc.send_signal(signum)
        async with asyncio.timeout(SUBPROCESS_TIMEOUT):
            self.out, self.err = await self.proc.communicate()
        assert self.proc.returncode is not None
        return self.proc.returncode


@asynccontextmanager
async def gateway_process(*argv: str) -> AsyncIterator[Gateway]:
    """``focas-net gateway *argv`` in a process of its own, once it printed its ready line;
    killed at the end unless :meth:`Gateway.stop` ended it."""
    proc = await focas_net_process("gateway", *argv, env={**os.environ, "PYTHONUNBUFFERED": "1"})
    assert proc.stdout is not None
    async with killed_at_exit(proc):
        async with asyncio.timeout(SUBPROCESS_TIMEOUT):
            ready = (await proc.stdout.readline()).decode()
        yield Gateway(proc, ready)


_ROOT = Path(__file__).resolve().parent.parent

#: Runs the command's entry with a SIGINT delivered while ``focas_net.cli`` is being imported.
INTERRUPTED_IMPORT = """
import builtins, os, signal, sys
real = builtins.__import__
def importing(name, *args, **kwargs):
    if name == "focas_net.cli":
        os.kill(os.getpid(), signal.SIGINT)
    return real(name, *args, **kwargs)
builtins.__import__ = importing
import focas_net_entry
sys.argv = ["focas-net", "--version"]
sys.exit(focas_net_entry.main())
"""


def run_entry(code: str, *, ignore_sigint: bool = False) -> subprocess.CompletedProcess[str]:
    """Run ``code`` in a new interpreter from the project's folder (with SIGINT ignored, as
    a shell leaves it to a background job, when ``ignore_sigint``)."""
    prefix = "import signal; signal.signal(signal.SIGINT, signal.SIG_IGN)\n"
    return subprocess.run(
        [sys.executable, "-c", (prefix if ignore_sigint else "") + code],
        capture_output=True,
        text=True,
        cwd=_ROOT,
        timeout=SUBPROCESS_TIMEOUT,
        check=False,
    )
