"""What a new user runs into, third pass: the command line as a child process against a real
server (127.0.0.1, ephemeral port), its exit codes and its one-line messages.

Each test names what a user typed and what the command must say: words that name the
mistake, the number printed once, plain decimals, the advice that fits the case.
"""

from __future__ import annotations

import asyncio
import re
import socket
import ssl
import sys
from collections.abc import AsyncIterator
from contextlib import asynccontextmanager
from pathlib import Path

import pytest
from cli_support import SUBPROCESS_TIMEOUT, at, fails, ok, one_line, run_focas_net
from support import Served, serving

from focas_net.cli import EXIT_CNC, EXIT_USAGE
from focas_net.sim import default_machine, load_machine

FWLIB_16I = Path(__file__).with_name("data") / "fwlib_16i_machine.toml"


# -- F: small ones -----------------------------------------------------------------------------


@pytest.mark.parametrize("values", ["1,2,,3", "1,", ",1"])
async def test_an_empty_item_of_a_byte_list_is_refused_naming_it(
    server: Served, values: str
) -> None:
    before = server.machine.read_pmc("R", 0, 4)
    line = await fails(
        EXIT_USAGE, "pmc", "write", "R", "0", values, *at(server), prefix="focas-net"
    )
    assert "empty item" in line and repr(values) in line
    assert server.machine.read_pmc("R", 0, 4) == before


async def test_a_bit_that_is_no_number_is_named(server: Served) -> None:
    line = await fails(EXIT_USAGE, "pmc", "bit", "R", "1.x", *at(server), prefix="focas-net")
    assert "bit after the dot" in line and "'x'" in line and "0..7" in line


async def test_a_pmc_address_out_of_range_names_the_range(server: Served) -> None:
    line = await fails(EXIT_USAGE, "pmc", "bit", "R", "99999.1", *at(server), prefix="focas-net")
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


# -- A: advice that fits the case --------------------------------------------------------------


@pytest.mark.parametrize("protocol", ["packed", "native"])
async def test_position_of_an_axis_the_machine_lacks_names_its_axes(
    server: Served, protocol: str
) -> None:
    line = await fails(EXIT_CNC, "position", "--axis", "9", "--protocol", protocol, *at(server))
    assert line.endswith("axis 9 is outside 1..3: the path has 3 axes); give --axis 1..3"), line


async def test_a_parameter_bit_past_its_width_reads_as_param_set_says_it(server: Served) -> None:
    got = await fails(EXIT_USAGE, "param", "get", "1815.9", "--axis", "1", *at(server))
    put = await fails(EXIT_USAGE, "param", "set", "1815.9", "1", "--axis", "1", *at(server))
    assert got == put == "focas-net: bit 9 is outside 0..7: parameter 1815 is 1 byte wide"


async def test_a_wrong_password_is_named_as_such() -> None:
    machine = default_machine()
    machine.set_param_password("AB12")
    async with serving(machine) as served:
        await ok("sim", "panel", "--mode", "MDI", "--pwe", "on", *at(served))
        line = await fails(EXIT_CNC, "param", "set", "3401", "1", "--password", "XXXX", *at(served))
        assert "(cnc_wrunlockparam)" in line
        assert "--password XXXX is not the CNC's parameter password" in line
        assert "MDI" not in line  # the gate is open: only the password is wrong
        await ok("sim", "panel", "--mode", "MEM", *at(served))
        line = await fails(EXIT_CNC, "param", "set", "3401", "1", "--password", "AB12", *at(served))
        assert "(cnc_wrparam)" in line
        assert "the --password was accepted; parameter writes need MDI mode and PWE on" in line
        # a machine without a password takes any, and native has none to send
    async with serving() as served:
        await ok("sim", "panel", "--mode", "MDI", "--pwe", "on", *at(served))
        assert "written" in await ok("param", "set", "3401", "1", "--password", "XXXX", *at(served))
        line = await fails(
            EXIT_USAGE, "param", "set", "3401", "1", "--password", "XXXX",
            "--protocol", "native", *at(served), prefix="focas-net",
        )  # fmt: skip
        assert "FOCAS/2 has no cnc_wrunlockparam" in line


async def test_a_16i_real_parameter_over_focas2_gets_advice_that_fits() -> None:
    async with serving(load_machine(FWLIB_16I)) as served:
        await ok("sim", "panel", "--mode", "MDI", "--pwe", "on", *at(served))
        for value in ("5", "12.5"):
            line = await fails(
                EXIT_CNC, "param", "set", "1451", value, "--protocol", "native", *at(served)
            )
            assert "EW_LENGTH (2)" in line and "None" not in line, line
            assert "16i-class CNC" in line and "--protocol packed" in line, line
        assert "12.500" in await ok("param", "set", "1451", "12.5", *at(served))


async def test_control_commands_are_named_with_their_codes(server: Served) -> None:
    line = await fails(
        EXIT_USAGE,
        *("pmc", "write", "X", "0", "1", "--force", "--protocol", "native"),
        *at(server),
        prefix="focas-net",
    )
    assert "a simulator control command, sim_set_pmc (0x0E04); see" in line, line
    line = await fails(
        EXIT_USAGE, "macro", "clear", "100", "--protocol", "native", *at(server), prefix="focas-net"
    )
    assert "a simulator control command, sim_vacate_macro (0x0E11); see" in line, line
    out = await ok("serve", "--help")
    assert "0x0E01..0x0E21" in " ".join(out.split())
    await ok("sim", "fault", "delay", "--arg", "5000", *at(server))
    line = await fails(3, "status", "--timeout", "0.5", *at(server))
    assert "no answer to cnc_rdcncstat (0x0001): nothing received" in line, line


# -- D and E: a dropped connection read the same on both transports; probes take no fault -------

