"""The gateway's configuration: what ``focas-net gateway CONFIG.toml`` reads (``docs/gateway.md``
gives the file's keys). Frozen values; reading and checking the file comes with them:
:func:`load_config`, :func:`parse_config` and :func:`shard`.

Every refusal is a :class:`ConfigError` naming the file, the key path as written
(``machine[3].groups.fast``), what was typed and what is expected. A host and a port are
checked by every front end's one check (``focas_net/_address.py``), a path number by
``client/_values.check_path``, a PMC area by :class:`~focas_net.protocol.PmcArea`: the command
line and the gateway refuse the same values with the same words.
"""

from __future__ import annotations

import os
import re
import tomllib
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any, Final, Literal
from urllib.parse import urlsplit, urlunsplit

from focas_net._address import check_host, check_port
from focas_net._typed import file_name_unfit, file_text, is_loopback, os_words
from focas_net.client._values import I16_MAX, check_path
from focas_net.protocol import PmcArea

from ._keys import At, ConfigError
from ._outputs import DEFAULT_GATEWAY, MOST_CHARS, MqttSettings, OpcUaSettings, OpcUaUser, deadbands

__all__ = [
    "DEFAULT_GATEWAY",
    "MAX_FLEET",
    "MIN_INTERVAL",
    "ConfigError",
    "GatewayConfig",
    "GroupIntervals",
    "MachineConfig",
    "MqttSettings",
    "OpcUaSettings",
    "OpcUaUser",
    "WriteGates",
    "check_machines",
    "check_outputs",
    "is_loopback",
    "load_config",
    "parse_config",
    "shard",
    "shard_refusal",
    "with_port",
]

#: Most machines one ``[[fleet]]`` expands to.
MAX_FLEET: Final = 10_000
#: The shortest poll interval of a group, in seconds: a group read faster than this would
#: only keep the loop busy (a control answers its reads in milliseconds, and a busy loop
#: serves every other machine late).
MIN_INTERVAL: Final = 0.01
#: A machine's name: the MQTT topic level and the OPC UA browse name.
_NAME: Final = re.compile(r"[A-Za-z0-9_.-]{1,64}")
_NAME_TEXT: Final = "a name of 1..64 letters, digits, '-', '_' or '.'"
_PROTOCOLS: Final = ("native", "packed")
_PMC_RANGE: Final = re.compile(r"([A-Za-z])([0-9]{1,9})(?:-([A-Za-z]?)([0-9]{1,9}))?")
_PMC_LAST_BYTE: Final = 0xFFFF


@dataclass(frozen=True, slots=True)
class GroupIntervals:
    """Poll intervals in seconds: the fast group, the slow group, and the alarm list."""

    fast: float = 1.0
    slow: float = 10.0
    alarms: float = 1.0

    def check(self, at: At) -> None:
        """Raise :class:`ConfigError` at ``at`` (``groups``) for an interval that is no
        number of seconds of at least :data:`MIN_INTERVAL`."""
        for key in _GROUP_KEYS:
            at.key(key).seconds(getattr(self, key), MIN_INTERVAL)


@dataclass(frozen=True, slots=True)
class WriteGates:
    """What may be written to one machine: inclusive ranges of macro variables and of
    parameters, and PMC byte ranges ``(area, first, last)``. Empty: nothing (the default)."""

    macros: tuple[tuple[int, int], ...] = ()
    params: tuple[tuple[int, int], ...] = ()
    pmc: tuple[tuple[str, int, int], ...] = ()

    def check(self, at: At) -> None:
        """Raise :class:`ConfigError` at ``at`` (``writes``) for a range that is no
        ``(first, last)`` of macro variable numbers (-32768..32767) or of parameter numbers
        (0..32767) with first <= last, or no ``(area, first, last)`` of a PMC area letter and
        bytes 0..65535 with first <= last."""
        _ranges(at.key("macros"), self.macros, -I16_MAX - 1, I16_MAX)
        _ranges(at.key("params"), self.params, 0, I16_MAX)
        pat = at.key("pmc")
        for i, gate in enumerate(pat.array(self.pmc, 0, 1000)):
            where = pat.index(i)
            if not isinstance(gate, tuple | list) or len(gate) != 3:
                where.expected(gate, "(area, first, last): ('R', 0, 99)")
            area, first, last = gate
            problem = _pmc_problem(area, first, last)
            if problem:
                where.expected(gate, f"(area, first, last): ('R', 0, 99), {problem}")


