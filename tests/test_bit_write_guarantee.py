"""What a bit write guarantees, as the docs state it: the bit writes of one client, from any
number of tasks, never lose one another (the example of docs/client.md runs); the lock is the
client's, so a bit written by another client between a read and a write is undone."""

from __future__ import annotations

import asyncio
import re
import sys
from pathlib import Path

import pytest
from support import IO_TIMEOUT, serving
from virtual_net import VirtualLoop

from focas_net.client import FocasClient, NativeClient
from focas_net.protocol import FaultKind
from focas_net.server import Fault, FocasServer
from focas_net.sim import default_machine

ROOT = Path(__file__).resolve().parent.parent
#: How late the server answers the first client's read in the two-client test, in ms.
DELAY_MS = 1000


async def test_the_shared_client_example_of_the_docs_loses_no_bit(tmp_path: Path) -> None:
    blocks = re.findall(r"```python\n(.*?)```", (ROOT / "docs" / "client.md").read_text(), re.S)
    (example,) = [b for b in blocks if "asyncio.TaskGroup" in b]
    async with serving(default_machine()) as served:
        script = tmp_path / "shared.py"
        script.write_text(example.replace('"127.0.0.1", 8193', f'"{served.host}", {served.port}'))
        proc = await asyncio.create_subprocess_exec(
            sys.executable, str(script), stdout=asyncio.subprocess.PIPE
        )
        async with asyncio.timeout(30 * IO_TIMEOUT):
            out, _ = await proc.communicate()
        assert proc.returncode == 0
        assert out.decode().splitlines() == ["R100 = 11111110"]
        assert served.machine.read_pmc("R", 100, 1) == b"\xfe"


def test_the_lock_is_the_clients_a_second_client_can_undo_a_bit() -> None:
    """On a clock the test steps (``virtual_net``): the server answers the first client's read
    of R100 late, so the second client's bit write falls between that read and the first
    client's write, whatever the machine's load."""
    loop = VirtualLoop()

    async def main() -> None:
        machine = default_machine()
        async with FocasServer(machine, host="127.0.0.1", port=0, idle_timeout=0) as server:
            host, port = server.listeners[0].address
            async with (
                FocasClient(host, port, timeout=IO_TIMEOUT) as first,
                NativeClient(host, port, timeout=IO_TIMEOUT) as second,
            ):
                faults = server.listeners[0].faults
                assert faults.arm(Fault(FaultKind.DELAY, DELAY_MS, 1)) == 0
                writing = asyncio.ensure_future(first.write_pmc_bit("R", 100, 0, True))
                for _ in range(1000):  # until the read is taken; its answer waits DELAY_MS
                    if not faults:
                        break
                    await asyncio.sleep(0)
                assert not faults
                await second.write_pmc_bit("R", 100, 1, True)  # no machine time passes
                assert machine.read_pmc("R", 100, 1) == b"\x02"
                await writing
                # the first client wrote back the byte it had read, with its bit: R100.1 is lost
                assert machine.read_pmc("R", 100, 1) == b"\x01"
                # the bit writes of one client wait for one another: none is lost
                await asyncio.gather(*(first.write_pmc_bit("R", 101, b, True) for b in range(8)))
                assert machine.read_pmc("R", 101, 1) == b"\xff"

    try:
        loop.run_until_complete(main())
    finally:
        loop.close()


def test_the_api_docs_say_whose_lock_it_is() -> None:
    protocol = (ROOT / "docs" / "protocol.md").read_text()
    section = protocol[protocol.index("## 6.") : protocol.index("## 7.")]
    (bullet,) = [b for b in section.split("\n- ") if b.startswith("**Bit writes**")]
    texts = [" ".join(bullet.split())]
    for client in (FocasClient, NativeClient):
        for method in (client.write_pmc_bit, client.write_param_bit):
            assert method.__doc__ is not None
            texts.append(" ".join(method.__doc__.split()))
    for text in texts:
        assert "never lose one another" in text
        assert "this client" in text or "of one client" in text, text
        assert "FANUC's library" in text and "no lock" in text, text


async def test_a_bits_value_is_true_false_one_or_zero_on_both_clients() -> None:
    """``2``, ``"0"`` or ``None`` is refused before anything is sent, rather than counting as
    set because it is truthy; ``1`` and ``0`` set and clear."""
    machine = default_machine()
    machine.set_panel(mode=0, pwe=1)
    async with serving(machine) as served:
        for kind in (FocasClient, NativeClient):
            async with kind(served.host, served.port, timeout=IO_TIMEOUT) as cnc:
                for bad in (2, -1, "0", "1", None, 1.0):
                    with pytest.raises(TypeError, match="a bit's value is True, False, 1 or 0"):
                        await cnc.write_pmc_bit("R", 100, 3, bad)  # type: ignore[arg-type]
                    with pytest.raises(TypeError, match=repr(bad).replace("(", r"\(")):
                        await cnc.write_param_bit(1815, 3, bad, axis=1)  # type: ignore[arg-type]
                assert machine.read_pmc("R", 100, 1) == b"\x00"
                await cnc.write_pmc_bit("R", 100, 3, 1)
                assert machine.read_pmc("R", 100, 1) == b"\x08"
                await cnc.write_pmc_bit("R", 100, 3, 0)
                assert machine.read_pmc("R", 100, 1) == b"\x00"
                with pytest.raises(ValueError, match=r"bit 9 is outside 0\.\.7: parameter 20 is 1"):
                    await cnc.write_param_bit(20, 9, True)
