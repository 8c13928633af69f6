"""A Mosquitto broker for the MQTT tests, and a subscriber to it. The broker is Debian's
``mosquitto``, started on 127.0.0.1 on a free port from a config file in the test's folder
(anonymous, no persistence), stopped at the end, and restartable on the same port; tests skip
with a message when the binary is missing (``.ci/run`` installs it)."""

from __future__ import annotations

import asyncio
import shutil
from collections.abc import AsyncIterator, Callable
from contextlib import asynccontextmanager
from dataclasses import dataclass, field
from pathlib import Path

import aiomqtt
import pytest
from support import free_port

__all__ = ["BOUND", "Broker", "Seen", "broker", "mosquitto_binary", "subscriber"]

#: A failure bound for waiting on the broker: never a figure a test asserts.
BOUND = 20.0

#: Where Debian puts the broker (not on root's PATH).
_DEBIAN = Path("/usr/sbin/mosquitto")


def mosquitto_binary() -> Path | None:
    found = shutil.which("mosquitto")
    if found:
        return Path(found)
    return _DEBIAN if _DEBIAN.exists() else None


class Broker:
    """One broker process; :meth:`stop` and :meth:`start` again keep its port."""

    def __init__(self, binary: Path, folder: Path) -> None:
        self.binary = binary
        self.host = "127.0.0.1"
        self.port = free_port()
        self.config = folder / "mosquitto.conf"
        self.log = folder / "mosquitto.log"
        self.config.write_text(
            f"listener {self.port} 127.0.0.1\n"
            "allow_anonymous true\n"
            "persistence false\n"
            # as root the broker would switch to the mosquitto user; the test's user runs it
            "user root\n"
        )
        self._process: asyncio.subprocess.Process | None = None

    async def start(self) -> None:
        """Start the broker and wait (at most 10 s) until it accepts connections."""
        assert self._process is None
        with self.log.open("ab") as log:
            self._process = await asyncio.create_subprocess_exec(
                str(self.binary), "-c", str(self.config), stdout=log, stderr=log
            )
        for _ in range(200):
            if self._process.returncode is not None:
                raise RuntimeError(f"mosquitto ended: {self.log.read_text()[-2000:]}")
            try:
                _reader, writer = await asyncio.open_connection(self.host, self.port)
            except OSError:
                await asyncio.sleep(0.05)
                continue
            writer.close()
            await writer.wait_closed()
            return
        raise RuntimeError(f"mosquitto did not listen on {self.port}")

    async def stop(self) -> None:
        """Stop the broker (SIGTERM, SIGKILL after 5 s) and wait for it."""
        process, self._process = self._process, None
        if process is None:
            return
        process.terminate()
        try:
            await asyncio.wait_for(process.wait(), 5)
        except TimeoutError:
            process.kill()
            await process.wait()


@pytest.fixture
async def broker(tmp_path: Path) -> AsyncIterator[Broker]:
    """A running broker, stopped at the end of the test."""
    binary = mosquitto_binary()
    if binary is None:
        pytest.skip("mosquitto is not installed (apt-get install mosquitto; .ci/run does)")
    running = Broker(binary, tmp_path)
    try:
        await running.start()
        yield running
    finally:
        await running.stop()


@dataclass
class Seen:
    """What a subscriber to ``focas/#`` received: every message in order, and the latest
    payload (and retain flag) per topic."""

    messages: list[aiomqtt.Message] = field(default_factory=list)
    changed: asyncio.Event = field(default_factory=asyncio.Event)

    def latest(self, topic: str) -> bytes | None:
        for m in reversed(self.messages):
            if m.topic.value == topic:
                assert isinstance(m.payload, bytes)
                return m.payload
        return None

    def retained(self, topic: str) -> bool:
        return any(m.topic.value == topic and m.retain for m in self.messages)

    def on(self, topic: str) -> list[bytes]:
        found = [m.payload for m in self.messages if m.topic.value == topic]
        assert all(isinstance(p, bytes) for p in found)
        return found

    async def until(self, condition: Callable[[Seen], bool]) -> None:
        """Wait until ``condition`` holds (failing after :data:`BOUND` seconds)."""
        async with asyncio.timeout(BOUND):
            for _ in range(100_000):
                if condition(self):
                    return
                self.changed.clear()
                await self.changed.wait()
        raise AssertionError("the condition never held")


@asynccontextmanager
async def subscriber(broker: Broker, topic: str = "focas/#") -> AsyncIterator[Seen]:
    seen = Seen()
    async with aiomqtt.Client(broker.host, broker.port) as client:
        await client.subscribe(topic, qos=1)

        async def collect() -> None:
            async for message in client.messages:
                seen.messages.append(message)
                seen.changed.set()

        task = asyncio.create_task(collect())
        try:
            yield seen
        finally:
            task.cancel()
            await asyncio.gather(task, return_exceptions=True)
