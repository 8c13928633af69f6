"""The Python API as a new user meets it, an eleventh pass: a PMC range of no bytes refused
in one rule's words by the machine and both clients, a PMC write past an area's end checked
before its first chunk where the client knows the area's size, and the arguments of the
public calls refused by kind (a type for a type, a range for a range) before anything is
sent."""

from __future__ import annotations

import pytest

from focas_net import EW, FocasClient, NativeClient
from focas_net._typed import pmc_count_unfit
from focas_net.sim import Machine, MachineError

Both = tuple[Machine, FocasClient, NativeClient]


# -- a PMC range of no bytes: one rule, the machine's and the clients' -------------------------
@pytest.mark.parametrize("count", [0, -1, -40])
async def test_a_pmc_range_of_no_bytes_is_refused_in_one_rule_s_words(
    both_clients: Both, count: int
) -> None:
    """The machine said ``PMC byte count 0: a PMC range holds one byte at least`` where both
    clients said ``PMC byte count 0 is outside 1..65536``."""
    machine, cnc, native = both_clients
    words = pmc_count_unfit(count)
    assert words is not None and words.startswith(f"PMC byte count {count} is outside 1..65536")
    assert "one byte at least" in words
    with pytest.raises(MachineError) as refused:
        machine.read_pmc("R", 10, count)
    assert (refused.value.ew, refused.value.detail) == (EW.LENGTH, words)
    for client in (cnc, native):
        with pytest.raises(ValueError) as given:
            await client.read_pmc("R", 10, count)
        assert str(given.value) == words, type(client).__name__
    if count == 0:
        with pytest.raises(MachineError) as refused:
            machine.write_pmc("R", 10, b"")
        assert refused.value.detail == words
        for client in (cnc, native):
            with pytest.raises(ValueError) as given:
                await client.write_pmc("R", 10, b"")
            assert str(given.value) == words, type(client).__name__
