"""Who may connect to the gateway's OPC UA server and what they may do: anonymous sessions only
on the loopback and only while writes are off, users by password, no endpoint beyond the
loopback without a certificate; the write methods only when writes are on, each refusal a Bad
status (BadUserAccessDenied for a write gate, the EW code's status otherwise)."""

from __future__ import annotations

from dataclasses import replace
from decimal import Decimal
from pathlib import Path

import pytest
from asyncua import Client, ua
from asyncua.crypto.cert_gen import setup_self_signed_certificate
from cryptography.x509.oid import ExtendedKeyUsageOID
from opcua_support import LATHE, SETTINGS, USERS, connected, machine_node, running, url

from focas_net.errors import EW, CncError, FocasConnectionError
from focas_net.gateway.opcua import OpcUaSink, is_loopback

DENIED = (ua.uaerrors.BadUserAccessDenied, ua.uaerrors.BadIdentityTokenRejected)


def test_loopback_hosts() -> None:
    assert is_loopback("127.0.0.1") and is_loopback("::1") and is_loopback("localhost")
    assert not is_loopback("0.0.0.0") and not is_loopback("plant.example") and not is_loopback(None)


def test_settings_no_client_could_use_safely_are_refused() -> None:
    beyond = replace(SETTINGS, endpoint="opc.tcp://0.0.0.0:4840/focas_net/", users=USERS)
    with pytest.raises(ValueError, match=r"opcua\.certificate: missing: .* beyond the loopback"):
        OpcUaSink(beyond)
    with pytest.raises(ValueError, match="opcua: no way in"):
        OpcUaSink(replace(SETTINGS, anonymous=False))
    with pytest.raises(ValueError, match="opcua: no way in"):
        OpcUaSink(replace(SETTINGS, writes=True), Recorder())
    with pytest.raises(ValueError, match=r"opcua\.private_key: missing: give certificate and"):
        OpcUaSink(replace(SETTINGS, certificate=SETTINGS.namespace))  # type: ignore[arg-type]


async def test_anonymous_sessions_are_refused_when_configured_off() -> None:
    async with running(replace(SETTINGS, anonymous=False, users=USERS)) as sink:
        with pytest.raises(DENIED):
            async with connected(sink):
                pass
        with pytest.raises(DENIED):
            async with connected(sink, "operator", "wrong"):
                pass
        with pytest.raises(DENIED):
            async with connected(sink, "nobody", "s3cret"):
                pass
        sink.described(LATHE)
        await sink.flush()
        async with connected(sink, "operator", "s3cret") as client:
            root = await machine_node(client, "lathe")
            assert (await root.read_browse_name()).Name == "lathe"


class Recorder:
    """A writer that records each write, or raises what it is told to."""

    def __init__(self, error: Exception | None = None) -> None:
        self.error = error
        self.calls: list[tuple[object, ...]] = []

    async def write_macro(self, machine: str, number: int, value: Decimal, path: int) -> None:
        self._call("macro", machine, number, value, path)

    async def write_param(self, machine: str, number: int, value: int, axis: int) -> None:
        self._call("param", machine, number, value, axis)

    async def write_pmc(self, machine: str, area: str, address: int, value: int) -> None:
        self._call("pmc", machine, area, address, value)

    def _call(self, *args: object) -> None:
        if self.error is not None:
            raise self.error
        self.calls.append(args)


async def test_the_write_methods_are_absent_when_read_only() -> None:
    for settings, writer, user in (
        (SETTINGS, Recorder(), None),
        (replace(SETTINGS, writes=True, users=USERS), None, USERS[0]),
    ):
        async with running(settings, writer) as sink:
            sink.described(LATHE)
            await sink.flush()
            name, password = (None, None) if user is None else (user.name, user.password)
            async with connected(sink, name, password) as client:
                root = await machine_node(client, "lathe")
                assert await root.get_methods() == []
                ns = await client.get_namespace_index("urn:focas-net:gateway")
                method = ua.NodeId("lathe/WriteMacro", ns)
                with pytest.raises(ua.UaStatusCodeError):
                    await root.call_method(method, 500, 1.5, 1)


WRITES = replace(SETTINGS, writes=True, users=USERS)


