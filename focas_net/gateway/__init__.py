"""A gateway from FANUC controls to OPC UA and MQTT (``focas-net gateway CONFIG.toml``):
see ``docs/gateway.md``."""

from .config import (
    GatewayConfig,
    GroupIntervals,
    MachineConfig,
    MqttSettings,
    OpcUaSettings,
    OpcUaUser,
    WriteGates,
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

__all__ = [
    "ITEMS",
    "AlarmChange",
    "GatewayConfig",
    "Group",
    "GroupIntervals",
    "Item",
    "MachineConfig",
    "MachineShape",
    "MqttSettings",
    "OpcUaSettings",
    "OpcUaUser",
    "PathShape",
    "Sample",
    "Scope",
    "Sink",
    "Unit",
    "Value",
    "WriteGates",
    "Writer",
    "item",
]