@dataclass(frozen=True, slots=True)
class MachineConfig:
    """One machine: its name (unique; the MQTT topic level and the OPC UA browse name), its
    address, its protocol, the paths to read (None: every path it has), the per-call timeout,
    its poll intervals and its write gates."""

    name: str
    host: str
    port: int = 8193
    protocol: Literal["native", "packed"] = "native"
    paths: tuple[int, ...] | None = None
    timeout: float = 3.0
    groups: GroupIntervals = field(default_factory=GroupIntervals)
    writes: WriteGates = field(default_factory=WriteGates)

    def check(self, source: str = "", place: str = "machine") -> None:
        """Raise :class:`ConfigError` naming the key (``machine[2].port: got 0; ...``, after
        ``source``, the file, when given; ``place`` the machine's place in it) for a machine
        no gateway could poll: the file's reader and :class:`~focas_net.gateway.Gateway`
        both call it, so that a machine built in Python is refused as the file's is."""
        self._check(At(source, place))

    def _check(self, at: At) -> None:
        if not isinstance(self.name, str) or not _NAME.fullmatch(self.name):
            at.key("name").expected(self.name, _NAME_TEXT)
        at.key("host").checked(self.host, check_host, "a host name or address")
        at.key("port").checked(self.port, check_port, "a port 1..65535", why=False)
        at.key("protocol").choice(self.protocol, _PROTOCOLS)
        if self.paths is not None:
            pat = at.key("paths")
            paths = [
                pat.index(i).checked(p, check_path, "a path number 1..10", why=False)
                for i, p in enumerate(pat.array(self.paths, 1, 10))
            ]
            if len(set(paths)) != len(paths):
                pat.fail(f"got {paths}; expected each path once")
        at.key("timeout").seconds(self.timeout)
        if not isinstance(self.groups, GroupIntervals):
            at.key("groups").expected(self.groups, "GroupIntervals(fast, slow, alarms)")
        self.groups.check(at.key("groups"))
        if not isinstance(self.writes, WriteGates):
            at.key("writes").expected(self.writes, "WriteGates(macros, params, pmc)")
        self.writes.check(at.key("writes"))


@dataclass(frozen=True, slots=True)
class GatewayConfig:
    """The whole file: the machines (after ``--shard``), and each output (None: not used)."""

    machines: tuple[MachineConfig, ...]
    opcua: OpcUaSettings | None = None
    mqtt: MqttSettings | None = None


# -- reading the file ------------------------------------------------------------------------
_TOP: Final = ("groups", "machine", "fleet", "mqtt", "opcua")
_GROUP_KEYS: Final = ("fast", "slow", "alarms")
_WRITE_KEYS: Final = ("macros", "params", "pmc")
_COMMON: Final = ("host", "protocol", "paths", "timeout", "groups", "writes")
_MACHINE_KEYS: Final = ("name", "port", *_COMMON)
_FLEET_KEYS: Final = ("name_prefix", "first_port", "count", *_COMMON)
_MQTT_KEYS: Final = (
    "host", "port", "prefix", "client_id", "username", "password", "password_env", "qos",
    "keepalive", "buffer", "tls", "tls_ca", "deadbands", "gateway",
)  # fmt: skip
_OPCUA_KEYS: Final = (
    "endpoint", "namespace", "anonymous", "users", "certificate", "private_key", "writes",
)  # fmt: skip
_USER_KEYS: Final = ("name", "password", "password_env")


def load_config(path: str | os.PathLike[str]) -> GatewayConfig:
    """The configuration in the TOML file ``path`` (relative file names in it are read from
    the file's folder); :class:`ConfigError` names what is wrong, an unreadable file and an
    empty name too; ``TypeError`` for a ``path`` that is no file name."""
    name = os.fspath(path) if isinstance(path, str | os.PathLike) else None
    if not isinstance(name, str):
        raise TypeError(f"load_config(): path must be a file name (a str or a Path), got {path!r}")
    why = file_name_unfit(name)
    if why is not None:
        raise ConfigError(why)
    try:
        raw = Path(name).read_bytes()
    except OSError as exc:
        raise ConfigError(f"{name}: {os_words(exc)}") from None
    try:
        text = file_text(raw)
    except ValueError as exc:
        raise ConfigError(f"{name}: {exc}") from None
    return parse_config(text, name, folder=Path(name).parent)