async def test_the_write_methods_call_the_writer() -> None:
    writer = Recorder()
    async with running(WRITES, writer) as sink:
        sink.described(LATHE)
        await sink.flush()
        async with connected(sink, "operator", "s3cret") as client:
            root = await machine_node(client, "lathe")
            ns = await client.get_namespace_index("urn:focas-net:gateway")
            names = sorted([(await m.read_browse_name()).Name for m in await root.get_methods()])
            assert names == ["WriteMacro", "WriteParameter", "WritePmc"]
            i32 = ua.VariantType.Int32
            await root.call_method(
                f"{ns}:WriteMacro", ua.Variant(500, i32), 1.25, ua.Variant(2, i32)
            )
            await root.call_method(
                f"{ns}:WriteParameter",
                ua.Variant(1320, i32),
                ua.Variant(1, i32),
                ua.Variant(-5, i32),
            )
            await root.call_method(
                f"{ns}:WritePmc", "R", ua.Variant(100, i32), ua.Variant(255, i32)
            )
    assert writer.calls == [
        ("macro", "lathe", 500, Decimal("1.25"), 2),
        ("param", "lathe", 1320, -5, 1),
        ("pmc", "lathe", "R", 100, 255),
    ]


@pytest.mark.parametrize(
    ("error", "refusal"),
    [
        (PermissionError("macro 500 is outside the write gates"), ua.uaerrors.BadUserAccessDenied),
        (CncError.from_ew(EW.NUMBER), ua.uaerrors.BadOutOfRange),
        (CncError.from_ew(EW.PASSWD), ua.uaerrors.BadUserAccessDenied),
        (CncError.from_ew(EW.MODE), ua.uaerrors.BadInvalidState),
        (ValueError("macro value out of range"), ua.uaerrors.BadInvalidArgument),
        (FocasConnectionError("reset by peer"), ua.uaerrors.BadCommunicationError),
    ],
)
async def test_a_refused_write_is_a_bad_status(
    error: Exception, refusal: type[ua.UaStatusCodeError]
) -> None:
    async with running(WRITES, Recorder(error)) as sink:
        sink.described(LATHE)
        await sink.flush()
        async with connected(sink, "operator", "s3cret") as client:
            root = await machine_node(client, "lathe")
            ns = await client.get_namespace_index("urn:focas-net:gateway")
            i32 = ua.VariantType.Int32
            with pytest.raises(refusal):
                await root.call_method(
                    f"{ns}:WriteMacro", ua.Variant(500, i32), 1.0, ua.Variant(1, i32)
                )


async def _certificate(folder: Path, name: str, uri: str, server: bool) -> tuple[Path, Path]:
    """A key and a self-signed application certificate (PEM key, DER certificate)."""
    key, cert = folder / f"{name}.key.pem", folder / f"{name}.der"
    use = [ExtendedKeyUsageOID.SERVER_AUTH if server else ExtendedKeyUsageOID.CLIENT_AUTH]
    await setup_self_signed_certificate(key, cert, uri, "localhost", use, {"commonName": name})
    return cert, key


async def test_with_a_certificate_the_basic256sha256_endpoints_serve_users(tmp_path: Path) -> None:
    cert, key = await _certificate(tmp_path, "gateway", SETTINGS.namespace, server=True)
    settings = replace(SETTINGS, certificate=cert, private_key=key, anonymous=False, users=USERS)
    async with running(settings) as sink:
        sink.described(LATHE)
        await sink.flush()
        client = Client(url(sink))
        endpoints = await client.connect_and_get_server_endpoints()
        policies = {(e.SecurityPolicyUri.rsplit("#", 1)[-1], e.SecurityMode) for e in endpoints}
        assert policies == {
            ("None", ua.MessageSecurityMode.None_),
            ("Basic256Sha256", ua.MessageSecurityMode.Sign),
            ("Basic256Sha256", ua.MessageSecurityMode.SignAndEncrypt),
        }
        tokens = {t.TokenType for e in endpoints for t in e.UserIdentityTokens}
        assert tokens == {ua.UserTokenType.UserName}
        mine, my_key = await _certificate(tmp_path, "client", "urn:test:client", server=False)
        client = Client(url(sink))
        await client.set_security_string(f"Basic256Sha256,SignAndEncrypt,{mine},{my_key}")
        client.set_user("operator")
        client.set_password("s3cret")
        async with client:
            root = await machine_node(client, "lathe")
            assert (await root.read_browse_name()).Name == "lathe"
