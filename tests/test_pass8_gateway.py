"""A new user's second pass over the gateway: the gateway's own name on the broker (two
gateways on one broker keep their births and wills apart), and the words of the MQTT client
and of the OPC UA server that the gateway rewords, checked against the libraries themselves
so that a change of their wording fails here rather than reaching a user."""

from __future__ import annotations

import asyncio
import contextlib
import gc
import json
import logging
import signal
import socket
from dataclasses import replace
from pathlib import Path
from typing import Literal

import aiomqtt
import pytest
from asyncua import Client, Server, ua
from cli_support import at, fails
from mosquitto_support import Broker, broker, mosquitto_binary, subscriber
from opcua_support import url as opcua_url
from poller_support import QUICK, RecordingSink, config
from support import free_port, reset_at_close, serving, wait_until

from focas_net.cli import EXIT_CNC, EXIT_PROTOCOL, EXIT_USAGE
from focas_net.cli._args import parse_log_level
from focas_net.client import FocasClient, NativeClient
from focas_net.errors import EW, CncError, FocasConnectionError
from focas_net.gateway import AlarmChange, Gateway, GatewayConfig
from focas_net.gateway._mqtt_messages import AlarmEvent, Publication
from focas_net.gateway._opcua_conditions import condition_name
from focas_net.gateway.config import (
    DEFAULT_GATEWAY,
    ConfigError,
    MqttSettings,
    OpcUaSettings,
    OpcUaUser,
    WriteGates,
    load_config,
    parse_config,
    shard,
)
from focas_net.gateway.mqtt import MqttSink, broker_reason
from focas_net.gateway.opcua import _TOLD, OpcUaSink, _Told
from focas_net.gateway.poller import reason_of
from focas_net.protocol.alarms import alarm_code
from focas_net.sim import load_machine

__all__ = ["broker"]  # the fixture, used by name

PLAIN = MqttSettings()
MACHINE = '[[machine]]\nname = "m1"\nhost = "127.0.0.1"\n'


# -- the gateway's name ------------------------------------------------------------------------
def test_the_file_names_the_gateway_or_its_client_id_does() -> None:
    named = parse_config(MACHINE + '[mqtt]\ngateway = "cell-7"\nclient_id = "c7"\n').mqtt
    assert named is not None and named.gateway_name == "cell-7"
    by_id = parse_config(MACHINE + '[mqtt]\nclient_id = "cell-8"\n').mqtt
    assert by_id is not None and by_id.gateway_name == "cell-8"
    plain = parse_config(MACHINE + "[mqtt]\n").mqtt
    assert plain is not None and plain.gateway_name == DEFAULT_GATEWAY == "focas-net"
    assert MqttSink(MqttSettings(client_id="cell-8")).publication.state_topic == (
        "focas/$gateway/cell-8/state"
    )


def test_each_shard_appends_its_number_to_the_gateway_s_name() -> None:
    text = '[[fleet]]\nname_prefix = "m"\nhost = "h"\nfirst_port = 9000\ncount = 2\n[mqtt]\n'
    for extra, names in (
        ('gateway = "cell-7"\n', ["cell-7-1", "cell-7-2"]),
        ('client_id = "c"\n', ["c-1", "c-2"]),
        ("", ["focas-net-1", "focas-net-2"]),
    ):
        config = parse_config(text + extra)
        sharded = [shard(config, i, 2).mqtt for i in (1, 2)]
        assert [s.gateway_name for s in sharded if s is not None] == names
        for settings in sharded:
            assert settings is not None
            settings.check()  # (a sink takes it)


@pytest.mark.parametrize(
    ("line", "said"),
    [
        ('gateway = ""', "mqtt.gateway: got ''; expected a non-empty string of printable"),
        ('gateway = "a\\nb"', "mqtt.gateway: got 'a\\\\nb'; expected a non-empty string of"),
        ("gateway = 7", "mqtt.gateway: got 7; expected a non-empty string of printable"),
        ('client_id = "c\\u0000"', "mqtt.client_id: got 'c\\\\x00'; expected a non-empty"),
        ('gateway_name = "x"', "mqtt.gateway_name: unknown key \\(did you mean 'gateway'\\?\\)"),
    ],
)
def test_a_gateway_name_a_topic_cannot_carry_is_refused_naming_the_key(
    line: str, said: str
) -> None:
    with pytest.raises(ConfigError, match=f"^plant.toml: {said}"):
        parse_config(MACHINE + f"[mqtt]\n{line}\n", "plant.toml")


