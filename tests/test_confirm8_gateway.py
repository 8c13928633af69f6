"""A confirming pass over the gateway: a broker whose certificate a private certificate
authority signed (``mqtt.tls_ca``, the clients' ``--tls-ca``), refused in the command line's
words when the file cannot be loaded, and reached live over TLS."""

from __future__ import annotations

import argparse
import asyncio
import datetime
import ipaddress
import logging
import ssl
from pathlib import Path

import aiomqtt
import pytest
from mosquitto_support import BOUND, Broker, mosquitto_binary

from focas_net.cli._run import tls_context
from focas_net.gateway.config import ConfigError, MqttSettings, OpcUaSettings, parse_config
from focas_net.gateway.mqtt import MqttSink

MACHINE = '[[machine]]\nname = "m1"\nhost = "127.0.0.1"\n'


def _private_ca(folder: Path) -> tuple[Path, Path, Path]:
    """A certificate authority's certificate, and a broker certificate for 127.0.0.1 it
    signed with that broker's key: PEM files in ``folder``."""
    from cryptography import x509
    from cryptography.hazmat.primitives import hashes, serialization
    from cryptography.hazmat.primitives.asymmetric import rsa
    from cryptography.x509.oid import NameOID

    now = datetime.datetime.now(datetime.UTC)
    ca_key = rsa.generate_private_key(public_exponent=65537, key_size=2048)
    ca_name = x509.Name([x509.NameAttribute(NameOID.COMMON_NAME, "plant CA")])
    ca = (
        x509.CertificateBuilder()
        .subject_name(ca_name)
        .issuer_name(ca_name)
        .public_key(ca_key.public_key())
        .serial_number(x509.random_serial_number())
        .not_valid_before(now - datetime.timedelta(days=1))
        .not_valid_after(now + datetime.timedelta(days=1))
        .add_extension(x509.BasicConstraints(ca=True, path_length=None), critical=True)
        .add_extension(
            x509.KeyUsage(
                digital_signature=True, content_commitment=False, key_encipherment=False,
                data_encipherment=False, key_agreement=False, key_cert_sign=True,
                crl_sign=True, encipher_only=False, decipher_only=False,
            ),
            critical=True,
        )
        .add_extension(
            x509.SubjectKeyIdentifier.from_public_key(ca_key.public_key()), critical=False
        )
        .sign(ca_key, hashes.SHA256())
    )  # fmt: skip
    key = rsa.generate_private_key(public_exponent=65537, key_size=2048)
    leaf = (
        x509.CertificateBuilder()
        .subject_name(x509.Name([x509.NameAttribute(NameOID.COMMON_NAME, "broker")]))
        .issuer_name(ca_name)
        .public_key(key.public_key())
        .serial_number(x509.random_serial_number())
        .not_valid_before(now - datetime.timedelta(days=1))
        .not_valid_after(now + datetime.timedelta(days=1))
        .add_extension(
            x509.SubjectAlternativeName([x509.IPAddress(ipaddress.ip_address("127.0.0.1"))]),
            critical=False,
        )
        .add_extension(
            x509.AuthorityKeyIdentifier.from_issuer_public_key(ca_key.public_key()),
            critical=False,
        )
        .sign(ca_key, hashes.SHA256())
    )
    ca_file, cert_file, key_file = folder / "ca.pem", folder / "broker.crt", folder / "broker.key"
    ca_file.write_bytes(ca.public_bytes(serialization.Encoding.PEM))
    cert_file.write_bytes(leaf.public_bytes(serialization.Encoding.PEM))
    key_file.write_bytes(
        key.private_bytes(
            serialization.Encoding.PEM,
            serialization.PrivateFormat.TraditionalOpenSSL,
            serialization.NoEncryption(),
        )
    )
    return ca_file, cert_file, key_file


# -- mqtt.tls_ca: the file ---------------------------------------------------------------------
def test_tls_ca_is_read_from_the_configuration_file_s_folder(tmp_path: Path) -> None:
    ca, _cert, _key = _private_ca(tmp_path)
    mqtt = parse_config(MACHINE + '[mqtt]\ntls = true\ntls_ca = "ca.pem"\n', folder=tmp_path).mqtt
    assert mqtt is not None and mqtt.tls_ca == ca
    context = mqtt.tls_context()
    assert context is not None and context.verify_mode == ssl.CERT_REQUIRED
    assert context.check_hostname
    assert [c["subject"] for c in context.get_ca_certs()] == [((("commonName", "plant CA"),),)]


def test_tls_ca_without_tls_is_refused_naming_both_keys(tmp_path: Path) -> None:
    _private_ca(tmp_path)
    with pytest.raises(ConfigError) as refused:
        parse_config(MACHINE + '[mqtt]\ntls_ca = "ca.pem"\n', "plant.toml", folder=tmp_path)
    assert str(refused.value) == (
        f"plant.toml: mqtt.tls_ca: got '{tmp_path / 'ca.pem'}' with tls = false; expected "
        "tls = true (the CA file checks the broker's TLS certificate)"
    )


