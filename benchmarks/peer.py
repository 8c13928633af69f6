"""The peer: pymodbus (optional extra ``bench``), measured in the same modes as the floor.

The server holds 100 holding registers; the client reads 10 of them (20 bytes, the size of the
status payload) with ``read_holding_registers``.

``python -m benchmarks.peer --port 0`` serves until killed and prints
``pymodbus: listening on HOST:PORT`` when ready.
"""

from __future__ import annotations

import argparse
import asyncio
import importlib.util
import logging
from typing import Any

#: Registers per read: 10 x 16 bits = the 20-byte status payload.
REGISTERS = 10
DEVICE_ID = 1


def available() -> bool:
    """True when pymodbus is installed."""
    return importlib.util.find_spec("pymodbus") is not None


class PeerClient:
    """One pymodbus TCP connection with the uniform ``read_status`` / ``close`` surface."""

    def __init__(self, client: Any) -> None:
        self._client = client

    @classmethod
    async def connect(cls, host: str, port: int) -> PeerClient:
        from pymodbus.client import AsyncModbusTcpClient

        client = AsyncModbusTcpClient(host, port=port, timeout=10, retries=0)
        if not await client.connect():
            raise ConnectionError(f"pymodbus could not connect to {host}:{port}")
        return cls(client)

    async def read_status(self) -> list[int]:
        response = await self._client.read_holding_registers(
            0, count=REGISTERS, device_id=DEVICE_ID
        )
        if response.isError():
            raise RuntimeError(f"pymodbus answered {response}")
        registers: list[int] = response.registers
        return registers

    async def close(self) -> None:
        self._client.close()


async def _main(host: str, port: int) -> None:
    from pymodbus.server import ModbusTcpServer
    from pymodbus.simulator import DataType, SimData, SimDevice

    device = SimDevice(
        id=DEVICE_ID,
        simdata=[SimData(address=0, count=100, values=1, datatype=DataType.REGISTERS)],
    )
    server = ModbusTcpServer(device, address=(host, port))
    await server.serve_forever(background=True)
    transport: Any = server.transport
    bound = transport.sockets[0].getsockname()
    print(f"pymodbus: listening on {bound[0]}:{bound[1]}", flush=True)
    await asyncio.Event().wait()


if __name__ == "__main__":
    from benchmarks._loop import run_forever

    parser = argparse.ArgumentParser(description="Run the pymodbus peer server.")
    parser.add_argument("--host", default="127.0.0.1")
    parser.add_argument("--port", type=int, default=0)
    parser.add_argument("--uvloop", action="store_true")
    args = parser.parse_args()
    logging.getLogger("pymodbus").setLevel(logging.ERROR)
    run_forever(_main(args.host, args.port), use_uvloop=args.uvloop)