def parse_config(
    data: str | Mapping[str, Any], source: str = "<config>", *, folder: Path | None = None
) -> GatewayConfig:
    """The configuration in ``data`` (TOML text, or the table it reads as), ``source`` naming
    it in errors; ``folder`` is where relative file names are read from (default: the current
    folder). Raises :class:`ConfigError`, and ``TypeError`` for ``data`` of another type."""
    top = At(source)
    if not isinstance(data, str | Mapping):
        raise TypeError(
            "parse_config(): data must be TOML text (a str; load_config reads a file) or the "
            f"table it reads as, got {'None' if data is None else type(data).__name__}"
        )
    if isinstance(data, str):
        try:
            data = tomllib.loads(data)
        except ValueError as exc:  # (TOMLDecodeError, or an integer of too many digits)
            top.fail(f"not valid TOML: {exc}")
    doc = top.table(data, _TOP)
    base = folder if folder is not None else Path()
    defaults = _groups(top.key("groups"), doc.get("groups", {}), GroupIntervals())
    machines: list[MachineConfig] = []
    where_of: dict[str, At] = {}
    # [[machine]] and [[fleet]] in the file's order (the first block of each kind decides):
    # --shard's "machines I, I+N, ... of the file" and the staggering follow it
    for kind in (key for key in doc if key in ("machine", "fleet")):
        at = top.key(kind)
        for i, table in enumerate(at.tables(doc[kind])):
            if kind == "machine":
                machines.append(_machine(at.index(i), table, defaults))
                _unique(machines[-1].name, where_of, at.index(i), "name")
                continue
            for machine in _fleet(at.index(i), table, defaults):
                machines.append(machine)
                _unique(machine.name, where_of, at.index(i), "name_prefix")
    if not machines:
        top.fail("no machine: give at least one [[machine]] or [[fleet]]")
    mqtt = _mqtt(top.key("mqtt"), doc["mqtt"], base) if "mqtt" in doc else None
    opcua = _opcua(top.key("opcua"), doc["opcua"], base) if "opcua" in doc else None
    return GatewayConfig(tuple(machines), opcua, mqtt)


def with_port(endpoint: str, port: int) -> str:
    """The URL ``endpoint`` (``opc.tcp://HOST:PORT/PATH``, checked) with ``port`` for its
    port."""
    parts = urlsplit(endpoint)
    netloc = f"{parts.netloc.rsplit(':', 1)[0]}:{port}"
    return urlunsplit(parts._replace(netloc=netloc))


def shard_refusal(index: int, count: int) -> str | None:
    """Why shard ``index`` of ``count`` is no shard (``"the shard must be within 1..2"``), or
    None when it is one: the check :func:`shard` and ``focas-net gateway --shard`` share, which
    needs no file."""
    if isinstance(count, bool) or not isinstance(count, int) or count < 1:
        return "the number of shards must be 1 or more"
    if isinstance(index, bool) or not isinstance(index, int) or not 1 <= index <= count:
        return f"the shard must be within 1..{count}"
    return None


def shard(config: GatewayConfig, index: int, count: int, source: str = "") -> GatewayConfig:
    """Shard ``index`` of ``count`` (1 <= index <= count): machines ``index``, ``index +
    count``, ... of the file, 1-based (round robin, so that each shard gets its share of every
    ``[[fleet]]``). Each machine is in exactly one shard. Of several shards, shard ``index``
    serves OPC UA on the endpoint's port + ``index - 1`` and connects to the MQTT broker as
    ``client_id-index`` (when the file names a client id), so that the shards of one file run
    side by side on one host. Raises :class:`ConfigError` for a bad shard, one with no machine
    or one whose port would pass 65535, naming ``source`` (the file) first when given;
    ``TypeError`` for an ``index`` or a ``count`` that is no ``int``."""
    for what, number in (("index", index), ("count", count)):
        if isinstance(number, bool) or not isinstance(number, int):
            raise TypeError(f"shard(): {what} must be an int, got {number!r}")
    at = At(source, f"--shard {index}/{count}")
    why = shard_refusal(index, count)
    if why is not None:
        at.fail(why)
    machines = config.machines[index - 1 :: count]
    if not machines:
        many = len(config.machines)
        at.fail(f"no machine (the file has {many} machine{'s' * (many != 1)})")
    if count == 1:
        return replace(config, machines=machines)
    opcua, mqtt = config.opcua, config.mqtt
    if opcua is not None:
        first = urlsplit(opcua.endpoint).port
        # (port 0, any free port, stays 0 for every shard)
        port = first + index - 1 if first else 0
        if port > 65535:
            at.fail(
                f"the OPC UA port of this shard, {first} + {index - 1}, passes 65535 "
                f"(opcua.endpoint {opcua.endpoint!r})"
            )
        opcua = replace(opcua, endpoint=with_port(opcua.endpoint, port))
    if mqtt is not None:
        mqtt = replace(mqtt, gateway=f"{mqtt.gateway_name}-{index}")
        if mqtt.client_id is not None:
            mqtt = replace(mqtt, client_id=f"{mqtt.client_id}-{index}")
        for key in ("client_id", "gateway"):  # (the file's own were checked as written)
            named = getattr(mqtt, key)
            if named is not None and len(named) > MOST_CHARS:
                at.fail(
                    f"mqtt.{key} with this shard's '-{index}' has {len(named)} characters, "
                    f"more than {MOST_CHARS}: give a shorter one"
                )
    return replace(config, machines=machines, opcua=opcua, mqtt=mqtt)


