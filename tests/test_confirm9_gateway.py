"""A confirming pass over the gateway and the labels every front end shares: the selected
mode is ``mode`` on the command line, the web page and the gateway alike; a key that takes a
number asks for a finite one; a shard out of range is a usage error of ``--shard``."""

from __future__ import annotations

from pathlib import Path

import pytest
from cli_support import Cli, run_focas_net
from gateway_support import polled_once
from support import serving

from focas_net.client._values import check_item
from focas_net.client.native import NativeClient
from focas_net.gateway import ConfigError, MachineConfig, WriteGates, parse_config
from focas_net.gateway.writer import GatedWriter
from focas_net.sim import default_machine
from focas_net.web.view import machine_view, status_fields

MACHINE = '[[machine]]\nname = "m1"\nhost = "127.0.0.1"\n'


# -- one value, one label ---------------------------------------------------------------------
async def test_the_selected_mode_is_mode_on_every_front_end(
    capsys: pytest.CaptureFixture[str],
) -> None:
    machine = default_machine()
    machine.set_panel(0, 1, 0)  # MDI
    async with serving(machine) as served:
        cli = Cli(served, capsys)
        text = await cli.ok("status")
        shown = await cli.json("status")
        panel = await cli.json("sim", "panel")
        panel_text = await cli.ok("sim", "panel")
        got = await polled_once(served.port)
    assert text.startswith("mode=MDI ") and "aut" not in text
    assert any(line.split()[:3] == ["mode", "0", "MDI"] for line in text.splitlines()[1:])
    assert "aut" not in shown and shown["mode"]["name"] == "MDI"
    assert panel_text.startswith("mode=MDI ")
    assert panel["mode"] == 0 and panel["status"]["mode"]["name"] == "MDI"
    web = {f["field"]: f["name"] for f in status_fields(machine)}
    assert "aut" not in web
    tile = machine_view(0, machine, 8193)
    assert got[(1, "mode", "")].value == web["mode"] == tile["mode"] == "MDI"


# -- a number must be finite ----------------------------------------------------------------
@pytest.mark.parametrize(
    ("text", "words"),
    [
        ("[mqtt]\ndeadbands = { feed = inf }\n", "mqtt.deadbands.feed: got inf; expected a "
         "finite number >= 0"),
        ("[groups]\nfast = inf\n", "groups.fast: got inf; expected a finite number of seconds "
         ">= 0.01"),
        (MACHINE + "timeout = inf\n", "machine[1].timeout: got inf; expected a finite number of "
         "seconds > 0"),
        (MACHINE + "timeout = nan\n", "machine[1].timeout: got nan; expected a finite number of "
         "seconds > 0"),
    ],
)  # fmt: skip
def test_an_infinite_number_is_refused_as_not_finite(text: str, words: str) -> None:
    if not text.startswith("[[machine]]"):
        text = MACHINE + text
    with pytest.raises(ConfigError) as caught:
        parse_config(text, "plant.toml")
    assert str(caught.value) == f"plant.toml: {words}"


# -- a shard out of range is a usage error of --shard ----------------------------------------
@pytest.mark.parametrize(
    ("typed", "words"),
    [
        ("0/2", "the shard must be within 1..2, got '0/2'"),
        ("3/2", "the shard must be within 1..2, got '3/2'"),
        ("1/0", "the number of shards must be 1 or more, got '1/0'"),
    ],
)
async def test_a_shard_out_of_range_is_refused_as_the_argument(
    tmp_path: Path, typed: str, words: str
) -> None:
    path = tmp_path / "plant.toml"
    path.write_text(MACHINE + "port = 8193\n")
    code, out, err = await run_focas_net("gateway", str(path), "--shard", typed)
    assert (code, out) == (2, "")
    assert err.splitlines()[-1] == (
        f"focas-net gateway: error: argument --shard: {words}; see focas-net gateway --help"
    )


# -- an axis out of range: one wording on the command line, the client and the gateway -------
@pytest.mark.parametrize(
    ("argv", "what"),
    [
        (("param", "set", "6711", "5"), "parameter"),
        (("param", "get", "6711"), "parameter"),
        (("diag", "300"), "diagnostic"),
    ],
)
@pytest.mark.parametrize("axis", [-1, 40000])
async def test_an_axis_out_of_range_is_worded_as_the_client_and_the_gateway_word_it(
    argv: tuple[str, ...], what: str, axis: int
) -> None:
    """``--axis -1`` said ``must not be negative, got -1`` where ``--axis 40000``, the Python
    client and the gateway's WriteParameter say the axis field's range."""
    words = f"axis {axis} is outside 0..32767 (0: not an axis {what})"
    code, out, err = await run_focas_net(*argv, "--axis", str(axis), "--port", "1")
    command = " ".join(argv[: 2 if argv[0] == "param" else 1])
    assert (code, out) == (2, "")
    assert err.splitlines()[-1] == (
        f"focas-net {command}: error: argument --axis: {words}; see focas-net {command} --help"
    )
    if what == "parameter":
        with pytest.raises(ValueError) as caught:
            check_item(6711, axis, "parameter")
        assert str(caught.value) == words
        machine = MachineConfig("m1", "127.0.0.1", writes=WriteGates(params=((6711, 6711),)))
        writer = GatedWriter(lambda name: (machine, NativeClient("127.0.0.1", 1)))
        with pytest.raises(ValueError) as caught:  # refused before any connection is made
            await writer.write_param("m1", 6711, 5, axis)
        assert str(caught.value) == words