async def test_two_gateways_on_one_broker_keep_their_birth_and_will_apart(broker: Broker) -> None:
    def sink(name: str) -> MqttSink:
        settings = MqttSettings(host=broker.host, port=broker.port, client_id=name)
        return MqttSink(settings, reconnect=(0.05, 0.2))

    async with subscriber(broker) as seen:
        async with sink("cell-1"):
            async with sink("cell-2"):
                await seen.until(
                    lambda s: (
                        s.latest("focas/$gateway/cell-1/state") == b"online"
                        and s.latest("focas/$gateway/cell-2/state") == b"online"
                    )
                )
            await seen.until(lambda s: s.latest("focas/$gateway/cell-2/state") == b"offline")
            assert seen.latest("focas/$gateway/cell-1/state") == b"online"
        await seen.until(lambda s: s.latest("focas/$gateway/cell-1/state") == b"offline")


# -- the MQTT client's words, as broker_reason rewords them --------------------------------------
async def _refusal(host: str, port: int, **options: object) -> aiomqtt.MqttError:
    try:
        async with aiomqtt.Client(host, port, **options):  # type: ignore[arg-type]
            pass
    except aiomqtt.MqttError as exc:
        return exc
    raise AssertionError(f"{host}:{port} took the connection")


async def test_a_closed_port_reads_connection_refused() -> None:
    port = free_port()
    exc = await _refusal("127.0.0.1", port)
    assert broker_reason(exc, MqttSettings(port=port)) == "connection refused"


async def test_a_peer_that_never_answers_connect_reads_as_no_answer() -> None:
    with socket.socket() as silent:  # (the kernel takes the connection; nobody answers)
        silent.bind(("127.0.0.1", 0))
        silent.listen()
        port = silent.getsockname()[1]
        exc = await _refusal("127.0.0.1", port, timeout=0.5)
    assert broker_reason(exc, MqttSettings(port=port)) == (
        "no answer to MQTT's CONNECT in time (is that a broker's port?)"
    )


async def test_a_name_that_does_not_resolve_is_the_resolver_s_words() -> None:
    exc = await _refusal("no-such-broker.invalid", 1883)
    said = broker_reason(exc, MqttSettings(host="no-such-broker.invalid"))
    assert "[Errno" not in said and said[:1].islower() and "name" in said


async def test_a_broker_that_refuses_the_client_is_named_with_its_reason_code(
    tmp_path: Path,
) -> None:
    binary = mosquitto_binary()
    if binary is None:
        pytest.skip("mosquitto is not installed (apt-get install mosquitto; .ci/run does)")
    closed = Broker(binary, tmp_path)
    closed.config.write_text(
        f"listener {closed.port} 127.0.0.1\nallow_anonymous false\npersistence false\nuser root\n"
    )
    await closed.start()
    try:
        exc = await _refusal(closed.host, closed.port, username="u", password="p")
    finally:
        await closed.stop()
    assert broker_reason(exc, MqttSettings(port=closed.port)) == (
        "the broker refused: not authorized (MQTT reason code 135)"
    )


# -- the OPC UA server's words, as the sink's filter knows them ---------------------------------
class _Records(logging.Handler):
    def __init__(self) -> None:
        super().__init__(logging.DEBUG)
        self.records: list[logging.LogRecord] = []

    def emit(self, record: logging.LogRecord) -> None:
        self.records.append(record)


async def _server_log(port: int, *, users: bool) -> list[logging.LogRecord]:
    """What asyncua's server logs while it starts on 127.0.0.1:``port`` (None security; user
    name tokens when ``users``), without the sink's filter."""
    records = _Records()
    logger = logging.getLogger("asyncua.server.server")
    logger.addHandler(records)
    server = Server()
    try:
        await server.init()
        server.set_endpoint(f"opc.tcp://127.0.0.1:{port}/focas_net/")
        server.set_security_policy([ua.SecurityPolicyType.NoSecurity])
        tokens = ua.UserNameIdentityToken if users else ua.AnonymousIdentityToken
        server.set_identity_tokens([tokens])
        try:
            await server.start()
        except OSError:
            return records.records
        await server.stop()
        return records.records
    finally:
        logger.removeHandler(records)