def check_machines(
    machines: Sequence[MachineConfig], source: str = "", *, name: str = "machines"
) -> None:
    """Raise :class:`ConfigError` for a machine of ``machines`` that is no
    :class:`MachineConfig`, fails its :meth:`~MachineConfig.check`, or has the name of an
    earlier one, naming it ``machine[i]`` (from 1) after ``source`` when given: what
    :class:`~focas_net.gateway.Gateway` asks of machines built in Python. ``machines`` that
    are no sequence (an iterator, a set) are a ``TypeError`` naming them ``name``."""
    if isinstance(machines, str | bytes) or not isinstance(machines, Sequence):
        raise TypeError(f"{name} must be a tuple of MachineConfig, got {machines!r}")
    where_of: dict[str, At] = {}
    for i, machine in enumerate(machines):
        at = At(source, f"machine[{i + 1}]")
        if not isinstance(machine, MachineConfig):
            at.expected(machine, "a MachineConfig")
        machine._check(at)
        _unique(machine.name, where_of, at, "name")


def check_outputs(config: GatewayConfig) -> None:
    """Raise ``TypeError`` for an output of ``config`` that is neither None (not used) nor
    its settings' class (:class:`MqttSettings`, :class:`OpcUaSettings`), naming it
    ``config.mqtt`` or ``config.opcua``: what :class:`~focas_net.gateway.Gateway` and
    :func:`~focas_net.gateway.outputs` ask of a configuration built in Python."""
    for key, value, cls in (
        ("mqtt", config.mqtt, MqttSettings),
        ("opcua", config.opcua, OpcUaSettings),
    ):
        if value is not None and not isinstance(value, cls):
            raise TypeError(f"config.{key} must be an {cls.__name__} or None, got {value!r}")


def _unique(name: str, where_of: dict[str, At], at: At, key: str) -> None:
    """Note that machine ``name`` is at ``at``; refuse it at ``at``'s ``key`` when an
    earlier machine has that name."""
    first = where_of.setdefault(name, at)
    if first is not at:
        at.key(key).fail(f"machine name {name!r} is used twice (first by {first.path})")


def _groups(at: At, value: object, base: GroupIntervals) -> GroupIntervals:
    table = at.table(value, _GROUP_KEYS)
    groups = GroupIntervals(**{key: table.get(key, getattr(base, key)) for key in _GROUP_KEYS})
    groups.check(at)
    return GroupIntervals(*(float(getattr(groups, key)) for key in _GROUP_KEYS))


def _common(at: At, table: Mapping[str, Any], defaults: GroupIntervals) -> dict[str, Any]:
    """What a ``[[machine]]`` and a ``[[fleet]]`` share, as the file gives it (the values
    are checked by :meth:`MachineConfig.check`)."""
    if "host" not in table:
        at.key("host").fail("missing (the CNC's name or address)")
    out: dict[str, Any] = {"host": table["host"]}
    for key in ("protocol", "timeout"):
        if key in table:
            out[key] = table[key]
    if "paths" in table:
        out["paths"] = at.key("paths").array(table["paths"], 1, 10)
    out["groups"] = _groups(at.key("groups"), table.get("groups", {}), defaults)
    out["writes"] = _writes(at.key("writes"), table.get("writes", {}))
    return out


