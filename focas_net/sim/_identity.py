"""What the machine says it is: its identity (``cnc_sysinfo``) and its class of FANUC control."""

from __future__ import annotations

import re
from collections.abc import Collection, Sequence
from dataclasses import dataclass
from typing import Final

__all__ = [
    "CLASSES_16I",
    "CLASS_MAX_AXES",
    "CONTROL_CLASSES",
    "DEFAULT_CONTROL_CLASS",
    "MAX_NAME_LENGTH",
    "MAX_PATH_AXES",
    "Identity",
    "axes_problem",
    "axis_name_problem",
    "checked_identity",
    "checked_name",
    "control_class_unfit",
    "known_class",
    "name_problem",
]

#: The control classes a machine can be, as FANUC names its series; a front end speaks as that
#: class of control does (FANUC's native protocol: the 16i command set for 16i, 18i, 21i and
#: 0i-C, the 30i set for 0i-D, 0i-F, 30i, 31i and 32i).
CONTROL_CLASSES: Final = ("16i", "18i", "21i", "0i-C", "0i-D", "0i-F", "30i", "31i", "32i")
#: The control classes of the 16i family (the others are of the 30i family): what they lack
#: (program folders) and what they report (their software) is that family's.
CLASSES_16I: Final = frozenset(CONTROL_CLASSES[:4])
#: The most controlled axes a CNC of each class has, what its ODBSYS ``max_axis`` and its FOCAS/2
#: open answer report: 32 for the 30i family and the 0i-D/0i-F built on it (a 0i-MF and a 0i-TF
#: report ``max_axis`` 32 through ``cnc_sysinfo``, and FANUC's Ethernet header sizes every
#: per-axis array with MAX_AXIS 32), 8 for the 16i family and the 0i-C (eight axes per path).
#: ``cnc_rddynamic2`` lays its position arrays out at this stride, so a program compiled with
#: FANUC's header reads them where a CNC of its class puts them.
CLASS_MAX_AXES: Final = {
    "16i": 8,
    "18i": 8,
    "21i": 8,
    "0i-C": 8,
    "0i-D": 32,
    "0i-F": 32,
    "30i": 32,
    "31i": 32,
    "32i": 32,
}
#: The control class of a machine that does not say (the built-in machine is a 0i-F).
DEFAULT_CONTROL_CLASS: Final = "0i-F"
#: Characters of a machine's name at most: it heads the server's ready line and its logs.
MAX_NAME_LENGTH: Final = 64
#: Axes of one path at most: the NC engine's macro variables give each axis one of 20 slots
#: (#5001-#5020 the positions, #5221-#5240 G54, ...), as FANUC's 0i and 16i do.
MAX_PATH_AXES: Final = 20
#: Identity texts and their widths (ODBSYS).
_IDENTITY_TEXTS: Final = (
    ("cnc_type", 2),
    ("mt_type", 2),
    ("series", 4),
    ("version", 4),
    ("axes", 2),
)


@dataclass(frozen=True, slots=True)
class Identity:
    """What the CNC says it is (FANUC's ODBSYS): ``cnc_type`` and ``mt_type`` 2 characters,
    ``series`` and ``version`` 4, ``axes`` 2 (the number of axes, ``"03"``)."""

    addinfo: int
    max_axis: int
    cnc_type: str
    mt_type: str
    series: str
    version: str
    axes: str


def control_class_unfit(text: str) -> str | None:
    """What keeps ``text`` from naming a control class (None: nothing); a class is named in
    either case, spaces around it left out."""
    if any(text.strip().lower() == known.lower() for known in CONTROL_CLASSES):
        return None
    return f"unknown control class {text.strip()!r} (expected one of: {', '.join(CONTROL_CLASSES)})"


def known_class(control_class: object) -> str:
    """The control class ``control_class`` names, as :data:`CONTROL_CLASSES` spells it: in
    either case (``"30I"``), as a machine file takes it; TypeError for another type,
    ValueError naming the classes for an unknown one."""
    if not isinstance(control_class, str):
        raise TypeError(f"control_class must be a str, got {control_class!r}")
    why = control_class_unfit(control_class)
    if why is not None:
        raise ValueError(why)
    text = control_class.strip().lower()
    return next(known for known in CONTROL_CLASSES if known.lower() == text)


def checked_identity(identity: Identity | None, control_class: str, axes: int) -> Identity:
    """``identity`` (the default one of a machine with ``axes`` axes when None), once it and
    ``control_class`` are checked: ValueError for an unknown class or a text of another width
    or not ASCII."""
    control_class = known_class(control_class)
    if not 1 <= axes <= 32:
        raise ValueError(f"a machine has 1..32 axes, got {axes}")
    if identity is None:
        most = max(axes, CLASS_MAX_AXES[control_class])
        identity = Identity(2, most, " 0", " M", "D4F1", "32.0", f"{axes:02d}")
    for key, size in _IDENTITY_TEXTS:
        text = getattr(identity, key)
        if not isinstance(text, str) or len(text) != size or not text.isascii():
            raise ValueError(f"identity {key} must be {size} ASCII characters, got {text!r}")
    return identity


def name_problem(name: str) -> str | None:
    """What keeps ``name`` from being a machine's name (None: nothing): a name is 1..64
    printable characters, so it stays on its one line of the ready line and the logs."""
    rule = f"a machine's name is 1..{MAX_NAME_LENGTH} printable characters"
    if not 1 <= len(name) <= MAX_NAME_LENGTH:
        return f"{rule}, not {len(name)}"
    bad = next((c for c in name if not c.isprintable()), None)
    return None if bad is None else f"{rule}: {bad!r} is not one"


#: An axis name as FANUC's CNC has one: the letter of parameter 1020 (A..Z, 65..90), then up
#: to three capital letters or digits (a subscript, parameter 3131, and extended names).
_AXIS_NAME: Final = re.compile(r"[A-Z][A-Z0-9]{0,3}")


def axis_name_problem(name: object, taken: Collection[object] = ()) -> str | None:
    """What is wrong with ``name`` as an axis name (a capital letter and up to 3 capital
    letters or digits, not one of ``taken``), or None."""
    if not (isinstance(name, str) and _AXIS_NAME.fullmatch(name)):
        return (
            "an axis name is a capital letter A..Z (FANUC's parameter 1020) and up to 3 "
            f"capital letters or digits, got {name!r}"
        )
    if name in taken:
        return f"axis {name!r} is named twice"
    return None


def axes_problem(names: Sequence[object]) -> str | None:
    """What is wrong with ``names`` as the axes of a path (1..:data:`MAX_PATH_AXES` distinct
    axis names), or None."""
    if not 1 <= len(names) <= MAX_PATH_AXES:
        return f"a path has 1..{MAX_PATH_AXES} axes, got {len(names)}"
    for i, name in enumerate(names):
        problem = axis_name_problem(name, names[:i])
        if problem is not None:
            return problem
    return None


def checked_name(name: str) -> str:
    """``name`` once it is checked (:func:`name_problem`): ValueError saying the rule
    (TypeError for a name that is no ``str``)."""
    if not isinstance(name, str):
        raise TypeError(f"a machine's name must be text (str), got {name!r}")
    problem = name_problem(name)
    if problem is not None:
        raise ValueError(problem)
    return name