@pytest.mark.parametrize(
    ("content", "words"),
    [
        (None, "no such file or directory"),
        (b"not a certificate\n", "no PEM certificate in it"),
        (
            b"-----BEGIN CERTIFICATE-----\nAAAA\n-----END CERTIFICATE-----\n",
            "a certificate in it cannot be read",
        ),
    ],
)
def test_a_ca_file_that_cannot_be_loaded_is_refused_in_the_clients_words(
    tmp_path: Path, content: bytes | None, words: str
) -> None:
    ca = tmp_path / "ca.pem"
    if content is not None:
        ca.write_bytes(content)
    with pytest.raises(ConfigError) as refused:
        parse_config(
            MACHINE + '[mqtt]\ntls = true\ntls_ca = "ca.pem"\n', "plant.toml", folder=tmp_path
        )
    message = str(refused.value)
    assert message.startswith(f"plant.toml: mqtt.tls_ca: got '{ca}': ")
    assert words.lower() in message.lower()
    # the command line's --tls-ca refuses the same file with the same reason
    with pytest.raises(ValueError, match=r"^argument --tls-ca: ") as cli:
        tls_context(argparse.Namespace(tls=True, tls_ca=str(ca), tls_insecure=False))
    assert message.split(": ", 3)[3] == str(cli.value).split(": ", 2)[2]


def test_settings_built_in_python_are_refused_as_the_file_s_are(tmp_path: Path) -> None:
    with pytest.raises(ConfigError, match=r"^mqtt\.tls_ca: got .* with tls = false"):
        MqttSink(MqttSettings(tls_ca=tmp_path / "ca.pem"))
    with pytest.raises(ConfigError, match=r"^mqtt\.tls_ca: got 5; expected a PEM file"):
        MqttSettings(tls=True, tls_ca=5).check()  # type: ignore[arg-type]


# -- mqtt.tls_ca: live -------------------------------------------------------------------------
async def test_a_broker_a_private_ca_signed_is_reached_with_tls_ca(tmp_path: Path) -> None:
    binary = mosquitto_binary()
    if binary is None:
        pytest.skip("mosquitto is not installed (apt-get install mosquitto; .ci/run does)")
    ca, cert, key = _private_ca(tmp_path)
    broker = Broker(binary, tmp_path)
    broker.config.write_text(
        f"listener {broker.port} 127.0.0.1\nallow_anonymous true\npersistence false\n"
        f"user root\ncertfile {cert}\nkeyfile {key}\n"
    )
    await broker.start()
    try:
        settings = MqttSettings(host=broker.host, port=broker.port, tls=True, tls_ca=ca)
        trusting = ssl.create_default_context(cafile=ca)
        async with (
            aiomqtt.Client(broker.host, broker.port, tls_context=trusting) as watcher,
            asyncio.timeout(BOUND),
        ):
            await watcher.subscribe("focas/$gateway/+/state", qos=1)
            async with MqttSink(settings, reconnect=(0.1, 0.5), timeout=2.0) as sink:
                async for message in watcher.messages:  # bounded by BOUND
                    if message.payload == b"online":
                        break
                assert sink.connected
                assert message.topic.value == "focas/$gateway/focas-net/state"
    finally:
        await broker.stop()


# -- a refused OPC UA write: the log names the machine, the method and why, in words ------------
async def test_a_refused_write_is_logged_with_the_machine_and_method_and_no_repr(
    caplog: pytest.LogCaptureFixture,
) -> None:
    from asyncua import ua
    from opcua_support import writable
    from support import serving

    from focas_net.gateway import WriteGates
    from focas_net.sim import default_machine

    i32 = ua.Variant(1, ua.VariantType.Int32)
    async with serving(default_machine()) as served:
        async with writable(served.port, WriteGates(macros=((500, 599),))) as (root, ns):
            with caplog.at_level(logging.INFO, "focas_net.gateway"):
                with pytest.raises(ua.uaerrors.BadInvalidArgument):
                    await root.call_method(f"{ns}:WriteMacro", "500", True, i32)
                with pytest.raises(ua.uaerrors.BadUserAccessDenied):
                    await root.call_method(
                        f"{ns}:WriteMacro", ua.Variant(100, ua.VariantType.Int32), 1.0, i32
                    )
                with pytest.raises(ua.uaerrors.BadInvalidArgument):
                    await root.call_method(
                        f"{ns}:WriteMacro", ua.Variant(500, ua.VariantType.Int32), float("nan"), i32
                    )
    told = [r.getMessage() for r in caplog.records if r.name.startswith("focas_net.gateway.")]
    refused = [m for m in told if "refused" in m]
    assert refused == [
        "OPC UA: mill WriteMacro refused: its arguments ('500', True, 1) are not of the "
        "declared types (Number Int32, Value Double, Path Int32)",
        "OPC UA: mill WriteMacro refused: mill: writes.macros does not allow #100 "
        "(allowed: 500..599)",
        "OPC UA: mill WriteMacro refused: #500: macro value NaN is not finite",
    ]