def _checked(at: At, config: MachineConfig) -> MachineConfig:
    """``config`` checked at ``at``, in the types it holds from then on."""
    config._check(at)
    paths = None if config.paths is None else tuple(config.paths)
    return replace(config, host=check_host(config.host), paths=paths, timeout=float(config.timeout))


def _machine(at: At, value: Mapping[str, Any], defaults: GroupIntervals) -> MachineConfig:
    table = at.table(value, _MACHINE_KEYS)
    if "name" not in table:
        at.key("name").fail(f"missing ({_NAME_TEXT})")
    out = _common(at, table, defaults)
    if "port" in table:
        out["port"] = table["port"]
    return _checked(at, MachineConfig(name=table["name"], **out))


def _fleet(at: At, value: Mapping[str, Any], defaults: GroupIntervals) -> list[MachineConfig]:
    table = at.table(value, _FLEET_KEYS)
    for key in ("name_prefix", "first_port", "count"):
        if key not in table:
            at.key(key).fail("missing")
    prefix = table["name_prefix"]
    if not isinstance(prefix, str) or not _NAME.fullmatch(prefix) or len(prefix) > 59:
        at.key("name_prefix").expected(prefix, "1..59 letters, digits, '-', '_' or '.'")
    first = at.key("first_port").checked(
        table["first_port"], check_port, "a port 1..65535", why=False
    )
    count = at.key("count").integer(table["count"], 1, MAX_FLEET)
    if first + count - 1 > 0xFFFF:
        at.key("count").fail(
            f"got {count}; expected at most {0xFFFF - first + 1} (from first_port {first} "
            f"the last machine would get port {first + count - 1})"
        )
    last = _fleet_name(prefix, count)
    if not _NAME.fullmatch(last):
        at.key("name_prefix").expected(
            prefix, f"a shorter prefix: the last name, {last!r}, is over 64 characters"
        )
    one = _checked(at, MachineConfig(name=last, port=first, **_common(at, table, defaults)))
    return [replace(one, name=_fleet_name(prefix, i + 1), port=first + i) for i in range(count)]


def _fleet_name(prefix: str, number: int) -> str:
    return f"{prefix}-{number:04d}"


def _ranges(at: At, value: object, low: int, high: int) -> tuple[tuple[int, int], ...]:
    """``[[first, last], ...]`` within ``low..high``, first <= last."""
    out: list[tuple[int, int]] = []
    for i, pair in enumerate(at.array(value, 0, 1000)):
        pat = at.index(i)
        if not isinstance(pair, list | tuple) or len(pair) != 2:
            pat.expected(pair, f"[first, last] with {low} <= first <= last <= {high}")
        first = pat.index(0).integer(pair[0], low, high)
        last = pat.index(1).integer(pair[1], first, high)
        out.append((first, last))
    return tuple(out)


def _pmc_range(at: At, value: object) -> tuple[str, int, int]:
    """``"R0-R99"`` (or ``"R0-99"``), ``"D100"``: an area letter and a byte range."""
    what = "an area letter and bytes: 'R0-R99' or 'D100'"
    match = _PMC_RANGE.fullmatch(value.strip()) if isinstance(value, str) else None
    if match is None:
        at.expected(value, what)
    letter, first_text, again, last_text = match.groups()
    first = int(first_text)
    last = first if last_text is None else int(last_text)
    problem = _pmc_problem(letter, first, last)
    if problem:
        at.expected(value, f"{what}, {problem}")
    if again and again.upper() != letter.upper():
        at.expected(value, f"{what}, one area from first to last")
    return PmcArea.parse(letter).name, first, last


def _pmc_problem(area: object, first: object, last: object) -> str | None:
    """What a PMC write gate of ``area`` (a letter), bytes ``first..last`` lacks, or None."""
    try:
        PmcArea.parse(area if isinstance(area, str) else "")
    except ValueError:
        return f"the area one of {''.join(a.name for a in PmcArea)}"
    if (
        isinstance(first, bool)
        or isinstance(last, bool)
        or not isinstance(first, int)
        or not isinstance(last, int)
        or not 0 <= first <= last <= _PMC_LAST_BYTE
    ):
        return f"first <= last <= {_PMC_LAST_BYTE}"
    return None


