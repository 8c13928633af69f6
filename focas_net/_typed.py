"""Words for a value typed that does not fit, shared by the machine and the clients so that
every front end refuses it alike (it knows no protocol and no machine)."""

from __future__ import annotations

__all__ = ["macro_unfit"]


def macro_unfit(value: object) -> str:
    """Why ``value`` does not fit a macro variable, and what to type instead."""
    return (
        f"{value} does not fit a macro variable: give at most 9 decimals and at most 10 digits, "
        "which without the decimal point stay within 32 bits (-2147483648..2147483647)"
    )
