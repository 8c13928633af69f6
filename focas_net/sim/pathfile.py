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

from focas_net._typed import os_words, program_file_text

from ._base import n_values
from ._identity import axes_problem, axis_name_problem
from ._paths import MAX_PATHS, PATH_KINDS, PathSpec, kind_of
from ._status import (
    AUT_MODES,
    MOTION_NUMBERS,
    MotionData,
    Panel,
    panel_conflict,
    panel_mode,
    unknown_mode,
)
from .filecheck import (
    _I32,
    _ascii,
    _bool,
    _Ctx,
    _int,
    _list,
    _only,
    _str,
    _table,
)
from .nc import ProgramError, ProgramStore, parse_program

__all__ = ["PATH_KEYS", "path_specs"]

#: The keys of a ``[[path]]`` table.
PATH_KEYS: Final = ("name", "kind", "axes", "spindles", "panel", "motion", "program")
#: What a machine of ``[[path]]`` tables gives per path, not outside them.
_PER_PATH: Final = ("panel", "motion", "program")


def path_specs(root: _Ctx, top: dict[str, Any], base: Path | None) -> list[PathSpec] | None:
    """The paths of a machine file's ``top`` table, None when it has no ``[[path]]`` (a
    machine of one path). A path's kind is the one of the file's ``sysinfo.mt_type``
    (:func:`kind_of`) unless it gives one."""
    if "path" not in top:
        return None
    sysinfo = top.get("sysinfo")
    given = sysinfo.get("mt_type") if isinstance(sysinfo, dict) else None
    default_kind = kind_of(given) if isinstance(given, str) else "M"
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
        typed = _str(c.sub("name"), t.get("name", f"PATH{i + 1}"))
        name = typed.strip()
        if not name or not name.isascii() or not name.isprintable() or len(name) > 32:
            c.sub("name").fail(f"a path's name is 1..32 printable ASCII characters: {typed!r}")
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


# -- what a path has: read for the machine of one path too ---------------------------------


def _axes(ctx: _Ctx, value: Any) -> list[str]:
    names: list[str] = []
    for i, raw in enumerate(_list(ctx, value)):
        name = _ascii(ctx.sub(i), raw)
        problem = axis_name_problem(name, names)
        if problem is not None:
            ctx.sub(i).fail(problem)
        names.append(name)
    problem = axes_problem(names)
    if problem is not None:
        ctx.fail(problem)
    return names


def _panel(ctx: _Ctx, value: Any) -> Panel:
    t = _table(ctx, value)
    _only(ctx, t, ("mode", "pwe", "emergency", "run"))
    mode_v = t.get("mode", "MEM")
    c = ctx.sub("mode")
    if isinstance(mode_v, str):
        try:
            mode = panel_mode(mode_v)
        except ValueError as exc:
            c.fail(str(exc))
    else:
        mode = _int(c, mode_v)
        if mode not in AUT_MODES:
            c.fail(unknown_mode(mode))
    pwe = int(_bool(ctx.sub("pwe"), t.get("pwe", False)))
    emergency = int(_bool(ctx.sub("emergency"), t.get("emergency", False)))
    run = _int(ctx.sub("run"), t.get("run", 0), (0, 4))
    conflict = panel_conflict(mode, emergency, run)
    if conflict is not None:
        ctx.sub("run").fail(conflict)
    return Panel(mode=mode, pwe=pwe, emergency=emergency, run=run)


def _motion(ctx: _Ctx, value: Any, n_axes: int) -> MotionData:
    t = _table(ctx, value)
    lists = ("absolute", "machine", "relative", "distance_to_go")
    scalars = tuple(MOTION_NUMBERS)
    _only(ctx, t, lists + scalars)
    positions = []
    for key in lists:
        c = ctx.sub(key)
        raw = _list(c, t.get(key, [0] * n_axes))
        if len(raw) != n_axes:
            c.fail(n_values(len(raw), n_axes))
        positions.append([_int(c.sub(i), v, _I32) for i, v in enumerate(raw)])
    nums = [_int(ctx.sub(k), t.get(k, 0), MOTION_NUMBERS[k]) for k in scalars]
    return MotionData(positions[0], positions[1], positions[2], positions[3], *nums)


def _programs(ctx: _Ctx, value: Any, base: Path | None) -> tuple[list[str], int | None]:
    """The ``[[program]]`` entries: each ``text`` (inline) or ``file`` (a path relative to
    the machine file), ``main = true`` on at most one. Each text is checked as the store
    will parse it; returns the texts and the main program's number (None: the first)."""
    texts: list[str] = []
    main: int | None = None
    numbers: set[int] = set()
    store = ProgramStore()
    for i, raw in enumerate(_list(ctx, value)):
        c = ctx.sub(i)
        t = _table(c, raw)
        _only(c, t, ("text", "file", "main"))
        if ("text" in t) == ("file" in t):
            c.fail("give either text (the program inline) or file (a path to it)")
        if "text" in t:
            key = c.sub("text")
            text = _str(key, t["text"])
        else:
            key = c.sub("file")
            named = _str(key, t["file"])
            if not named.strip():  # it would name the machine file's folder
                key.fail(f"{named!r} names no file: give the path of the program's text")
            given = Path(named)
            where = given if given.is_absolute() or base is None else base / given
            if "\x00" in str(given):  # no file system takes it
                key.fail(f"{str(given)!r}: a file name has no NUL character")
            try:
                text = program_file_text(where.read_bytes())
            except OSError as exc:
                key.fail(f"cannot read {str(where)!r}: {os_words(exc)}")
            except ValueError as exc:  # in the words of program load
                key.fail(f"{str(where)!r}: {exc}")
        try:
            program = parse_program(text)
        except ProgramError as exc:
            if "\\n" in text and "\n" not in text.strip():  # 'O1\nM30': a literal string
                key.fail(
                    f"{exc} (a TOML string in '...' keeps \\n as written: write the "
                    'program in """...""", one block a line, or in "..." with \\n)'
                )
            key.fail(str(exc))
        if program.number in numbers:
            key.fail(f"program O{program.number:04d} is given twice")
        numbers.add(program.number)
        try:  # the store's own limits (count, characters), named by the entry past them
            store.store(text)
        except ProgramError as exc:
            c.fail(str(exc))
        if _bool(c.sub("main"), t.get("main", False)):
            if main is not None:
                c.sub("main").fail(f"O{main:04d} is already the main program")
            main = program.number
        texts.append(text)
    return texts, main
