"""A clear of alarms that clears none names the alarms asked for as the CNC names them, in one
wording for the page and the command line (``T14`` for a type of no name, never ``type 14``
on one front end and ``T14`` on the other).
"""

from __future__ import annotations

import pytest
from cli_support import at, fails
from support import serving

from focas_net.protocol import alarm_filter_text
from focas_net.sim import default_machine
from focas_net.web import Station, perform


@pytest.mark.parametrize(
    ("alm_type", "alm_no", "text"),
    [(-1, -1, None), (3, -1, "PS"), (14, -1, "T14"), (-1, 100, "number 100"), (3, 100, "PS0100")],
)
def test_the_alarms_asked_for_are_named_as_the_cnc_names_them(
    alm_type: int, alm_no: int, text: str | None
) -> None:
    assert alarm_filter_text(alm_type, alm_no) == text


async def test_a_type_of_no_name_is_worded_alike_on_the_page_and_the_command_line() -> None:
    page = perform(Station(0, default_machine()), "clear_alarms", {"alm_type": 14})
    assert page["note"].startswith("no active alarm matches T14;"), page
    async with serving() as server:
        line = await fails(1, "sim", "clear", "T14", *at(server))
    assert line.startswith("focas-net: no active alarm matches T14;"), line
