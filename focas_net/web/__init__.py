"""The web dashboard of the simulator (``focas-net serve --web``, ``docs/web.md``).

Pure parts: :mod:`.view` (machines as JSON-able dicts), :mod:`.operations` (page actions as
machine operations, with the machine's checks), :mod:`.address` (``[HOST:]PORT``),
:mod:`.broadcast` (one producer of live frames, bounded per-page queues). The thin aiohttp
shell, :mod:`.shell`, imports aiohttp only when a :class:`Dashboard` starts.
"""

from .address import DEFAULT_WEB_HOST, is_loopback, parse_web_address
from .broadcast import DEFAULT_INTERVAL, FLEET, Broadcaster, Subscription, Topic, machine_topic
from .operations import (
    ACTION_KEYS,
    ACTIONS,
    FORCED_PMC_AREAS,
    ActionError,
    Station,
    action_args,
    decimal_number,
    no_twice,
    perform,
    refusal,
    shown,
    whole_number,
)
from .shell import STATIC_DIR, Dashboard, WebUnavailableError, stations_of
from .view import (
    HISTORY_SHOWN,
    MACRO_SEARCH_CAP,
    PATH_POINTS,
    PMC_ROW_BYTES,
    JsonDict,
    PathTrail,
    fleet_view,
    machine_tile,
    machine_view,
    macro_note,
    macro_range,
    macro_rows,
    param_rows,
    param_text,
    pmc_address,
    pmc_window,
    status_fields,
)

__all__ = [
    "ACTIONS",
    "ACTION_KEYS",
    "DEFAULT_INTERVAL",
    "DEFAULT_WEB_HOST",
    "FLEET",
    "FORCED_PMC_AREAS",
    "HISTORY_SHOWN",
    "MACRO_SEARCH_CAP",
    "PATH_POINTS",
    "PMC_ROW_BYTES",
    "STATIC_DIR",
    "ActionError",
    "Broadcaster",
    "Dashboard",
    "JsonDict",
    "PathTrail",
    "Station",
    "Subscription",
    "Topic",
    "WebUnavailableError",
    "action_args",
    "decimal_number",
    "fleet_view",
    "is_loopback",
    "machine_tile",
    "machine_topic",
    "machine_view",
    "macro_note",
    "macro_range",
    "macro_rows",
    "no_twice",
    "param_rows",
    "param_text",
    "parse_web_address",
    "perform",
    "pmc_address",
    "pmc_window",
    "refusal",
    "shown",
    "stations_of",
    "status_fields",
    "whole_number",
]