# -- the OPC UA server's certificate and key: PEM or DER, whatever the files are named --------
async def test_pem_files_named_crt_and_key_are_read_as_pem(tmp_path: Path) -> None:
    """A PEM certificate and key are read by what they hold, not by their names' ending (a
    ``.crt`` or ``.key`` file was read as DER and refused)."""
    from opcua_support import url as opcua_url

    from focas_net.gateway.opcua import OpcUaSink

    _ca, cert, key = _private_ca(tmp_path)
    settings = OpcUaSettings(
        endpoint="opc.tcp://127.0.0.1:0/focas_net/", certificate=cert, private_key=key
    )
    async with OpcUaSink(settings) as sink:
        assert opcua_url(sink).startswith("opc.tcp://127.0.0.1:")


@pytest.mark.parametrize(
    ("swap", "refusal"),
    [
        ("certificate", "opcua.certificate: got '{key}'; expected a certificate in PEM or DER "
         "(no PEM certificate in it)"),
        ("private_key", "opcua.private_key: got '{cert}'; expected a private key in PEM or DER "
         "(no PEM private key in it)"),
        ("junk", "opcua.certificate: got '{junk}'; expected a certificate in PEM or DER (it is "
         "neither)"),
    ],
)  # fmt: skip
async def test_a_file_of_the_wrong_kind_is_refused_in_words(
    tmp_path: Path, swap: str, refusal: str
) -> None:
    from focas_net.gateway.opcua import OpcUaSink

    _ca, cert, key = _private_ca(tmp_path)
    junk = tmp_path / "junk.der"
    junk.write_bytes(b"\x30\x03\x02\x01")
    files = {"certificate": (key, key), "private_key": (cert, cert), "junk": (junk, key)}[swap]
    settings = OpcUaSettings(
        endpoint="opc.tcp://127.0.0.1:0/focas_net/", certificate=files[0], private_key=files[1]
    )
    with pytest.raises(ConfigError) as refused:
        async with OpcUaSink(settings):
            pass
    assert str(refused.value) == refusal.format(key=key, cert=cert, junk=junk)


def test_the_command_line_names_the_file_of_a_certificate_it_cannot_read(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    from focas_net.cli import main

    _ca, _cert, key = _private_ca(tmp_path)
    config = tmp_path / "plant.toml"
    config.write_text(
        MACHINE + '[opcua]\nendpoint = "opc.tcp://127.0.0.1:0/x/"\n'
        'certificate = "broker.key"\nprivate_key = "broker.key"\n'
    )
    logger = logging.getLogger("focas_net")
    level = logger.level
    try:
        assert main(["gateway", str(config)]) == 2
    finally:  # (the command sets focas_net's threshold: later tests' DEBUG records must show)
        logger.setLevel(level)
    assert capsys.readouterr().err == (
        f"focas-net gateway: error: {config}: opcua.certificate: got '{key}'; expected a "
        "certificate in PEM or DER (no PEM certificate in it)\n"
    )


# -- a connection lost and back: the client's log says it as the command line does ------------
@pytest.mark.parametrize("protocol", ["packed", "native"])
async def test_the_client_log_tells_a_lost_connection_and_its_return_as_the_cli_does(
    protocol: str, caplog: pytest.LogCaptureFixture
) -> None:
    """The gateway's standard error shows the clients' log from WARNING: a connection lost
    was told (``connection to H:P lost (why); reconnecting``) and its return only at INFO, so
    a machine back looked lost still; the lines are now the command line's own, both told."""
    from support import serving, wait_until

    from focas_net.client import ClientState, FocasClient, NativeClient, ReconnectPolicy

    policy = ReconnectPolicy(initial_delay=0.01, max_delay=0.05, jitter=0)
    cls = NativeClient if protocol == "native" else FocasClient
    async with serving() as served:
        client = cls("127.0.0.1", served.port, timeout=2.0, reconnect=policy)
        await client.connect()
        try:
            await client.read_status()
            with caplog.at_level(logging.WARNING, "focas_net.client"):
                for conn in list(served.listener.all_connections()):
                    conn.abort()
                await wait_until(lambda: client.state is ClientState.RECONNECTING)
                await client.read_status()  # reconnected
                await wait_until(lambda: len(caplog.records) >= 2)
        finally:
            await client.aclose()
    address = f"127.0.0.1:{served.port}"
    assert [r.getMessage() for r in caplog.records if r.levelno >= logging.WARNING] == [
        f"connection to {address} lost: connection closed by {address}; reconnecting",
        f"reconnected to {address}",
    ]
