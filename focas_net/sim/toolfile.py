"""The ``[[tools]]`` tables of a machine file: each path's tool offsets, work zero offsets and
tool life groups (schema in ``docs/machine-file.md``; the model: :mod:`._tools`).

Each table names its ``path`` (1 unless given; one table per path). Lengths are millimetres
(an integer or a decimal of at most 3 places), kept in least input increments; what the
values mean and their ranges are the machine's rules, checked here for the path's kind and
axes so that each refusal names its key.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from decimal import Decimal
from typing import Any, Final

from ._paths import MAX_PATHS
from ._tool_ops import work_problem
from ._tools import (
    LIFE_TYPES,
    MAX_GROUPS,
    MAX_TOOL_OFFSETS,
    MAX_TOOLS_PER_GROUP,
    OFFSET_TYPES,
    WORK_OFFSET_NAMES,
    LifeTool,
    ToolGroup,
    ToolLife,
    ToolsSpec,
    listed_elsewhere,
    listed_twice,
    offset_problem,
    repeated_tool,
)
from .filecheck import _Ctx, _int, _list, _only, _str, _table

__all__ = ["TOOLS_KEYS", "tool_specs"]

#: The keys of a ``[[tools]]`` table.
TOOLS_KEYS: Final = (
    "path",
    "offsets",
    "offset",
    "work",
    "max_groups",
    "max_tools",
    "ignore_number",
    "group",
)
_OFFSET_KEYS: Final = ("number", *sorted({n for names in OFFSET_TYPES.values() for n in names}))
_GROUP_KEYS: Final = ("number", "life", "type", "count", "tools")
_TOOL_KEYS: Final = ("t", "h", "d")
_MAX_T: Final = 99_999_999


def _mm(ctx: _Ctx, value: Any) -> int:
    """Millimetres (at most 3 decimals) as least input increments (0.001 mm)."""
    if isinstance(value, bool) or not isinstance(value, int | float):
        ctx.fail(f"must be a number of millimetres, got {type(value).__name__}")
    if isinstance(value, float) and not math.isfinite(value):
        ctx.fail(f"must be a finite number of millimetres, got {value}")
    exact = Decimal(repr(value)) if isinstance(value, float) else Decimal(value)
    scaled = exact.scaleb(3)
    if scaled != scaled.to_integral_value():
        ctx.fail(f"{value} has more than 3 decimals (0.001 mm is the least increment)")
    return int(scaled)


def tool_specs(ctx: _Ctx, value: Any, shapes: Sequence[tuple[str, int]]) -> dict[int, ToolsSpec]:
    """Every ``[[tools]]`` table of a machine file whose paths are ``shapes`` (each path's
    kind, ``"M"`` or ``"T"``, and number of axes), by path number; a value the machine would
    refuse is refused naming its key, in the machine's words."""
    paths = len(shapes)
    specs: dict[int, ToolsSpec] = {}
    for i, raw in enumerate(_list(ctx, value)):
        c = ctx.sub(i)
        t = _table(c, raw)
        _only(c, t, TOOLS_KEYS)
        path = _int(c.sub("path"), t.get("path", 1), (1, MAX_PATHS))
        if path > paths:
            c.sub("path").fail(f"the machine has no path {path} (its paths: 1..{paths})")
        if path in specs:
            c.sub("path").fail(f"path {path} has a [[tools]] table already")
        kind, n_axes = shapes[path - 1]
        offsets = _int(c.sub("offsets"), t.get("offsets", 64), (1, MAX_TOOL_OFFSETS))
        values: dict[tuple[int, str], int] = {}
        for j, entry in enumerate(_list(c.sub("offset"), t.get("offset", []))):
            oc = c.sub("offset").sub(j)
            o = _table(oc, entry)
            _only(oc, o, _OFFSET_KEYS)
            if "number" not in o:
                oc.sub("number").fail("missing (the offset number)")
            number = _int(oc.sub("number"), o["number"], (1, offsets))
            for name, v in o.items():
                if name == "number":
                    continue
                key = (number, name)
                if key in values:
                    oc.sub(name).fail(f"offset {number} {name} is given twice")
                tip = name == "tip"
                values[key] = _int(oc.sub(name), v, (0, 9)) if tip else _mm(oc.sub(name), v)
                problem = offset_problem(kind, number, name, values[key])
                if problem is not None:
                    oc.sub(name).fail(problem)
        work: dict[str, list[int]] = {}
        w = _table(c.sub("work"), t.get("work", {}))
        _only(c.sub("work"), w, WORK_OFFSET_NAMES)
        for name, row in w.items():
            wc = c.sub("work").sub(name)
            work[name] = [_mm(wc.sub(k), v) for k, v in enumerate(_list(wc, row))]
            problem = work_problem(name, work[name], n_axes)
            if problem is not None:
                wc.fail(problem)
        gc = c.sub("group")
        groups = [_group(gc.sub(j), g) for j, g in enumerate(_list(gc, t.get("group", [])))]
        ignore = _int(c.sub("ignore_number"), t.get("ignore_number", 0), (0, _MAX_T))
        for j, group in enumerate(groups):
            repeated = repeated_tool(group)
            if repeated is not None:
                gc.sub(j).sub("tools").sub(repeated[0]).fail(repeated[1])
        for j, group in enumerate(groups if not ignore else ()):
            shared = listed_elsewhere(groups[:j], group)
            if shared is not None:
                index, other = shared
                tool = group.tools[index].number
                gc.sub(j).sub("tools").sub(index).fail(listed_twice(tool, other))
        max_groups = _int(c.sub("max_groups"), t.get("max_groups", 16), (1, MAX_GROUPS))
        max_tools = _int(c.sub("max_tools"), t.get("max_tools", 4), (1, MAX_TOOLS_PER_GROUP))
        life = ToolLife(max_groups, max_tools, (), ignore)
        for j, group in enumerate(groups):  # the machine's checks, naming the group's key
            try:
                life.add(group)
            except ValueError as exc:
                gc.sub(j).fail(str(exc))
        specs[path] = ToolsSpec(
            offsets=offsets,
            offset_values=values,
            work=work,
            max_groups=max_groups,
            max_tools=max_tools,
            groups=tuple(groups),
            ignore=ignore,
        )
    return specs


