"""What a new user runs into, third pass: the command line as a child process against a real
server (127.0.0.1, ephemeral port), its exit codes and its one-line messages.

Each test names what a user typed and what the command must say: words that name the
mistake, the number printed once, plain decimals, the advice that fits the case.
"""

from __future__ import annotations

import pytest
from cli_support import run_focas_net
from support import Served, serving

from focas_net.cli import EXIT_CNC, EXIT_OK, EXIT_USAGE


def at(served: Served) -> list[str]:
    return ["--host", "127.0.0.1", "--port", str(served.port)]


def one_line(err: str) -> str:
    """The one ``focas-net:`` line of a failure."""
    assert err.startswith("focas-net: ") and err.count("\n") == 1, err
    return err.strip()


async def fails(code: int, *argv: str) -> str:
    got, out, err = await run_focas_net(*argv)
    assert got == code, (argv, got, err)
    assert out == ""
    return one_line(err)


async def ok(*argv: str) -> str:
    got, out, err = await run_focas_net(*argv)
    assert got == EXIT_OK, (argv, got, err)
    assert err == ""
    return out


# -- F: small ones -----------------------------------------------------------------------------


@pytest.mark.parametrize("values", ["1,2,,3", "1,", ",1"])
async def test_an_empty_item_of_a_byte_list_is_refused_naming_it(
    server: Served, values: str
) -> None:
    before = server.machine.read_pmc("R", 0, 4)
    line = await fails(EXIT_USAGE, "pmc", "write", "R", "0", values, *at(server))
    assert "empty item" in line and repr(values) in line
    assert server.machine.read_pmc("R", 0, 4) == before


async def test_a_bit_that_is_no_number_is_named(server: Served) -> None:
    line = await fails(EXIT_USAGE, "pmc", "bit", "R", "1.-1", *at(server))
    assert "bit after the dot" in line and "'-1'" in line and "0..7" in line


async def test_a_pmc_address_out_of_range_names_the_range(server: Served) -> None:
    line = await fails(EXIT_USAGE, "pmc", "bit", "R", "99999.1", *at(server))
    assert "PMC start address 99999" in line and "0..65535" in line


async def test_a_macro_value_prints_in_plain_decimals(server: Served) -> None:
    out = await ok("macro", "set", "100", "-0.0000001", *at(server))
    assert out == "#100 = -0.0000001 (written)\n"
    assert await ok("macro", "get", "100", *at(server)) == "#100 = -0.0000001\n"
    json_out = await ok("macro", "get", "100", "--json", *at(server))
    assert '"-0.0000001"' in json_out and "E" not in json_out


async def test_an_unknown_ew_code_shows_its_number_once(server: Served) -> None:
    out = await ok("sim", "fault", "error", "--arg", "12345", *at(server))
    assert "EW_UNKNOWN(12345)" in out and "(12345) (12345)" not in out
    line = await fails(EXIT_CNC, "status", *at(server))
    assert line.startswith("focas-net: EW_UNKNOWN(12345): unknown return code"), line


async def test_serve_on_a_port_in_use_says_so_without_the_address_tuple() -> None:
    async with serving() as served:
        code, _, err = await run_focas_net("serve", *at(served))
    assert code == EXIT_CNC, err
    assert err == (
        f"focas-net serve: error: cannot listen on 127.0.0.1:{served.port}: "
        "address already in use\n"
    )