ON_PURPOSE = "so it closed this one on purpose (as a drop fault does: focas-net sim fault drop)"
#: What the packed advice adds: a packed server closes a frame longer than its --max-frame.
LONGER = ", or as a server does with a request longer than it takes (focas-net serve --max-frame)"


@pytest.mark.parametrize("protocol", ["packed", "native"])
async def test_the_probes_after_a_drop_take_no_fault_of_the_next_command(
    server: Served, protocol: str
) -> None:
    await ok("sim", "fault", "drop", "--count", "2", *at(server))
    for _ in range(2):  # each drop is the user's command's, diagnosed alike
        line = await fails(3, "status", "--protocol", protocol, *at(server))
        assert f"connection closed by 127.0.0.1:{server.port} before any answer" in line, line
        assert line.endswith(ON_PURPOSE + (LONGER if protocol == "packed" else "")), line
    assert await ok("sim", "faults", *at(server)) == "no pending faults of this machine\n"
    await ok("status", "--protocol", protocol, *at(server))


@pytest.mark.parametrize("protocol", ["packed", "native"])
async def test_a_timeout_names_what_went_unanswered(server: Served, protocol: str) -> None:
    await ok("sim", "fault", "delay", "--arg", "5000", *at(server))
    line = await fails(3, "status", "--protocol", protocol, "--timeout", "0.5", *at(server))
    assert line.startswith("focas-net: timed out after 0.5 s: no answer to ")
    assert line.count(f"127.0.0.1:{server.port}") == 1, line
    want = "cnc_rdcncstat (0x0001): nothing" if protocol == "packed" else "the connect requests"
    assert want in line, line


# -- C: watch and alarms --follow against a peer that never answers -----------------------------

#: The command lines that follow a machine, each bounded (a follower that did not give up
#: would end by --count, exit 0, and fail the test).
FOLLOWERS = (("watch", "--count", "3"), ("alarms", "--follow", "--count", "3"))


@asynccontextmanager
async def http_server(folder: Path) -> AsyncIterator[int]:
    """``python -m http.server`` on 127.0.0.1, an ephemeral port: its port."""
    proc = await asyncio.create_subprocess_exec(
        sys.executable, "-u", "-m", "http.server", "0", "--bind", "127.0.0.1",
        "--directory", str(folder),
        stdout=asyncio.subprocess.PIPE, stderr=asyncio.subprocess.DEVNULL,
    )  # fmt: skip
    try:
        assert proc.stdout is not None
        async with asyncio.timeout(SUBPROCESS_TIMEOUT):
            line = (await proc.stdout.readline()).decode()
        match = re.search(r"port (\d+)", line)
        assert match, line
        yield int(match[1])
    finally:
        proc.kill()
        await proc.wait()


def closed_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        port: int = s.getsockname()[1]
    return port


async def one_shot_and_followers(port: int, *extra: str) -> tuple[int, set[str]]:
    """The exit code and the line of ``status`` and of each follower against ``port``: each
    the same."""
    where = ["--host", "127.0.0.1", "--port", str(port), "--timeout", "1", *extra]
    results = set()
    for argv in (("status",), *FOLLOWERS):
        code, out, err = await run_focas_net(*argv, *where)
        assert out == "", (argv, out)
        results.add((code, one_line(err)))
    assert len(results) == 1, results
    ((code, line),) = results
    return code, {line}


async def test_followers_fail_at_a_tls_server_as_a_one_shot_command(
    certificate: tuple[Path, Path],
) -> None:
    ctx = ssl.SSLContext(ssl.PROTOCOL_TLS_SERVER)
    ctx.load_cert_chain(*certificate)
    async with serving(ssl=ctx) as served:
        code, (line,) = await one_shot_and_followers(served.port)
    assert code == 3
    assert line.endswith("the server uses TLS: give --tls (with --tls-ca FILE or --tls-insecure)")


async def test_followers_fail_at_a_plain_server_given_tls_as_a_one_shot_command(
    server: Served,
) -> None:
    code, (line,) = await one_shot_and_followers(server.port, "--tls-insecure")
    assert code == 3
    assert "TLS handshake failed" in line and line.endswith("drop --tls")


async def test_followers_fail_at_an_http_server_as_a_one_shot_command(tmp_path: Path) -> None:
    async with http_server(tmp_path) as port:
        code, (line,) = await one_shot_and_followers(port)
    assert code == 4
    assert "does not speak the FOCAS protocol" in line and line.endswith(": an HTTP server)")


async def test_followers_fail_at_a_closed_port_as_a_one_shot_command() -> None:
    port = closed_port()
    code, (line,) = await one_shot_and_followers(port)
    assert code == 3
    assert line == f"focas-net: cannot connect to 127.0.0.1:{port}: connection refused"


# -- B: a parameter value refused in the same words on both transports --------------------------


@pytest.mark.parametrize(
    ("number", "value", "words"),
    [
        ("1020", "300", "parameter 1020 is a byte parameter: 300 is outside -128..127"),
        ("1420", "5000000000", "parameter 1420 is a two-word parameter: 5000000000 is outside"),
        ("1420", "1.5", "parameter 1420 is not a real parameter: 1.5 is no integer"),
    ],
)
async def test_a_value_that_does_not_fit_reads_the_same_on_both_transports(
    server: Served, number: str, value: str, words: str
) -> None:
    lines = set()
    for protocol in ("packed", "native"):
        argv = ["param", "set", number, value, "--axis", "1", "--protocol", protocol]
        lines.add(await fails(EXIT_USAGE, *argv, *at(server)))
    assert lines == {f"focas-net: {words}"} or (
        len(lines) == 1 and lines.pop().startswith(f"focas-net: {words}")
    ), lines
