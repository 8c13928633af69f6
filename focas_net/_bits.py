"""A bit parameter's value written as its bits, read the same way by the machine file, the
command line and the dashboard (it knows no protocol and no machine).

The command line and the page show a bit parameter as its eight bits #7..#0 (``10110000``);
typed back, the same eight digits are those bits, never the decimal number 10110000 or, with
leading zeros, ``00000011`` as eleven.
"""

from __future__ import annotations

__all__ = ["bits_hint", "bits_of_text"]

_BINARY = frozenset("01")


def bits_hint(text: str, number: str = "an integer 0..255") -> str:
    """How to write a bit parameter's value, for a refusal of ``text``: its bits, ``0b`` and
    ``number``, the other way the front end takes (the page, which takes no decimal: ``0x``)."""
    raw = text.strip().lower().replace("_", "").removeprefix("0b")
    if raw and not set(raw) - _BINARY and len(raw) > 8:  # no value to show it as: too many
        return (
            f"{text!r} has {len(raw)} bits: a bit parameter has eight, #7..#0: write them "
            f'(as "10110000"), a binary number with 0b of at most eight digits or {number}'
        )
    example = raw if raw and not set(raw) - _BINARY and len(raw) < 8 else "1011"
    return (
        f'{text!r} is not 8 bits: write the eight bits #7..#0 ("{int(example, 2):08b}"), '
        f'a binary number with 0b ("0b{example}") or {number}'
    )


def bits_of_text(text: str, number: str = "an integer 0..255") -> int | None:
    """The value of a bit parameter typed as ``text`` when the text is written as bits: the
    eight digits #7..#0 (``"10110000"`` is 176; ``_`` may separate them) or ``0b`` and at most
    eight digits (``"0b1011"`` is 11). None for text of another shape (``"176"``, ``"0xB0"``),
    which the caller reads as a number.

    :raises ValueError: 0/1 digits that are not eight and start with 0 (``"0101"``: the bits
        #3..#0, or 101 with a leading zero?), four to seven or more than eight of them
        (``"1011"``: the bits #3..#0 or #7..#4, and as a decimal no byte) and more than eight
        after ``0b``.
    """
    raw = text.strip().lower().replace("_", "")
    binary = raw.startswith("0b")
    digits = raw.removeprefix("0b")
    if not digits or set(digits) - _BINARY:
        return None
    if len(digits) == 8 or (binary and len(digits) < 8):
        return int(digits, 2)
    if binary or (digits.startswith("0") and len(digits) > 1) or len(digits) > 3:
        raise ValueError(bits_hint(text, number))
    return None