def _writes(at: At, value: object) -> WriteGates:
    table = at.table(value, _WRITE_KEYS)
    macros = _ranges(at.key("macros"), table.get("macros", []), -I16_MAX - 1, I16_MAX)
    params = _ranges(at.key("params"), table.get("params", []), 0, I16_MAX)
    pat = at.key("pmc")
    pmc = tuple(
        _pmc_range(pat.index(i), v) for i, v in enumerate(pat.array(table.get("pmc", []), 0, 1000))
    )
    return WriteGates(macros, params, pmc)  # (checked as the file gives them)


def _secret(at: At, table: Mapping[str, Any]) -> str | None:
    """``password``, or the environment variable ``password_env`` names (not both)."""
    if "password" in table and "password_env" in table:
        at.key("password_env").fail("give password or password_env, not both")
    if "password" in table:
        return at.key("password").text(table["password"], "a non-empty string")
    if "password_env" in table:
        name = at.key("password_env").text(table["password_env"], "an environment variable name")
        secret = os.environ.get(name)
        if not secret:
            at.key("password_env").fail(f"the environment variable {name} is not set (or empty)")
        return secret
    return None


def _mqtt(at: At, value: object, base: Path) -> MqttSettings:
    table = at.table(value, _MQTT_KEYS)
    out: dict[str, Any] = {}
    for key in (
        "host", "port", "prefix", "client_id", "username", "qos", "keepalive", "buffer", "gateway",
    ):  # fmt: skip
        if key in table:
            out[key] = table[key]
    if "tls" in table:
        out["tls"] = table["tls"]
    if "tls_ca" in table:
        name = at.key("tls_ca").text(table["tls_ca"], "a PEM file of certificate authorities")
        out["tls_ca"] = Path(name) if Path(name).is_absolute() else base / name
    out["password"] = _secret(at, table)
    if "deadbands" in table:
        bands = deadbands(at.key("deadbands"), table["deadbands"])
        out["deadbands"] = dict(bands)
    settings = MqttSettings(**out)
    settings.check(at.source)
    return replace(settings, deadbands={k: float(v) for k, v in settings.deadbands.items()})


def _file(at: At, value: object, base: Path) -> Path:
    name = at.text(value, "a file name")
    path = Path(name) if Path(name).is_absolute() else base / name
    if not path.is_file():
        why = "is a directory" if path.is_dir() else "does not exist"
        at.fail(f"got {name!r}; expected a file that exists ({path} {why})")
    return path


def _opcua(at: At, value: object, base: Path) -> OpcUaSettings:
    table = at.table(value, _OPCUA_KEYS)
    out: dict[str, Any] = {}
    if "endpoint" in table:
        out["endpoint"] = at.key("endpoint").text(table["endpoint"], "opc.tcp://HOST:PORT/PATH")
    if "namespace" in table:
        out["namespace"] = at.key("namespace").text(table["namespace"], "a namespace URI")
    if "writes" in table:
        out["writes"] = at.key("writes").boolean(table["writes"])
    if "anonymous" in table:
        out["anonymous"] = at.key("anonymous").boolean(table["anonymous"])
    users: list[OpcUaUser] = []
    if "users" in table:
        uat = at.key("users")
        for i, entry in enumerate(uat.tables(table["users"])):
            one = uat.index(i)
            user = one.table(entry, _USER_KEYS)
            if "name" not in user:
                one.key("name").fail("missing")
            name = one.key("name").text(user["name"], "a user name")
            secret = _secret(one, user)
            if secret is None:
                one.key("password").fail("missing (give password or password_env)")
            if any(u.name == name for u in users):
                one.key("name").fail(f"user {name!r} is given twice")
            users.append(OpcUaUser(name, secret))
    out["users"] = tuple(users)
    for key in ("certificate", "private_key"):
        if key in table:
            out[key] = Path(at.key(key).text(table[key], "a file name"))
    settings = OpcUaSettings(**out)
    settings.check(at.source)
    cert: Path | None = None
    private: Path | None = None
    if settings.certificate is not None:
        cert = _file(at.key("certificate"), table["certificate"], base)
        private = _file(at.key("private_key"), table["private_key"], base)
    # (the file's default made explicit: anonymous sessions wherever they may be)
    return replace(
        settings, anonymous=settings.anonymous_sessions, certificate=cert, private_key=private
    )
