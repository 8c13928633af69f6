"""The number options of the examples, read as the ``focas-net`` command line reads number
text: ASCII digits, a sign and a decimal point, or a whole number in ``0x``/``0b``/``0o``;
an exponent (``1e3``), NaN and infinity words are refused naming the text. Each is an
argparse ``type=``, so a refusal is argparse's one line and exit code 2.

Not an example itself: the scripts of this folder import it (Python puts a script's folder
on ``sys.path``).
"""

from __future__ import annotations

import argparse

from focas_net._typed import typed_number, whole_number

__all__ = ["number", "ports", "positive", "whole"]


def whole(text: str) -> int:
    """A whole number (a port, a count, a parameter number); its range is the caller's."""
    try:
        return whole_number(text)
    except ValueError as exc:
        raise argparse.ArgumentTypeError(str(exc)) from None


def number(text: str) -> float:
    """A finite number of seconds; its range is the caller's (a client refuses a timeout
    of 0 in its own words)."""
    try:
        return float(typed_number(text))  # at most 100 digits: never infinite
    except ValueError as exc:
        raise argparse.ArgumentTypeError(str(exc)) from None


def positive(text: str) -> float:
    """A positive, finite number (seconds, a speed)."""
    value = number(text)
    if not value > 0:
        raise argparse.ArgumentTypeError(f"must be positive, got {text.strip()}")
    return value


def ports(text: str) -> list[int]:
    """``--ports``: ports separated by commas (or spaces), at least one, each 1..65535."""
    try:
        listed = [whole_number(p) for p in text.replace(",", " ").split()]
    except ValueError as exc:
        raise argparse.ArgumentTypeError(f"not a list of ports: {text!r} ({exc})") from None
    if not listed:
        raise argparse.ArgumentTypeError(f"no port in {text!r} (give e.g. 8193,8194)")
    if not all(1 <= p <= 65535 for p in listed):
        raise argparse.ArgumentTypeError(f"ports are 1..65535, got {text!r}")
    return listed