def _group(ctx: _Ctx, raw: Any) -> ToolGroup:
    g = _table(ctx, raw)
    _only(ctx, g, _GROUP_KEYS)
    for key in ("number", "life", "tools"):
        if key not in g:
            ctx.sub(key).fail("missing")
    kind = _str(ctx.sub("type"), g.get("type", "count")).strip().lower()
    if kind not in LIFE_TYPES:
        ctx.sub("type").fail(f'must be "count" or "time", got {kind!r}')
    tools: list[LifeTool] = []
    for k, entry in enumerate(_list(ctx.sub("tools"), g["tools"])):
        tc = ctx.sub("tools").sub(k)
        if isinstance(entry, dict):
            _only(tc, entry, _TOOL_KEYS)
            if "t" not in entry:
                tc.sub("t").fail("missing (the tool's T number)")
            tools.append(
                LifeTool(
                    _int(tc.sub("t"), entry["t"], (1, _MAX_T)),
                    _int(tc.sub("h"), entry.get("h", 0), (0, _MAX_T)),
                    _int(tc.sub("d"), entry.get("d", 0), (0, _MAX_T)),
                )
            )
        else:
            tools.append(LifeTool(_int(tc, entry, (1, _MAX_T))))
    return ToolGroup(
        _int(ctx.sub("number"), g["number"], (1, MAX_GROUPS)),
        _int(ctx.sub("life"), g["life"], (1, 9999)),
        kind,
        _int(ctx.sub("count"), g.get("count", 0), (0, 9999)),
        tools,
    )
