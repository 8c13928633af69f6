"""The OPC UA write methods check a call's arguments against the declared ones before any
write: too few is BadArgumentsMissing, too many BadTooManyArguments, and an argument of
another type (a Boolean, text for a number, a float for an integer, an array, an empty
variant) BadInvalidArgument with BadTypeMismatch for it, as OPC UA's Call service has it;
never BadUnexpectedError with a traceback on the gateway's log, and never a number read out of
text or a float cut to an integer."""

from __future__ import annotations

import logging
from decimal import Decimal
from typing import Any

import pytest
from asyncua import ua
from opcua_support import writable
from support import serving

from focas_net.gateway import WriteGates
from focas_net.gateway._opcua_methods import arguments
from focas_net.sim import default_machine

V = ua.VariantType
I32, DBL, TXT = ua.ObjectIds.Int32, ua.ObjectIds.Double, ua.ObjectIds.String


def declared(*types: int) -> list[ua.Argument]:
    return [
        ua.Argument(Name=f"a{i}", DataType=ua.NodeId(t), ValueRank=-1) for i, t in enumerate(types)
    ]


MACRO = declared(I32, DBL, I32)


def test_arguments_of_the_declared_types_give_their_values() -> None:
    given = (ua.Variant(500, V.Int16), ua.Variant(1.5, V.Double), ua.Variant(1, V.UInt32))
    assert arguments(given, MACRO) == [500, 1.5, 1]
    given = (ua.Variant(500, V.Int32), ua.Variant(2, V.Int64), ua.Variant(1, V.Byte))
    assert arguments(given, MACRO) == [500, 2, 1]
    assert arguments((ua.Variant("R", V.String),), declared(TXT)) == ["R"]


@pytest.mark.parametrize(
    ("given", "status"),
    [
        ((), ua.StatusCodes.BadArgumentsMissing),
        ((ua.Variant(500, V.Int32), ua.Variant(1.0, V.Double)), ua.StatusCodes.BadArgumentsMissing),
        (
            (
                ua.Variant(500, V.Int32),
                ua.Variant(1.0, V.Double),
                ua.Variant(1, V.Int32),
                ua.Variant(1, V.Int32),
            ),
            ua.StatusCodes.BadTooManyArguments,
        ),
    ],
)
def test_a_wrong_count_is_its_status(given: tuple[Any, ...], status: int) -> None:
    assert arguments(given, MACRO) == ua.StatusCode(status)


@pytest.mark.parametrize(
    ("given", "bad"),
    [
        ((ua.Variant("500", V.String), ua.Variant(1.0, V.Double), ua.Variant(1, V.Int32)), [0]),
        ((ua.Variant(500.7, V.Double), ua.Variant(1.0, V.Double), ua.Variant(1, V.Int32)), [0]),
        ((ua.Variant(True, V.Boolean), ua.Variant(1.0, V.Double), ua.Variant(1, V.Int32)), [0]),
        (
            (ua.Variant(500, V.Int32), ua.Variant("1.5", V.String), ua.Variant(True, V.Boolean)),
            [1, 2],
        ),
        ((ua.Variant(500, V.Int32), ua.Variant([1.0, 2.0], V.Double), ua.Variant(1, V.Int32)), [1]),
        ((ua.Variant(500, V.Int32), ua.Variant(None, V.Null), ua.Variant(1, V.Int32)), [1]),
    ],
)
def test_an_argument_of_another_type_is_a_type_mismatch(
    given: tuple[Any, ...], bad: list[int]
) -> None:
    result = arguments(given, MACRO)
    assert isinstance(result, ua.CallMethodResult)
    assert result.StatusCode == ua.StatusCode(ua.StatusCodes.BadInvalidArgument)
    mismatch = ua.StatusCode(ua.StatusCodes.BadTypeMismatch)
    assert [i for i, r in enumerate(result.InputArgumentResults) if r == mismatch] == bad
    assert all(r.is_good() for i, r in enumerate(result.InputArgumentResults) if i not in bad)


async def test_bad_calls_write_nothing_and_log_no_traceback(
    caplog: pytest.LogCaptureFixture,
) -> None:
    machine = default_machine()
    async with serving(machine) as served:
        gates = WriteGates(macros=((500, 599),), params=((6711, 6713),), pmc=(("R", 100, 199),))
        async with writable(served.port, gates) as (root, ns):
            i32 = ua.Variant(1, V.Int32)
            with caplog.at_level(logging.WARNING):
                with pytest.raises(ua.uaerrors.BadArgumentsMissing):
                    await root.call_method(f"{ns}:WriteMacro", ua.Variant(500, V.Int32))
                with pytest.raises(ua.uaerrors.BadTooManyArguments):
                    await root.call_method(f"{ns}:WritePmc", "R", i32, i32, i32)
                with pytest.raises(ua.uaerrors.BadInvalidArgument):  # text for the number
                    await root.call_method(f"{ns}:WriteMacro", "500", 1.0, i32)
                with pytest.raises(ua.uaerrors.BadInvalidArgument):  # 6711.9 is no parameter
                    await root.call_method(
                        f"{ns}:WriteParameter",
                        6711.9,
                        ua.Variant(0, V.Int32),
                        ua.Variant(5, V.Int32),
                    )
                for odd in (float("nan"), float("inf"), 1e300):  # the macro's own check
                    with pytest.raises(ua.uaerrors.UaStatusCodeError):
                        await root.call_method(
                            f"{ns}:WriteMacro", ua.Variant(500, V.Int32), odd, i32
                        )
            assert machine.read_macro(500) is None
            assert machine.read_param(6711, 0) == 0
            assert not [r for r in caplog.records if r.levelno >= logging.ERROR], caplog.records
            # and a good call still writes
            await root.call_method(f"{ns}:WriteMacro", ua.Variant(500, V.Int16), 2.5, i32)
            assert machine.read_macro(500) == Decimal("2.5")
