"""A parameter password is 1..4 ASCII characters everywhere, and only an exact match unlocks.

The machine, the machine file, ``serve --param-password``, ``unlock``, ``--password`` and the
client's ``password=`` refuse a longer one naming what was typed; on the wire a 0x0105 payload
longer than 4 bytes is a wrong password (EW_PASSWD), never a prefix match.
"""

from __future__ import annotations

import asyncio
import sys
from collections.abc import AsyncIterator

import pytest
from cli_support import Cli, run_focas_net
from support import Served, serving

from focas_net.cli import EXIT_CNC, EXIT_USAGE
from focas_net.client import FocasClient
from focas_net.errors import EW, AccessDeniedError
from focas_net.protocol import Command, ParamValue, Password
from focas_net.sim import MachineError, default_machine
from focas_net.web import Station, perform

START_TIMEOUT = 30.0


@pytest.mark.parametrize("bad", ["12345", "123456", "", "\u20ac", "12\x003"])
def test_machine_refuses_a_password_that_is_not_1_to_4_ascii(bad: str) -> None:
    with pytest.raises(ValueError, match=r"parameter password") as exc:
        default_machine(param_password=bad)
    assert repr(bad) in str(exc.value)
    m = default_machine(param_password="1234")
    with pytest.raises(ValueError, match=r"parameter password"):
        m.set_param_password(bad)


@pytest.mark.parametrize("typed", ["1234xx", "1234WRONG", "123", "12345", "1234\x00"])
def test_machine_unlock_is_an_exact_match(typed: str) -> None:
    m = default_machine(param_password="1234")
    s = m.new_session()
    m.unlock(s, "1234")
    assert s.unlocked
    with pytest.raises(MachineError) as exc:
        m.unlock(s, typed)
    assert exc.value.ew == EW.PASSWD
    assert not s.unlocked  # a failed unlock locks the session again


def test_a_short_password_is_no_prefix_of_a_longer_one() -> None:
    m = default_machine(param_password="12")
    s = m.new_session()
    with pytest.raises(MachineError):
        m.unlock(s, "1234")
    m.unlock(s, "12")
    assert s.unlocked


@pytest.mark.parametrize("bad", ["12345", "", "\u00e9"])
def test_password_payload_refuses_what_it_cannot_carry(bad: str) -> None:
    with pytest.raises(ValueError, match=r"parameter password") as exc:
        Password.from_text(bad)
    assert repr(bad) in str(exc.value)
    assert Password.from_text("12").encode() == b"12\x00\x00"


@pytest.mark.parametrize("payload", [b"1234xx", b"1234WRONG", b"12345"])
async def test_a_long_unlock_payload_is_a_wrong_password(payload: bytes) -> None:
    async with serving(default_machine(param_password="1234")) as served:
        async with await served.connect() as w:
            assert await w.ew(Command.WRUNLOCKPARAM, b"1234") == 0
            assert await w.ew(Command.WRUNLOCKPARAM, payload) == EW.PASSWD
            # the failed unlock locked the connection: writes need a new unlock
            served.machine.set_panel(0, 1, 0)
            assert await w.ew(Command.WRPARAM, ParamValue(6711, 0, 42, 4).encode()) == EW.PASSWD


async def test_client_refuses_a_long_password_before_sending(server: Served) -> None:
    with pytest.raises(ValueError, match=r"'12345'"):
        FocasClient(server.host, server.port, password="12345")
    async with FocasClient(server.host, server.port) as cnc:
        with pytest.raises(ValueError, match=r"'1234xx'"):
            await cnc.unlock("1234xx")


async def test_client_long_password_against_a_4_character_one() -> None:
    async with serving(default_machine(param_password="1234")) as served:
        async with FocasClient(served.host, served.port) as cnc:
            await cnc.unlock("1234")
            with pytest.raises(AccessDeniedError):
                await cnc.unlock("123")


@pytest.fixture
async def locked_cli(capsys: pytest.CaptureFixture[str]) -> AsyncIterator[Cli]:
    async with serving(default_machine(param_password="1234")) as served:
        yield Cli(served, capsys)


async def test_cli_unlock_refuses_a_long_password(locked_cli: Cli) -> None:
    for typed in ("1234xx", "1234WRONG"):  # refused by the parser, naming the argument
        code, out, err = await run_focas_net("unlock", typed, "--port", str(locked_cli.served.port))
        assert (code, out) == (EXIT_USAGE, "")
        assert err.startswith(
            f"focas-net unlock: error: argument PASSWORD: parameter password {typed!r}: "
            "must be 1..4 ASCII characters; "
        )
    await locked_cli.fails(EXIT_CNC, "unlock", "4321")
    await locked_cli.ok("unlock", "1234")


async def test_cli_password_option_refuses_a_long_password(locked_cli: Cli) -> None:
    port = str(locked_cli.served.port)
    code, out, err = await run_focas_net(
        "param", "set", "6711", "42", "--password", "1234zzz", "--port", port
    )
    assert (code, out) == (EXIT_USAGE, "")
    assert err.startswith(
        "focas-net param set: error: argument --password: parameter password '1234zzz': must "
        "be 1..4 ASCII characters; "
    )
    assert locked_cli.served.machine.read_param(6711, 0) == 0


async def _serve_to_exit(*args: str) -> tuple[int, str, str]:
    proc = await asyncio.create_subprocess_exec(
        sys.executable, "-m", "focas_net", "serve", "--port", "0", *args,
        stdout=asyncio.subprocess.PIPE, stderr=asyncio.subprocess.PIPE,
    )  # fmt: skip
    async with asyncio.timeout(START_TIMEOUT):
        out, err = await proc.communicate()
    assert proc.returncode is not None
    return proc.returncode, out.decode(), err.decode()


async def test_serve_refuses_a_long_param_password() -> None:
    code, out, err = await _serve_to_exit("--param-password", "123456")
    assert code == 2
    assert out == ""
    assert "'123456'" in err and "1..4" in err
    assert "Traceback" not in err


@pytest.mark.parametrize("typed", ["", "a\u00e9", "12345", "12\x00"])
@pytest.mark.parametrize("password", [None, "1234"])
def test_the_machine_refuses_text_that_is_no_password(typed: str, password: str | None) -> None:
    """1..4 ASCII characters, checked by the machine so the page (and every front end) says
    so, with or without a password set; the session stays locked."""
    m = default_machine(param_password=password)
    s = m.new_session()
    with pytest.raises(MachineError, match=r"must be 1\.\.4 ASCII characters") as exc:
        m.unlock(s, typed)
    assert exc.value.ew == EW.PASSWD and not s.unlocked
    station = Station(0, m)
    with pytest.raises(MachineError, match=r"must be 1\.\.4 ASCII"):
        perform(station, "unlock", {"password": typed})