async def test_the_servers_words_on_a_port_in_use_are_the_ones_the_sink_tells_itself() -> None:
    with socket.socket() as taken:
        taken.bind(("127.0.0.1", 0))
        taken.listen()
        records = await _server_log(taken.getsockname()[1], users=False)
    told = [r for r in records if not _Told().filter(r)]
    assert told, f"asyncua no longer says {_TOLD[0]!r}: {[r.getMessage() for r in records]}"
    assert all(r.levelno >= logging.ERROR for r in told)


async def test_the_servers_words_on_unencrypted_passwords_are_the_ones_the_sink_warns_of() -> None:
    records = await _server_log(free_port(), users=True)
    told = [r for r in records if not _Told().filter(r)]
    assert told, f"asyncua no longer says {_TOLD[1]!r}: {[r.getMessage() for r in records]}"
    assert all("plaintext" in r.getMessage() for r in told)


# -- one refusal in one set of words over both transports -----------------------------------------
async def test_a_write_of_a_parameter_the_cnc_has_not_names_the_write_over_both_transports() -> (
    None
):
    """The packed client learns a parameter's width by reading it first; the CNC's refusal of
    that read is the write's refusal, named as the write (FOCAS/2 asks the same in the first
    frame of cnc_wrparam)."""
    async with serving() as served:
        said = {
            protocol: await fails(
                EXIT_CNC, "param", "set", "32000", "5", "--protocol", protocol, *at(served)
            )
            for protocol in ("packed", "native")
        }
        for client in (
            FocasClient(served.host, served.port),
            NativeClient(served.host, served.port),
        ):
            async with client:
                with pytest.raises(CncError) as refused:
                    await client.write_param(32000, 5)
                assert refused.value.ew == EW.NUMBER
                assert refused.value.detail == "cnc_wrparam: the CNC has no parameter 32000"
    assert (
        said["packed"]
        == said["native"]
        == (
            "focas-net: EW_NUMBER (3): data number / address range error (cnc_wrparam); "
            "the CNC has no parameter 32000"
        )
    )


# -- the broker's connection, told in words -----------------------------------------------------
def test_a_connection_lost_or_unacknowledged_is_not_told_as_a_refusal_or_a_wrong_port() -> None:
    lost = aiomqtt.MqttCodeError(7, "Could not publish message")
    assert broker_reason(lost, PLAIN, connected=True) == "the connection to the broker was lost"
    assert broker_reason(lost, PLAIN) == "the connection to the broker was lost"
    iteration = aiomqtt.MqttError("Disconnected during message iteration")
    assert broker_reason(iteration, PLAIN) == "the connection to the broker was lost"
    late = aiomqtt.MqttError("Operation timed out")
    assert broker_reason(late, PLAIN, connected=True) == (
        "the broker acknowledged no message in time: the connection is taken as lost"
    )
    assert broker_reason(late, PLAIN, reached=True) == "no answer to MQTT's CONNECT in time"
    reset = "[Errno 104] Connection reset by peer"
    assert broker_reason(late, PLAIN, socket_error=reset) == (
        "connection reset by peer before any answer to MQTT's CONNECT (is that a broker's port?)"
    )


def _warnings(caplog: pytest.LogCaptureFixture) -> list[str]:
    return [r.getMessage() for r in caplog.records if r.name == "focas_net.gateway.mqtt"]


async def _until_warned(caplog: pytest.LogCaptureFixture, words: str) -> None:
    for _ in range(2000):  # bounded: 20 s
        if any(words in w for w in _warnings(caplog)):
            return
        await asyncio.sleep(0.01)
    raise AssertionError(f"never warned {words!r}: {_warnings(caplog)}")


