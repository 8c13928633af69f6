"""Two refusals that named too little: an operator message's A address in digits of another
script (taken as A1.1 before), a rapid override typed as a step name other than F0 (``F25``:
"not a whole number"), which now lists the steps, on every front end that reads it, and a
``--web`` port a CNC of the same command took ("address already in use" alone)."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from cli_support import fails, ok
from support import free_port, serving

from focas_net._typed import rapid_step
from focas_net.cli import EXIT_CNC, EXIT_USAGE
from focas_net.sim import MachineFileError, load_machine
from focas_net.web import parse_web_address

LATHE = Path(__file__).resolve().parent.parent / "examples" / "lathe_2path.toml"

MACHINE = """
[machine]
name = "m"
axes = ["X"]

[pmc.A]
size = 10

[[operator_messages]]
address = "{address}"
number = 2001
text = "HELLO"
"""


def test_an_address_in_digits_of_another_script_is_refused(tmp_path: Path) -> None:
    path = tmp_path / "m.toml"
    path.write_text(MACHINE.format(address="A1.1"))
    load_machine(path)  # the ASCII address loads
    path.write_text(MACHINE.format(address="A\u0661.1"))  # an Arabic-Indic 1
    with pytest.raises(MachineFileError) as refused:
        load_machine(path)
    assert "operator_messages" in str(refused.value) and "address" in str(refused.value)


@pytest.mark.parametrize("typed", ["F25", "f50", " F100 "])
def test_a_step_name_other_than_f0_lists_the_steps(typed: str) -> None:
    with pytest.raises(ValueError, match=r"is no rapid override: F0, or a step of 25, 50, 100"):
        rapid_step(typed)
    assert rapid_step(" f0 ") == 0 and rapid_step("50") == 50


async def test_the_command_line_says_so() -> None:
    async with serving() as served:
        line = await fails(
            EXIT_USAGE, "sim", "override", "--rapid", "F25", "--port", str(served.port),
            prefix="focas-net",
        )  # fmt: skip
    assert "'F25' is no rapid override: F0, or a step of 25, 50, 100 (%)" in line


async def test_web_on_a_port_the_cnc_took_says_so() -> None:
    port = str(free_port())
    line = await fails(EXIT_CNC, "serve", "--port", port, "--web", port, prefix="focas-net")
    assert line == (
        f"focas-net serve: error: --web 127.0.0.1:{port}: cannot listen: address already in use "
        f"(a CNC of this command listens on port {port}: give --web another)"
    )


@pytest.mark.parametrize(
    ("typed", "said"),
    [
        ("1.2.3.4.5:0", "'1.2.3.4.5:0': not an IPv4 address: host '1.2.3.4.5'"),
        ("256.1.1.1:80", "'256.1.1.1:80': not an IPv4 address: host '256.1.1.1'"),
        ("tcp://1.2.3.4:80", "'tcp://1.2.3.4:80' is a URL: write [HOST:]PORT without a scheme "
         "(1.2.3.4:80)"),
        ("http://[::1]/", "'http://[::1]/' is a URL: write [HOST:]PORT without a scheme "
         "([::1]:PORT)"),
    ],
)  # fmt: skip
def test_a_web_address_is_checked_as_every_host_is(typed: str, said: str) -> None:
    with pytest.raises(ValueError) as refused:
        parse_web_address(typed)
    assert str(refused.value) == said


async def test_serve_refuses_a_bad_web_host_before_anything_listens() -> None:
    line = await fails(
        EXIT_USAGE, "serve", "--port", "0", "--web", "1.2.3.4.5:0", prefix="focas-net"
    )
    assert line == (
        "focas-net serve: error: argument --web: '1.2.3.4.5:0': not an IPv4 address: host "
        "'1.2.3.4.5'; see focas-net serve --help"
    )


async def test_sysinfo_axes_are_the_machines_on_packed_and_the_paths_on_focas2() -> None:
    """As docs/cli.md says: the one documented difference of the two transports' reads."""
    lathe = load_machine(LATHE)
    async with serving(lathe) as served:
        port = str(served.port)
        packed = await ok("sysinfo", "--port", port, "--json")
        native = await ok(
            "sysinfo", "--port", port, "--json", "--protocol", "native", "--path", "2"
        )
    assert (json.loads(packed)["axes"], json.loads(native)["axes"]) == ("04", "02")


@pytest.mark.parametrize(("typed", "mode"), [("mem ", 1), (" MDI", 0), ("edit", 3)])
def test_a_machine_files_mode_is_read_as_the_page_and_mode_read_it(
    tmp_path: Path, typed: str, mode: int
) -> None:
    path = tmp_path / "m.toml"
    path.write_text(f'[machine]\nname = "m"\naxes = ["X"]\n[panel]\nmode = "{typed}"\n')
    assert load_machine(path).status().aut == mode


def test_a_mode_of_other_letters_is_no_mode_in_a_machine_file(tmp_path: Path) -> None:
    path = tmp_path / "m.toml"
    path.write_text('[machine]\nname = "m"\naxes = ["X"]\n[panel]\nmode = "md\u0131"\n')
    with pytest.raises(MachineFileError, match="unknown mode"):
        load_machine(path)
