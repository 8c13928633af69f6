"""``focas-net gateway CONFIG.toml`` as a user runs it: a ready line, a clean end on SIGINT
and SIGTERM, one line and exit 2 for a bad file, a bad ``--shard`` or a missing extra."""

from __future__ import annotations

import asyncio
import signal
import sys
from pathlib import Path

import pytest
from cli_support import SUBPROCESS_TIMEOUT, fails, gateway_process, one_line
from support import serving

from focas_net.cli import EXIT_OK, EXIT_USAGE


def write_config(folder: Path, text: str) -> Path:
    path = folder / "plant.toml"
    path.write_text(text)
    return path


def machine(name: str, port: int, protocol: str = "native") -> str:
    return f'[[machine]]\nname = "{name}"\nhost = "127.0.0.1"\nport = {port}\n' + (
        f'protocol = "{protocol}"\n'
    )


@pytest.mark.parametrize(
    ("text", "words"),
    [
        (machine("a", 70000), "machine[1].port: got 70000; expected a port 1..65535"),
        (
            machine("a", 1) + "[groups]\nfsat = 1\n",
            "groups.fsat: unknown key (did you mean 'fast'?)",
        ),
        ("", "no machine"),
    ],
)
async def test_a_bad_file_is_one_line_and_exit_2(tmp_path: Path, text: str, words: str) -> None:
    config = write_config(tmp_path, text)
    line = await fails(EXIT_USAGE, "gateway", str(config), prefix="focas-net gateway: error: ")
    assert str(config) in line and words in line


async def test_a_missing_file_and_a_bad_shard_are_exit_2(tmp_path: Path) -> None:
    line = await fails(
        EXIT_USAGE, "gateway", str(tmp_path / "none.toml"), prefix="focas-net gateway: error: "
    )
    assert "none.toml: no such file" in line
    config = write_config(tmp_path, machine("a", 8193) + machine("b", 8194))
    line = await fails(
        EXIT_USAGE, "gateway", str(config), "--shard", "3/2", prefix="focas-net gateway: error: "
    )
    assert line.endswith(
        "argument --shard: the shard must be within 1..2, got '3/2'; see focas-net gateway --help"
    )
    line = await fails(
        EXIT_USAGE, "gateway", str(config), "--shard", "half", prefix="focas-net gateway: error: "
    )
    assert "argument --shard: give the shard as I/N" in line
    line = await fails(  # digits of another script are no shard number
        EXIT_USAGE, "gateway", str(config), "--shard", "\u0661/\u0662",
        prefix="focas-net gateway: error: ",
    )  # fmt: skip
    assert "argument --shard: give the shard as I/N" in line


async def test_an_output_without_its_package_names_the_extra(tmp_path: Path) -> None:
    config = write_config(tmp_path, machine("a", 8193) + "[mqtt]\n")
    blocked = (
        "import sys; sys.modules['aiomqtt'] = None; sys.modules['asyncua'] = None; "
        "from focas_net.cli import main; sys.exit(main(sys.argv[1:]))"
    )
    proc = await asyncio.create_subprocess_exec(
        sys.executable, "-c", blocked, "gateway", str(config),
        stdout=asyncio.subprocess.PIPE, stderr=asyncio.subprocess.PIPE,
    )  # fmt: skip
    async with asyncio.timeout(SUBPROCESS_TIMEOUT):
        out, err = await proc.communicate()
    assert proc.returncode == EXIT_USAGE
    assert out == b""
    line = one_line(err.decode(), "focas-net gateway: error: ")
    assert "[mqtt] needs" in line and "pip install 'focas-net[gateway]'" in line


@pytest.mark.parametrize("signum", [signal.SIGTERM, signal.SIGINT])
async def test_it_polls_until_told_to_stop(tmp_path: Path, signum: signal.Signals) -> None:
    async with serving() as mill:
        async with serving() as gone:
            dead = gone.port  # a machine that cannot be reached is no error
        config = write_config(
            tmp_path, machine("mill", mill.port) + machine("packed", mill.port, "packed")
            + machine("dead", dead)
        )  # fmt: skip
        async with gateway_process(str(config), "--shard", "1/1") as gateway:
            assert gateway.ready == (
                "focas-net: gateway polling 3 machines (shard 1/1); no output ([mqtt] or [opcua])\n"
            )
            for _ in range(200):  # the gateway's connections reach the machine
                if mill.listener.native_connections:
                    break
                await asyncio.sleep(0.02)
            assert mill.listener.native_connections
            assert await gateway.stop(signum) == EXIT_OK, gateway.err
        assert gateway.out == b""
        err = gateway.err
        assert b"Traceback" not in err


def test_log_level_is_focas_nets_and_other_libraries_stay_at_warning() -> None:
    import logging

    from focas_net.cli.gateway_cmd import log_to_stderr

    root, ours = logging.getLogger(), logging.getLogger("focas_net")
    saved = (root.level, list(root.handlers), ours.level)
    root.handlers.clear()
    try:
        log_to_stderr("INFO")
        assert ours.getEffectiveLevel() == logging.INFO
        assert logging.getLogger("focas_net.gateway.poller").isEnabledFor(logging.INFO)
        assert not logging.getLogger("asyncua.server").isEnabledFor(logging.INFO)
        assert logging.getLogger("asyncua.server").isEnabledFor(logging.WARNING)
        root.handlers.clear()
        log_to_stderr("ERROR")
        assert not ours.isEnabledFor(logging.WARNING)
        assert not logging.getLogger("asyncua").isEnabledFor(logging.WARNING)
    finally:
        root.handlers[:] = saved[1]
        root.setLevel(saved[0])
        ours.setLevel(saved[2])


async def test_the_ready_line_names_the_port_an_opc_ua_server_of_port_0_took(
    tmp_path: Path,
) -> None:
    async with serving() as mill:
        config = write_config(
            tmp_path,
            machine("mill", mill.port) + '[opcua]\nendpoint = "opc.tcp://127.0.0.1:0/plant"\n',
        )
        async with gateway_process(str(config)) as gateway:
            line = gateway.ready
            head, _, endpoint = line.rstrip("\n").partition("; OPC UA ")
            assert head == "focas-net: gateway polling 1 machine", line
            host_port = endpoint.removeprefix("opc.tcp://").removesuffix("/plant")
            host, _, port = host_port.rpartition(":")
            assert host == "127.0.0.1" and int(port) != 0, line
            _reader, writer = await asyncio.open_connection(host, int(port))  # it listens there
            writer.close()
            await writer.wait_closed()
            assert await gateway.stop() == EXIT_OK, gateway.err