async def test_a_peer_that_resets_the_connection_is_one_warning_in_words(
    caplog: pytest.LogCaptureFixture,
) -> None:
    """The MQTT client's own ``failed to receive on socket: [Errno 104] ...`` stays out of the
    log; the sink's warning says it in words."""
    caplog.set_level(logging.WARNING)

    async def closing(reader: asyncio.StreamReader, writer: asyncio.StreamWriter) -> None:
        # a reset, what a port forwarder with nothing behind does (a bare abort before the
        # CONNECT came would close cleanly instead)
        reset_at_close(writer.get_extra_info("socket"))
        writer.transport.abort()

    server = await asyncio.start_server(closing, "127.0.0.1", 0)
    async with server:
        port = server.sockets[0].getsockname()[1]
        settings = MqttSettings(port=port)
        async with MqttSink(settings, reconnect=(5.0, 5.0), timeout=0.5):
            await _until_warned(caplog, "before any answer")
    said = [r.getMessage() for r in caplog.records]
    told = (
        f"MQTT broker 127.0.0.1:{port}: connection reset by peer before any answer to MQTT's "
        "CONNECT (is that a broker's port?)"
    )
    assert told in said, said
    assert not any("Errno" in line for line in said), said


async def test_a_broker_that_stops_answering_or_dies_is_told_so_and_its_return_too(
    broker: Broker, caplog: pytest.LogCaptureFixture
) -> None:
    caplog.set_level(logging.WARNING)
    settings = MqttSettings(host=broker.host, port=broker.port)
    process = broker._process
    assert process is not None
    async with MqttSink(settings, reconnect=(0.05, 0.2), timeout=0.5) as sink:
        await wait_until(lambda: sink.connected)
        process.send_signal(signal.SIGSTOP)  # (the host hangs: nothing is acknowledged)
        try:
            sink.online("m1", True, "", 0.0)
            await _until_warned(caplog, "acknowledged no message in time")
            await _until_warned(caplog, "no answer to MQTT's CONNECT in time")
        finally:
            process.send_signal(signal.SIGCONT)
        await _until_warned(caplog, "connected again")
        await broker.stop()
        await _until_warned(caplog, "the connection to the broker was lost")
        caplog.clear()
        await broker.start()
        await _until_warned(caplog, "connected again")
    said = _warnings(caplog)
    assert not any("message iteration" in w or "is that a broker's port" in w for w in said)
    gc.collect()  # (a connection attempt given up, answered late, is no news either)
    assert not [r.getMessage() for r in caplog.records if r.name == "asyncio"]


# -- the docs' example: what its gateway may write, its machine has --------------------------------
EXAMPLES = Path(__file__).resolve().parent.parent / "examples"


def test_what_the_example_gateway_opens_to_writes_the_example_machine_has() -> None:
    """``examples/gateway.toml`` in front of ``examples/lathe_2path.toml`` (docs/gateway.md,
    Running): every parameter, macro variable and PMC byte its write gates open is one the
    machine has, and the parts the slow group reads (6713 too) are there."""
    config = load_config(EXAMPLES / "gateway.toml")
    lathe = load_machine(EXAMPLES / "lathe_2path.toml")
    opened = [m for m in config.machines if m.writes != WriteGates()]
    assert opened
    for machine in opened:
        for path in machine.paths or (1, 2):
            for first, last in machine.writes.params:
                for number in range(first, last + 1):
                    lathe.read_param(number, 0, path=path)
            for first, last in machine.writes.macros:
                for number in (first, last):
                    lathe.read_macro(number, path=path)
        for letter, first, last in machine.writes.pmc:
            assert len(lathe.read_pmc(letter, first, last - first + 1)) == last - first + 1
    for path in (1, 2):
        lathe.read_param(6713, 0, path=path)


@pytest.mark.parametrize("command", ["serve", "gateway"])
async def test_a_log_level_refused_is_named_as_typed_and_any_case_is_taken(command: str) -> None:
    said = await fails(
        EXIT_USAGE, command, "gateway.toml", "--log-level", "verbose", prefix="focas-net"
    )
    assert said == (
        f"focas-net {command}: error: argument --log-level: invalid choice: 'verbose' (choose "
        f"from DEBUG, INFO, WARNING, ERROR, CRITICAL, in any case); see focas-net {command} --help"
    )
    assert parse_log_level(" info ") == "INFO"


@pytest.mark.parametrize("item", ["mode", "alarm", "message"])
def test_a_deadband_of_an_item_without_a_unit_says_so_rather_than_unknown_key(item: str) -> None:
    with pytest.raises(ConfigError) as refused:
        parse_config(MACHINE + f"[mqtt]\ndeadbands = {{ {item} = 1 }}\n", "plant.toml")
    said = str(refused.value)
    assert said.startswith(
        f"plant.toml: mqtt.deadbands.{item}: {item} is not a number with a unit (the items a "
        "deadband is for: absolute, cutting_time, "
    )
    assert "unknown key" not in said
    with pytest.raises(ConfigError, match=f"^mqtt.deadbands.{item}: {item} is not a number"):
        MqttSettings(deadbands={item: 1.0}).check()


