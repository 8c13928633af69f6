"""The ``[[path]]`` tables of a machine file: a machine of several paths (schema in
``docs/machine-file.md``).

A file without ``[[path]]`` describes a machine of one path, its axes in ``machine.axes``, its
panel, motion figures and programs in the top-level ``[panel]``, ``[motion]`` and
``[[program]]``. A file with ``[[path]]`` (1..10 of them) describes each path in its table:
``axes``, ``name``, ``kind``, ``spindles``, and the path's own ``[path.panel]``,
``[path.motion]`` and ``[[path.program]]``; those four keys may then not be given outside
the paths. Errors name the key as ``path[1].axes[0]`` (the first path is ``path[0]``, as a
TOML array counts).
"""

from __future__ import annotations

from pathlib import Path
from typing import Any, Final

from ._paths import MAX_PATHS, PATH_KINDS, PathSpec
from .machinefile import _axes, _Ctx, _int, _list, _motion, _only, _panel, _programs, _str, _table

__all__ = ["PATH_KEYS", "path_specs"]

#: The keys of a ``[[path]]`` table.
PATH_KEYS: Final = ("name", "kind", "axes", "spindles", "panel", "motion", "program")
#: What a machine of ``[[path]]`` tables gives per path, not outside them.
_PER_PATH: Final = ("panel", "motion", "program")


def path_specs(root: _Ctx, top: dict[str, Any], base: Path | None) -> list[PathSpec] | None:
    """The paths of a machine file's ``top`` table, None when it has no ``[[path]]`` (a
    machine of one path). A path's kind is the file's ``sysinfo.mt_type`` unless it gives
    one ("M" when that is neither)."""
    if "path" not in top:
        return None
    sysinfo = top.get("sysinfo")
    given = sysinfo.get("mt_type") if isinstance(sysinfo, dict) else None
    default_kind = given.strip() if isinstance(given, str) else "M"
    if default_kind not in PATH_KINDS:
        default_kind = "M"
    ctx = root.sub("path")
    for key in _PER_PATH:
        if key in top:
            root.sub(key).fail(f"a machine of [[path]] tables gives {key} in each [[path]]")
    head = top.get("machine", {})
    if isinstance(head, dict) and "axes" in head:
        root.sub("machine").sub("axes").fail(
            "a machine of [[path]] tables gives axes in each [[path]]"
        )
    tables = _list(ctx, top["path"])
    if not 1 <= len(tables) <= MAX_PATHS:
        ctx.fail(f"a machine has 1..{MAX_PATHS} paths, got {len(tables)}")
    specs: list[PathSpec] = []
    owner: dict[str, int] = {}
    names: dict[str, int] = {}
    for i, raw in enumerate(tables):
        c = ctx.sub(i)
        t = _table(c, raw)
        _only(c, t, PATH_KEYS)
        if "axes" not in t:
            c.sub("axes").fail("missing (the path's axis names)")
        if t["axes"] == []:
            c.sub("axes").fail("a path has at least one axis")
        axes = _axes(c.sub("axes"), t["axes"])
        for j, axis in enumerate(axes):
            if axis in owner:
                c.sub("axes").sub(j).fail(f"axis {axis!r} is path[{owner[axis]}]'s already")
            owner[axis] = i
        name = _str(c.sub("name"), t.get("name", f"PATH{i + 1}")).strip()
        if not name or not name.isascii() or not name.isprintable() or len(name) > 32:
            c.sub("name").fail(f"a path's name is 1..32 printable ASCII characters: {name!r}")
        if name in names:
            c.sub("name").fail(f"{name!r} is path[{names[name]}]'s name already")
        names[name] = i
        kind = _str(c.sub("kind"), t.get("kind", default_kind)).strip().upper()
        if kind not in PATH_KINDS:
            c.sub("kind").fail(f'must be "M" (machining centre) or "T" (lathe), got {kind!r}')
        spindles = _int(c.sub("spindles"), t.get("spindles", 1), (1, 8))
        texts, main = _programs(c.sub("program"), t.get("program", []), base)
        specs.append(
            PathSpec(
                tuple(axes),
                name=name,
                kind=kind,
                spindles=spindles,
                programs=tuple(texts),
                main_program=main,
                panel=_panel(c.sub("panel"), t.get("panel", {})),
                motion=_motion(c.sub("motion"), t.get("motion", {}), len(axes)),
            )
        )
    return specs
