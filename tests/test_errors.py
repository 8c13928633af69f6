"""EW codes, their OPC UA mapping (docs/protocol.md section 2) and the exception tree."""

from __future__ import annotations

import pickle

import pytest
from hypothesis import given
from hypothesis import strategies as st

from focas_net.errors import (
    EW,
    EW_TABLE,
    OPCUA_BAD_COMMUNICATION_ERROR,
    OPCUA_BAD_TIMEOUT,
    OPCUA_BAD_UNEXPECTED_ERROR,
    OPCUA_GOOD,
    AccessDeniedError,
    ChunkedWriteError,
    CncError,
    FocasConnectionError,
    FocasError,
    FocasTimeoutError,
    FrameError,
    OpcUaStatus,
    PayloadError,
    ProtocolError,
    ew_info,
    ew_name,
)

# The table of docs/protocol.md section 2: code -> (canonical name, aliases).
CONTRACT_EW = {
    0: ("EW_OK", ()),
    1: ("EW_FUNC", ("EW_NOPMC",)),
    2: ("EW_LENGTH", ()),
    3: ("EW_NUMBER", ("EW_RANGE",)),
    4: ("EW_ATTRIB", ("EW_TYPE",)),
    5: ("EW_DATA", ()),
    6: ("EW_NOOPT", ()),
    7: ("EW_PROT", ()),
    8: ("EW_OVRFLOW", ()),
    9: ("EW_PARAM", ()),
    10: ("EW_BUFFER", ()),
    11: ("EW_PATH", ()),
    12: ("EW_MODE", ()),
    13: ("EW_REJECT", ()),
    14: ("EW_DTSRVR", ()),
    15: ("EW_ALARM", ()),
    16: ("EW_STOP", ()),
    17: ("EW_PASSWD", ()),
    -1: ("EW_BUSY", ()),
    -2: ("EW_RESET", ()),
    -8: ("EW_HANDLE", ()),
    -16: ("EW_SOCKET", ()),
    -17: ("EW_PROTOCOL", ()),
}

# The OPC UA statuses docs/protocol.md section 2 names, with their values.
CONTRACT_OPCUA = {
    0: ("Good", 0x00000000),
    17: ("BadUserAccessDenied", 0x801F0000),
    1: ("BadNotSupported", 0x803D0000),
    6: ("BadNotSupported", 0x803D0000),
    7: ("BadNotWritable", 0x803B0000),
    3: ("BadOutOfRange", 0x803C0000),
    4: ("BadTypeMismatch", 0x80740000),
    2: ("BadInvalidArgument", 0x80AB0000),
    5: ("BadInvalidArgument", 0x80AB0000),
    -1: ("BadResourceUnavailable", 0x80040000),
    -16: ("BadCommunicationError", 0x80050000),
    -8: ("BadCommunicationError", 0x80050000),
}


def test_the_table_has_exactly_the_contract_codes() -> None:
    assert set(EW_TABLE) == set(CONTRACT_EW)
    assert {int(e) for e in EW} == set(CONTRACT_EW)


@pytest.mark.parametrize("code", sorted(CONTRACT_EW))
def test_every_code_name_and_alias(code: int) -> None:
    name, aliases = CONTRACT_EW[code]
    row = EW_TABLE[code]
    assert row.code == code
    assert row.name == name
    assert row.aliases == aliases
    assert row.meaning
    assert ew_name(code) == name
    assert ew_info(code) is row
    assert EW[name.removeprefix("EW_")] == code
    for alias in aliases:
        assert EW[alias.removeprefix("EW_")] == code
        assert EW[alias.removeprefix("EW_")] is EW[name.removeprefix("EW_")]


def test_aliases_share_a_value() -> None:
    assert EW["FUNC"] is EW["NOPMC"]
    assert EW["NUMBER"] is EW["RANGE"]
    assert EW["ATTRIB"] is EW["TYPE"]
    assert int(EW.PASSWD) == 17  # FANUC's header, not the design note's 11
    assert int(EW.PATH) == 11


@pytest.mark.parametrize("code", sorted(CONTRACT_OPCUA))
def test_opcua_mapping_of_the_contract(code: int) -> None:
    name, value = CONTRACT_OPCUA[code]
    status = EW_TABLE[code].opcua
    assert (status.name, status.value) == (name, value)
    assert CncError(code).opcua_status == status


def test_every_code_maps_to_an_opcua_status() -> None:
    for code, row in EW_TABLE.items():
        assert isinstance(row.opcua, OpcUaStatus)
        is_bad = row.opcua.value & 0x80000000 != 0
        assert is_bad is (code != 0), code
        assert row.opcua.name.startswith("Bad") is (code != 0)


def test_connection_and_timeout_statuses() -> None:
    assert (OPCUA_GOOD.name, OPCUA_GOOD.value) == ("Good", 0)
    assert (OPCUA_BAD_TIMEOUT.name, OPCUA_BAD_TIMEOUT.value) == ("BadTimeout", 0x800A0000)
    assert (OPCUA_BAD_COMMUNICATION_ERROR.name, OPCUA_BAD_COMMUNICATION_ERROR.value) == (
        "BadCommunicationError",
        0x80050000,
    )
    assert FocasConnectionError("lost").opcua_status == OPCUA_BAD_COMMUNICATION_ERROR
    assert FocasTimeoutError("late").opcua_status == OPCUA_BAD_TIMEOUT
    assert str(OPCUA_BAD_TIMEOUT) == "BadTimeout (0x800A0000)"


