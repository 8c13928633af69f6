"""The gateway's configuration: what ``focas-net gateway CONFIG.toml`` reads (``docs/gateway.md``
gives the file's keys). Frozen values; reading and checking the file comes with them."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Literal

__all__ = [
    "GatewayConfig",
    "GroupIntervals",
    "MachineConfig",
    "MqttSettings",
    "OpcUaSettings",
    "OpcUaUser",
    "WriteGates",
]


@dataclass(frozen=True, slots=True)
class GroupIntervals:
    """Poll intervals in seconds: the fast group, the slow group, and the alarm list."""

    fast: float = 1.0
    slow: float = 10.0
    alarms: float = 1.0


@dataclass(frozen=True, slots=True)
class WriteGates:
    """What may be written to one machine: inclusive ranges of macro variables and of
    parameters, and PMC byte ranges ``(area, first, last)``. Empty: nothing (the default)."""

    macros: tuple[tuple[int, int], ...] = ()
    params: tuple[tuple[int, int], ...] = ()
    pmc: tuple[tuple[str, int, int], ...] = ()


@dataclass(frozen=True, slots=True)
class MachineConfig:
    """One machine: its name (unique; the MQTT topic level and the OPC UA browse name), its
    address, its protocol, the paths to read (None: every path it has), the per-call timeout,
    its poll intervals and its write gates."""

    name: str
    host: str
    port: int = 8193
    protocol: Literal["native", "packed"] = "native"
    paths: tuple[int, ...] | None = None
    timeout: float = 3.0
    groups: GroupIntervals = field(default_factory=GroupIntervals)
    writes: WriteGates = field(default_factory=WriteGates)


@dataclass(frozen=True, slots=True)
class MqttSettings:
    """The MQTT publisher: broker address, topic prefix, session, QoS, the bound of the buffer
    kept while the broker is away (messages), and absolute deadbands by item name."""

    host: str = "127.0.0.1"
    port: int = 1883
    prefix: str = "focas"
    client_id: str | None = None
    username: str | None = None
    password: str | None = None
    qos: int = 1
    keepalive: int = 30
    buffer: int = 10_000
    tls: bool = False
    deadbands: Mapping[str, float] = field(default_factory=dict)


@dataclass(frozen=True, slots=True)
class OpcUaUser:
    """A user the OPC UA server accepts, with its password."""

    name: str
    password: str


@dataclass(frozen=True, slots=True)
class OpcUaSettings:
    """The OPC UA server: its endpoint, its namespace URI, whether anonymous sessions are
    accepted (never on an endpoint beyond the loopback), its users, its certificate and key
    (PEM or DER files; both or neither), and whether the write methods exist at all (read-only
    by default; each machine's :class:`WriteGates` still applies)."""

    endpoint: str = "opc.tcp://127.0.0.1:4840/focas_net/"
    namespace: str = "urn:focas-net:gateway"
    anonymous: bool = True
    users: tuple[OpcUaUser, ...] = ()
    certificate: Path | None = None
    private_key: Path | None = None
    writes: bool = False


@dataclass(frozen=True, slots=True)
class GatewayConfig:
    """The whole file: the machines (after ``--shard``), and each output (None: not used)."""

    machines: tuple[MachineConfig, ...]
    opcua: OpcUaSettings | None = None
    mqtt: MqttSettings | None = None
