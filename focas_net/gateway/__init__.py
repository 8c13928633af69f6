"""A gateway from FANUC controls to OPC UA and MQTT (``focas-net gateway CONFIG.toml``):
see ``docs/gateway.md``."""

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
    "Group",
    "Item",
    "MachineShape",
    "PathShape",
    "Sample",
    "Scope",
    "Sink",
    "Unit",
    "Value",
    "Writer",
    "item",
]