@pytest.mark.parametrize(("alm_type", "number", "axis"), [(15, 1001, 0), (6, 411, 2), (14, 1, 0)])
def test_an_alarm_on_mqtt_carries_the_code_the_cli_and_opc_ua_show(
    alm_type: int, number: int, axis: int
) -> None:
    change = AlarmChange("m1", 1, alm_type, number, axis, "COOLANT LEVEL LOW", True, 0.0)
    event, active = Publication("focas", "gw", {}).alarms([change])
    code = alarm_code(alm_type, number)  # (the CLI's `alarms --json` code)
    assert json.loads(event.payload)["code"] == code
    assert json.loads(active.payload)["alarms"][0]["code"] == code
    assert condition_name(alm_type, number, axis) == (f"{code}/{axis}" if axis else code)
    assert AlarmEvent.decode(event.payload).alm_no == number


# -- a port that is an HTTP server, as the command line and the gateway name it --------------------
@pytest.mark.parametrize("protocol", ["native", "packed"])
async def test_an_http_server_where_a_cnc_was_expected_is_named_alike_by_cli_and_gateway(
    protocol: Literal["native", "packed"],
) -> None:
    async def http(reader: asyncio.StreamReader, writer: asyncio.StreamWriter) -> None:
        with contextlib.suppress(OSError, asyncio.IncompleteReadError):
            await reader.readuntil(b"\r\n\r\n")  # (a FOCAS frame never ends a request line)
            writer.write(b"HTTP/1.0 404 Not Found\r\n\r\n")
            await writer.drain()
        writer.close()

    server = await asyncio.start_server(http, "127.0.0.1", 0)
    async with server:
        port = server.sockets[0].getsockname()[1]
        said = await fails(
            EXIT_PROTOCOL, "status", "--protocol", protocol, "--timeout", "0.5", "--port", str(port)
        )
        sink = RecordingSink()
        gateway = Gateway(
            GatewayConfig((replace(config("web", port, protocol), timeout=0.5),)), policy=QUICK
        )
        gateway.add_sink(sink)
        async with gateway:
            await wait_until(lambda: any(not up for _, up, _ in sink.states))
        reasons = [why for _, up, why in sink.states if not up]
    assert said == (
        f"focas-net: 127.0.0.1:{port} does not speak the FOCAS protocol (it answers "
        "'HTTP/1.0 404' to an HTTP request and no FOCAS frame: an HTTP server)"
    )
    assert reasons[0] == "protocol: " + said.removeprefix("focas-net: ")


# -- OPC UA certificate files -------------------------------------------------------------------
async def test_a_certificate_or_key_the_server_cannot_load_names_the_key_and_the_file(
    tmp_path: Path,
) -> None:
    garbage = tmp_path / "garbage.pem"
    garbage.write_text("not a certificate\n")
    settings = OpcUaSettings(
        endpoint="opc.tcp://127.0.0.1:0/focas_net/",
        users=(OpcUaUser("operator", "s3cret"),),
        certificate=garbage,
        private_key=garbage,
    )
    with pytest.raises(ConfigError) as refused:
        async with OpcUaSink(settings):
            pass
    said = str(refused.value)
    assert said.startswith(
        f"opcua.certificate: got {str(garbage)!r}; expected a certificate in PEM or DER ("
    )
    assert "http" not in said


def test_a_certificate_that_is_a_folder_is_not_said_not_to_exist(tmp_path: Path) -> None:
    (tmp_path / "certs").mkdir()
    (tmp_path / "key.pem").write_text("")
    text = MACHINE + '[opcua]\ncertificate = "certs"\nprivate_key = "key.pem"\n'
    with pytest.raises(ConfigError) as refused:
        parse_config(text, "plant.toml", folder=tmp_path)
    assert str(refused.value) == (
        "plant.toml: opcua.certificate: got 'certs'; expected a file that exists "
        f"({tmp_path / 'certs'} is a directory)"
    )


