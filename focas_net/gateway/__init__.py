"""A gateway from FANUC controls to OPC UA and MQTT (``focas-net gateway CONFIG.toml``):
see ``docs/gateway.md``."""

from ._keys import ConfigError
from .config import (
    MAX_FLEET,
    MIN_INTERVAL,
    GatewayConfig,
    GroupIntervals,
    MachineConfig,
    MqttSettings,
    OpcUaSettings,
    OpcUaUser,
    WriteGates,
    load_config,
    parse_config,
    shard,
)
from .model import (
    ITEMS,
    AlarmChange,
    Group,
    Item,
    MachineShape,
    PathShape,
    Sample,
    Scope,
    Sink,
    Unit,
    Value,
    Writer,
    item,
)
from .poller import DEFAULT_POLICY, Poller, client_for, reason_of
from .run import EXTRA, Gateway, MissingExtra, outputs
from .writer import GatedWriter

__all__ = [
    "DEFAULT_POLICY",
    "EXTRA",
    "ITEMS",
    "MAX_FLEET",
    "MIN_INTERVAL",
    "AlarmChange",
    "ConfigError",
    "GatedWriter",
    "Gateway",
    "GatewayConfig",
    "Group",
    "GroupIntervals",
    "Item",
    "MachineConfig",
    "MachineShape",
    "MissingExtra",
    "MqttSettings",
    "OpcUaSettings",
    "OpcUaUser",
    "PathShape",
    "Poller",
    "Sample",
    "Scope",
    "Sink",
    "Unit",
    "Value",
    "WriteGates",
    "Writer",
    "client_for",
    "item",
    "load_config",
    "outputs",
    "parse_config",
    "reason_of",
    "shard",
]