def test_from_ew_17_is_access_denied() -> None:
    exc = CncError.from_ew(17)
    assert type(exc) is AccessDeniedError
    assert isinstance(exc, CncError)
    assert isinstance(exc, FocasError)
    assert exc.access_denied is True
    assert exc.ew == 17
    assert exc.name == "EW_PASSWD"
    assert exc.opcua_status.name == "BadUserAccessDenied"
    assert exc.opcua_status.value == 0x801F0000


def test_ew_passwd_is_recognisable_even_without_from_ew() -> None:
    assert CncError(17).access_denied is True


@pytest.mark.parametrize("code", sorted(c for c in CONTRACT_EW if c not in (0, 17)))
def test_other_codes_are_plain_cnc_errors(code: int) -> None:
    exc = CncError.from_ew(code, "while reading")
    assert type(exc) is CncError
    assert exc.access_denied is False
    assert exc.ew == code
    assert exc.name == CONTRACT_EW[code][0]
    assert exc.detail == "while reading"
    assert CONTRACT_EW[code][0] in str(exc)
    assert "while reading" in str(exc)


def test_exception_tree() -> None:
    assert issubclass(CncError, FocasError)
    assert issubclass(AccessDeniedError, CncError)
    assert issubclass(ChunkedWriteError, FocasError)
    assert issubclass(ProtocolError, FocasError)
    assert issubclass(FrameError, ProtocolError)
    assert issubclass(PayloadError, ProtocolError)
    assert issubclass(FocasConnectionError, FocasError)
    assert issubclass(FocasTimeoutError, FocasError)


def test_connection_error_is_a_builtin_connection_error() -> None:
    exc = FocasConnectionError("peer closed")
    assert isinstance(exc, ConnectionError)
    assert isinstance(exc, OSError)
    with pytest.raises(ConnectionError):
        raise exc


def test_timeout_error_is_a_builtin_timeout_error() -> None:
    exc = FocasTimeoutError("no answer")
    assert isinstance(exc, TimeoutError)
    with pytest.raises(TimeoutError):
        raise exc


@pytest.mark.parametrize(
    "exc",
    [
        CncError(3),
        CncError(-1, "busy"),
        CncError.from_ew(17, "parameter 1320"),
        CncError(99),
    ],
    ids=["number", "busy", "passwd", "unknown"],
)
def test_pickling_cnc_error_round_trips(exc: CncError) -> None:
    copy = pickle.loads(pickle.dumps(exc))
    assert type(copy) is type(exc)
    assert (copy.ew, copy.name, copy.detail, copy.opcua_status) == (
        exc.ew,
        exc.name,
        exc.detail,
        exc.opcua_status,
    )
    assert str(copy) == str(exc)
    assert copy.access_denied is exc.access_denied


@pytest.mark.parametrize("code", [18, 100, -3, -32768, 32767])
def test_unknown_codes_get_a_synthetic_name(code: int) -> None:
    assert ew_name(code) == f"EW_UNKNOWN({code})"
    info = ew_info(code)
    assert info.code == code
    assert info.opcua == OPCUA_BAD_UNEXPECTED_ERROR
    exc = CncError.from_ew(code)
    assert exc.name == f"EW_UNKNOWN({code})"
    assert str(exc) == f"EW_UNKNOWN({code}): unknown return code"  # the number once
    assert exc.opcua_status == OPCUA_BAD_UNEXPECTED_ERROR


@given(st.integers(-32768, 32767))
def test_ew_info_never_raises(code: int) -> None:
    info = ew_info(code)
    assert info.code == code
    assert info.name.startswith("EW_")
    exc = CncError.from_ew(code)
    assert exc.ew == code
    assert exc.access_denied is (code == 17)


def test_chunked_write_error_says_what_was_written() -> None:
    cause = CncError.from_ew(7)
    exc = ChunkedWriteError("R", [(0, 31)], [(32, 63)], cause)
    assert exc.written == [(0, 31)]
    assert exc.not_written == [(32, 63)]
    assert exc.cause is cause
    assert exc.opcua_status.name == "BadNotWritable"
    assert "R0..R31" in str(exc) and "R32..R63" in str(exc)
    assert ChunkedWriteError("D", [], [(0, 3)], OSError()).opcua_status == (
        OPCUA_BAD_UNEXPECTED_ERROR
    )


def test_protocol_errors_map_to_an_opcua_status() -> None:
    assert PayloadError("x").opcua_status.value & 0x80000000
    assert FrameError("x").opcua_status.value & 0x80000000


def test_pickling_chunked_write_error_round_trips() -> None:
    exc = ChunkedWriteError("R", [(0, 31)], [(32, 63)], CncError(7))
    copy = pickle.loads(pickle.dumps(exc))
    assert (copy.area, copy.written, copy.not_written) == ("R", [(0, 31)], [(32, 63)])
    assert str(copy) == str(exc)


def test_chunked_write_error_lists_unconfirmed_ranges() -> None:
    exc = ChunkedWriteError("D", [(0, 31)], [], FocasTimeoutError("late"), [(32, 63)])
    assert exc.uncertain == [(32, 63)]
    assert "unconfirmed: D32..D63" in str(exc)
    copy = pickle.loads(pickle.dumps(exc))
    assert copy.uncertain == [(32, 63)] and str(copy) == str(exc)
    assert exc.opcua_status.name == "BadTimeout"
