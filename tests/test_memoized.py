"""The self-filling memo behind the codecs' ``decode_bytes``: a hit is the dict's look-up, a
miss computes and keeps, a failure keeps nothing, and it never grows past its size."""

from __future__ import annotations

import pytest

from focas_net._memo import Memoized


def test_a_key_is_computed_once_and_then_read_from_the_dict() -> None:
    computed: list[bytes] = []

    def compute(key: bytes) -> int:
        computed.append(key)
        return len(key)

    memo = Memoized(8, compute)
    get = memo.__getitem__
    assert get(b"abc") == 3
    assert get(b"abc") == 3
    assert get(b"de") == 2
    assert computed == [b"abc", b"de"]
    assert dict(memo) == {b"abc": 3, b"de": 2}


def test_what_compute_raises_is_raised_and_nothing_is_kept() -> None:
    def compute(key: bytes) -> int:
        raise ValueError(f"cannot take {key!r}")

    memo = Memoized(8, compute)
    with pytest.raises(ValueError, match="cannot take b'x'"):
        memo[b"x"]
    assert len(memo) == 0


def test_it_empties_itself_when_full_and_keeps_the_new_value() -> None:
    memo = Memoized(3, lambda key: key * 2)
    for key in (1, 2, 3):
        assert memo[key] == key * 2
    assert len(memo) == 3
    assert memo[4] == 8  # full: emptied, then the new value kept
    assert dict(memo) == {4: 8}
    assert memo[1] == 2
    assert dict(memo) == {4: 8, 1: 2}
