"""Running a script of ``examples/`` as a user runs it: a subprocess with its arguments, its
exit code and output (killed after a bound), and the address arguments of a served machine."""

from __future__ import annotations

import asyncio
import sys
from pathlib import Path

from support import IO_TIMEOUT, Served, killed_at_exit

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"
#: The scripts of ``examples/``; a module named with a leading ``_`` (``_options.py``) is
#: what they share, imported by them and run by none.
SCRIPTS = sorted(p.name for p in EXAMPLES.glob("*.py") if not p.name.startswith("_"))
#: Upper bound of one example run (they all finish by themselves well before).
RUN_TIMEOUT = 12 * IO_TIMEOUT


async def run_example(name: str, *args: str) -> tuple[int, str, str]:
    """Run ``examples/<name>`` with ``args``; its exit code, stdout and stderr."""
    proc = await asyncio.create_subprocess_exec(
        sys.executable, str(EXAMPLES / name), *args,
        stdout=asyncio.subprocess.PIPE, stderr=asyncio.subprocess.PIPE,
    )  # fmt: skip
    async with killed_at_exit(proc):
        out, err = await asyncio.wait_for(proc.communicate(), RUN_TIMEOUT)
    assert proc.returncode is not None
    return proc.returncode, out.decode(), err.decode()


def port_args(served: Served) -> list[str]:
    """``--host H --port P`` of ``served``."""
    return ["--host", served.host, "--port", str(served.port)]