async def test_a_host_name_without_an_address_is_unresolved_not_lost() -> None:
    for client_type in (FocasClient, NativeClient):
        with pytest.raises(FocasConnectionError) as failed:
            async with client_type("no-such-host.invalid", 8193, timeout=2.0):
                pass
        assert reason_of(failed.value) == f"unresolved: {failed.value}"
    assert reason_of(FocasConnectionError("gone")) == "lost: gone"


async def test_a_refused_opc_ua_session_is_one_warning_naming_the_user(
    caplog: pytest.LogCaptureFixture,
) -> None:
    """asyncua's own ERROR lines of a refused session name nobody; the sink tells each refusal
    once at WARNING, with the user and why (and fails here if asyncua's words change)."""
    caplog.set_level(logging.INFO)
    settings = OpcUaSettings(
        endpoint="opc.tcp://127.0.0.1:0/focas_net/",
        users=(OpcUaUser("op", "s3cret"),),
        anonymous=False,
    )
    async with OpcUaSink(settings) as sink:
        for user, password in (("op", "wrong"), ("nobody", "x"), (None, None)):
            client = Client(opcua_url(sink))
            if user is not None:
                client.set_user(user)
                client.set_password(password or "")
            with pytest.raises(ua.UaStatusCodeError):
                async with client:
                    pass
    ours = [r.getMessage() for r in caplog.records if r.name == "focas_net.gateway.opcua"]
    assert "OPC UA: user 'op' refused: wrong password" in ours
    assert "OPC UA: user 'nobody' refused: no such user" in ours
    assert any(m.startswith("OPC UA: a session refused: its identity is not offered") for m in ours)
    theirs = [
        r.getMessage()
        for r in caplog.records
        if r.name.startswith("asyncua.server") and r.levelno >= logging.WARNING
    ]
    assert not [m for m in theirs if "refused" in m.lower() or "Bad" in m or "Reject" in m]


def _self_signed(folder: Path) -> tuple[Path, Path]:
    """A self-signed certificate for 127.0.0.1 and its key, PEM files in ``folder``."""
    import datetime

    from cryptography import x509
    from cryptography.hazmat.primitives import hashes, serialization
    from cryptography.hazmat.primitives.asymmetric import rsa
    from cryptography.x509.oid import NameOID

    key = rsa.generate_private_key(public_exponent=65537, key_size=2048)
    name = x509.Name([x509.NameAttribute(NameOID.COMMON_NAME, "127.0.0.1")])
    now = datetime.datetime.now(datetime.UTC)
    cert = (
        x509.CertificateBuilder()
        .subject_name(name)
        .issuer_name(name)
        .public_key(key.public_key())
        .serial_number(x509.random_serial_number())
        .not_valid_before(now - datetime.timedelta(days=1))
        .not_valid_after(now + datetime.timedelta(days=1))
        .sign(key, hashes.SHA256())
    )
    cert_file, key_file = folder / "broker.crt", folder / "broker.key"
    cert_file.write_bytes(cert.public_bytes(serialization.Encoding.PEM))
    key_file.write_bytes(
        key.private_bytes(
            serialization.Encoding.PEM,
            serialization.PrivateFormat.TraditionalOpenSSL,
            serialization.NoEncryption(),
        )
    )
    return cert_file, key_file


async def test_a_tls_broker_whose_certificate_is_not_trusted_is_told_so_not_a_wrong_port(
    tmp_path: Path, caplog: pytest.LogCaptureFixture
) -> None:
    binary = mosquitto_binary()
    if binary is None:
        pytest.skip("mosquitto is not installed (apt-get install mosquitto; .ci/run does)")
    caplog.set_level(logging.WARNING)
    cert, key = _self_signed(tmp_path)
    tls = Broker(binary, tmp_path)
    tls.config.write_text(
        f"listener {tls.port} 127.0.0.1\nallow_anonymous true\npersistence false\nuser root\n"
        f"certfile {cert}\nkeyfile {key}\n"
    )
    await tls.start()
    try:
        settings = MqttSettings(host=tls.host, port=tls.port, tls=True)
        async with MqttSink(settings, reconnect=(5.0, 5.0), timeout=2.0):
            await _until_warned(caplog, "TLS certificate not trusted")
    finally:
        await tls.stop()
    assert (
        f"MQTT broker 127.0.0.1:{tls.port}: TLS certificate not trusted: self-signed "
        "certificate (the gateway trusts the certificate authorities of the system)"
    ) in _warnings(caplog)
