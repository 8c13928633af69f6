"""What a new user runs into, sixth pass: the command line as a child process against a real
server (127.0.0.1, ephemeral port) on both transports, its exit codes and its one-line
messages, and the Python clients beside it.

Each test names what a user typed and what the command must say.
"""

from __future__ import annotations

import re
from decimal import Decimal

import pytest
from cli_support import at, fails, ok
from support import IO_TIMEOUT, Served

from focas_net.cli import EXIT_USAGE
from focas_net.client import FocasClient, NativeClient
from focas_net.sim import MachineError
from focas_net.web import ActionError, Station, perform

#: The transports, as the command line chooses them.
PROTOCOLS = [[], ["--protocol", "native"]]


# -- a macro value far beyond what a variable holds ---------------------------------------------


@pytest.mark.parametrize("protocol", PROTOCOLS)
@pytest.mark.parametrize("typed", ["1e99999999999", "1e-99999999999", "-1e-30", "9E+9999"])
async def test_a_macro_value_of_a_huge_exponent_does_not_fit(
    server: Served, protocol: list[str], typed: str
) -> None:
    """1e99999999999 raised decimal.Overflow (a traceback); 1e-99999999999 was written as 0,
    though 0.0000000001 is refused."""
    server.machine.write_macro(100, Decimal(7))
    line = await fails(EXIT_USAGE, "macro", "set", "100", typed, *protocol, *at(server))
    assert line == (
        f"focas-net: #100: macro value {typed} does not fit a macro variable: give at most 9 "
        "decimals and at most 10 digits, which without the decimal point stay within 32 bits "
        "(-2147483648..2147483647)"
    )
    assert server.machine.read_macro(100) == 7


@pytest.mark.parametrize("typed", ["0e99999999999", "0e-99999999999", "1e-9", "2.147483647e9"])
async def test_a_macro_value_with_an_exponent_that_fits_is_written(
    server: Served, typed: str
) -> None:
    out = await ok("macro", "set", "100", typed, *at(server))
    assert out.startswith("#100 = ") and out.endswith("(written)\n")
    assert server.machine.read_macro(100) == Decimal(typed)


async def test_both_clients_refuse_a_huge_exponent_before_sending(server: Served) -> None:
    async with (
        FocasClient(server.host, server.port, timeout=IO_TIMEOUT) as packed,
        NativeClient(server.host, server.port, timeout=IO_TIMEOUT) as native,
    ):
        for client in (packed, native):
            for value in ("1e99999999999", Decimal("1e-99999999999")):
                with pytest.raises(ValueError, match="does not fit a macro variable"):
                    await client.write_macro(100, value)


# -- an alarm message that is no line of text ----------------------------------------------------


@pytest.mark.parametrize(
    ("typed", "shown", "char"),
    [("a\nb", "'a\\nb'", "'\\n' (U+000A)"), ("tab\there", "'tab\\there'", "'\\t' (U+0009)"),
     ("\x7f", "'\\x7f'", "'\\x7f' (U+007F)")],
)  # fmt: skip
async def test_an_alarm_message_with_a_control_character_says_which(
    server: Served, typed: str, shown: str, char: str
) -> None:
    """It was EW_DATA (exit 1) with "its type, number or message is out of range"; the machine
    knew the character, and the page showed it."""
    words = (
        f"alarm message {shown} holds the control character {char}: a message is one line of text"
    )
    line = await fails(EXIT_USAGE, "sim", "alarm", "PS0102", typed, *at(server))
    assert line == f"focas-net: {words}"
    assert list(server.machine.active_alarms()) == []
    with pytest.raises(ActionError) as refused:  # the page's text, refused as the client's
        perform(
            Station(0, server.machine), "raise_alarm", {"alm_type": 3, "alm_no": 102, "msg": typed}
        )
    assert str(refused.value) == f"msg: {words}"
    with pytest.raises(MachineError) as kept:  # and the machine's own check says the same
        server.machine.raise_alarm(0, 3, 102, typed)
    assert str(kept.value).endswith(words)


async def test_a_control_character_past_what_the_machine_keeps_is_cut_with_it(
    server: Served,
) -> None:
    """The machine keeps 32 characters: what it cuts off is not checked, on every front end."""
    typed = "x" * 32 + "\n"
    out = await ok("sim", "alarm", "PS0103", typed, *at(server))
    assert re.fullmatch(r"raised PS0103 x{32}\n", out), out
