"""A client's refusal for want of a connection says what to do or why it was lost, on both
transports; the machine names an axis beyond the path with the path's count."""

from __future__ import annotations

from collections.abc import Callable

import pytest
from cli_support import at, fails
from support import serving

from focas_net.cli import EXIT_CNC
from focas_net.client import FocasClient, NativeClient
from focas_net.errors import EW, FocasConnectionError
from focas_net.server import FocasServer
from focas_net.sim import (
    MachineError,
    default_machine,
    machine_from_dict,
)
from focas_net.web.view import pmc_window

Client = Callable[[str, int], FocasClient | NativeClient]
CLIENTS: list[Client] = [FocasClient, NativeClient]


@pytest.mark.parametrize("make", CLIENTS, ids=["packed", "native"])
async def test_a_client_never_connected_says_how_to_connect(make: Client) -> None:
    client = make("127.0.0.1", 8193)
    with pytest.raises(FocasConnectionError) as caught:
        await client.read_status()
    assert str(caught.value) == (
        "not connected to 127.0.0.1:8193: call connect() first, or use `async with`"
    )


@pytest.mark.parametrize("make", CLIENTS, ids=["packed", "native"])
async def test_a_client_without_reconnect_says_why_its_link_was_lost(make: Client) -> None:
    server = FocasServer(default_machine(), host="127.0.0.1", port=0)
    await server.start()
    port = server.addresses[0][1]
    client = make("127.0.0.1", port)
    try:
        await client.connect()
        await client.read_status()
        await server.aclose()
        for _ in range(2):  # the loss is seen by the first call or before it; both say why
            with pytest.raises(FocasConnectionError) as caught:
                await client.read_status()
        text = str(caught.value)
        assert text.startswith(f"not connected to 127.0.0.1:{port} (connection closed by")
        assert client.lost_reason is not None and str(client.lost_reason) in text
    finally:
        await client.aclose()
        await server.aclose()


def test_the_machine_names_an_axis_beyond_the_path_with_the_count() -> None:
    machine = default_machine()
    count = len(machine.positions("absolute"))
    with pytest.raises(MachineError) as caught:
        machine.positions("absolute", axis=count + 1)
    assert caught.value.ew == EW.ATTRIB
    assert str(caught.value).endswith(
        f"axis {count + 1} is outside 1..{count}: the path has {count} axes"
    )


@pytest.mark.parametrize(
    ("mt_type", "kind"),
    [(" T", "T"), (" t", "T"), ("TT", "T"), ("tt", "T"), (" M", "M"), ("MM", "M"), ("MT", "T")],
)
def test_a_path_kind_follows_mt_type_as_the_kind_key_reads_it(mt_type: str, kind: str) -> None:
    """``mt_type = " t"`` made a lathe's one path M while ``kind = "t"`` is T, and ``"TT"``
    (a lathe of several paths, as one reports it) made every path M."""
    one = machine_from_dict(
        {"machine": {"name": "L", "axes": ["X", "Z"]}, "sysinfo": {"mt_type": mt_type}}
    )
    assert one.path_info(1).kind == kind
    two = machine_from_dict(
        {
            "machine": {"name": "L"},
            "sysinfo": {"mt_type": mt_type},
            "path": [{"axes": ["X1", "Z1"]}, {"axes": ["X2"]}],
        }
    )
    assert [two.path_info(n).kind for n in (1, 2)] == [kind, kind]


@pytest.mark.parametrize(
    ("argv", "span"),
    [(["read", "R", "8000", "1"], "R8000"), (["write", "R", "7999", "1", "2"], "R7999..R8000")],
)
async def test_a_pmc_address_past_its_area_reads_alike_on_the_page_and_the_command_line(
    argv: list[str], span: str
) -> None:
    """The page said ``R8000 is outside R0..R7999`` where ``pmc read`` says ``R8000 goes past
    the end of PMC area R``: the machine's words are the command line's, the range after."""
    async with serving() as served:
        line = await fails(EXIT_CNC, "pmc", *argv[:1], *at(served), *argv[1:])
        words = f"{span} goes past the end of PMC area R"
        assert words in line
        with pytest.raises(MachineError) as refused:
            if argv[0] == "read":
                pmc_window(served.machine, "R", 8000)
            else:
                served.machine.write_pmc("R", 7999, b"\1\2")
        assert refused.value.detail == f"{words} (R0..R7999)"
