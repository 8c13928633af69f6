"""Who may connect to the gateway's OPC UA server and what they may do: anonymous sessions only
on the loopback and only while writes are off, users by password, no endpoint beyond the
loopback without a certificate; the write methods only when writes are on, each refusal a Bad
status (BadUserAccessDenied for a write gate, the EW code's status otherwise)."""

from __future__ import annotations

from dataclasses import replace
from decimal import Decimal

import pytest
from asyncua import ua
from opcua_support import LATHE, SETTINGS, USERS, connected, machine_node, running

from focas_net.errors import EW, CncError
from focas_net.gateway.opcua import OpcUaSink, is_loopback

DENIED = (ua.uaerrors.BadUserAccessDenied, ua.uaerrors.BadIdentityTokenRejected)


def test_loopback_hosts() -> None:
    assert is_loopback("127.0.0.1") and is_loopback("::1") and is_loopback("localhost")
    assert not is_loopback("0.0.0.0") and not is_loopback("plant.example") and not is_loopback(None)


def test_settings_no_client_could_use_safely_are_refused() -> None:
    beyond = replace(SETTINGS, endpoint="opc.tcp://0.0.0.0:4840/focas_net/", users=USERS)
    with pytest.raises(ValueError, match="beyond the loopback: it needs certificate"):
        OpcUaSink(beyond)
    with pytest.raises(ValueError, match="no client could connect"):
        OpcUaSink(replace(SETTINGS, anonymous=False))
    with pytest.raises(ValueError, match="no client could connect"):
        OpcUaSink(replace(SETTINGS, writes=True), Recorder())
    with pytest.raises(ValueError, match="come together"):
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
    for settings, writer in ((SETTINGS, Recorder()), (replace(SETTINGS, writes=True), None)):
        async with running(settings, writer) as sink:
            sink.described(LATHE)
            await sink.flush()
            async with connected(sink) as client:
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
