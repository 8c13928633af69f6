"""The gateway's configuration file: every refusal names the file, the key as written, what
was typed and what is expected; fleets expand; shards split the machines."""

from __future__ import annotations

from pathlib import Path

import pytest

from focas_net.gateway import GroupIntervals, WriteGates
from focas_net.gateway.config import ConfigError, load_config, parse_config, shard

EXAMPLE = Path(__file__).resolve().parent.parent / "examples" / "gateway.toml"

ONE = """
[[machine]]
name = "mill-1"
host = "127.0.0.1"
"""


USER = "[[opcua.users]]\nname = 'op'\npassword = 'pw'\n"
FLEET = "[[fleet]]\nname_prefix='f'\nhost='h'\nfirst_port=1\ncount=3"


def refusal(text: str) -> str:
    with pytest.raises(ConfigError) as caught:
        parse_config(text, "plant.toml")
    return str(caught.value)


#: (what the file says, the words the refusal must have): the key path as written first.
BAD: list[tuple[str, tuple[str, ...]]] = [
    ("", ("plant.toml: no machine",)),
    ("[[machine]]\nname='a'\nhost='h'\nprotocl='native'", ("machine[1].protocl", "'protocol'")),
    ("[groups]\nfast = 0\n" + ONE, ("groups.fast: got 0", "seconds >= 0.01")),
    ("[groups]\nfats = 1\n" + ONE, ("groups.fats: unknown key", "'fast'")),
    (ONE + ONE.replace("mill-1", "b") + "[machine.groups]\nslow = -1", ("machine[2].groups.slow",)),
    (ONE + "port = 70000", ("machine[1].port: got 70000", "1..65535")),
    (ONE + "port = true", ("machine[1].port: got true",)),
    (ONE + "protocol = 'fwlib'", ("machine[1].protocol: got 'fwlib'", "'native' or 'packed'")),
    (ONE + "paths = []", ("machine[1].paths: got 0 entries", "1..10")),
    (ONE + "paths = [1, 11]", ("machine[1].paths[2]: got 11", "1..10")),
    (ONE + "paths = [1, 1]", ("machine[1].paths", "each path once")),
    (ONE + "timeout = 0", ("machine[1].timeout: got 0",)),
    (ONE.replace('"mill-1"', '"mill 1"'), ("machine[1].name: got 'mill 1'", "letters, digits")),
    (ONE.replace('"mill-1"', '"a/b"'), ("machine[1].name: got 'a/b'",)),
    (ONE.replace('"mill-1"', '"' + "m" * 65 + '"'), ("machine[1].name",)),
    ("[[machine]]\nhost = 'h'", ("machine[1].name: missing",)),
    ("[[machine]]\nname = 'a'", ("machine[1].host: missing",)),
    (ONE.replace('"127.0.0.1"', '"127.0.0.1:8193"'), ("machine[1].host", "host and a port")),
    (ONE + ONE, ("machine[2].name", "'mill-1' is used twice", "machine[1]")),
    (ONE + "[machine.writes]\nmacros = [[5, 1]]", ("machine[1].writes.macros[1][2]: got 1",)),
    (
        ONE + "[machine.writes]\nmacros = [5]",
        ("machine[1].writes.macros[1]: got 5", "[first, last]"),
    ),
    (ONE + "[machine.writes]\nparams = [[0, 40000]]", ("writes.params[1][2]: got 40000",)),
    (ONE + "[machine.writes]\npmc = ['Q0-Q9']", ("writes.pmc[1]: got 'Q0-Q9'", "one of")),
    (ONE + "[machine.writes]\npmc = ['R9-R0']", ("writes.pmc[1]", "first <= last")),
    (ONE + "[machine.writes]\npmc = ['R0-D9']", ("writes.pmc[1]", "one area")),
    (ONE + "[machine.writes]\npmc = ['R']", ("writes.pmc[1]: got 'R'",)),
    (ONE + "[machine.writes]\npmc = ['R\u0661\u0662']", ("writes.pmc[1]: got 'R\u0661\u0662'",)),
    (ONE + "[machine.writes]\npmc = ['R0-R65536']", ("writes.pmc[1]", "65535")),
    (ONE + "[machine.writes]\npmc = ['R" + "9" * 5000 + "']", ("writes.pmc[1]: got 'R99",)),
    (ONE + "port = " + "9" * 5000, ("plant.toml: not valid TOML", "5000 digits")),
    (
        ONE + "[machine.writes]\nmacro = [[1, 2]]",
        ("machine[1].writes.macro: unknown key", "'macros'"),
    ),
    ("[[fleet]]\nname_prefix='f'\nhost='h'\nfirst_port=65535\ncount=2", ("fleet[1].count: got 2",)),
    ("[[fleet]]\nname_prefix='f'\nhost='h'\nfirst_port=1\ncount=0", ("fleet[1].count: got 0",)),
    (
        f"[[fleet]]\nname_prefix='{'p' * 59}'\nhost='h'\nfirst_port=1\ncount=10000",
        ("fleet[1].name_prefix: got 'ppp", "the last name", "64"),
    ),
    ("[[fleet]]\nname_prefix='f'\nhost='h'\ncount=2", ("fleet[1].first_port: missing",)),
    (
        ONE.replace("mill-1", "f-0002")
        + "[[fleet]]\nname_prefix='f'\nhost='h'\nfirst_port=1\ncount=3",
        ("fleet[1].name_prefix", "'f-0002' is used twice", "machine[1]"),
    ),
    (ONE + "[mqtt]\nport = 0", ("mqtt.port: got 0",)),
    (ONE + "[mqtt]\nqos = 3", ("mqtt.qos: got 3", "0..2")),
    (ONE + "[mqtt]\nprefix = '$SYS/x'", ("mqtt.prefix: got '$SYS/x'", "a '$' first")),
    (ONE + "[mqtt]\nprefix = 'a/'", ("mqtt.prefix: got 'a/'", "'/' at either end")),
    (ONE + "[mqtt]\nprefix = 'a/#'", ("mqtt.prefix: got 'a/#'",)),
    (ONE + "[mqtt]\npasword = 'x'", ("mqtt.pasword: unknown key", "'password'")),
    (ONE + "[mqtt]\npassword_env = 'FOCAS_NET_NO_SUCH_VARIABLE'", ("FOCAS_NET_NO_SUCH_VARIABLE",)),
    (ONE + "[mqtt]\npassword = 'a'\npassword_env = 'B'", ("mqtt.password_env", "not both")),
    (ONE + "[mqtt.deadbands]\nmode = 1.0", ("mqtt.deadbands.mode: mode is not a number",)),
    (ONE + "[mqtt.deadbands]\nfeed = -1", ("mqtt.deadbands.feed: got -1",)),
    (ONE + "[opcua]\nendpoint = 'http://x:1/'", ("opcua.endpoint: got 'http://x:1/'",)),
    (
        ONE + "[opcua]\nendpoint = 'opc.tcp://0.0.0.0:4840/'\nanonymous = true",
        ("opcua.anonymous: got true", "beyond the loopback"),
    ),
    (ONE + "[opcua]\nendpoint = 'opc.tcp://10.0.0.1:4840/'", ("plant.toml: opcua: no way in",)),
    (ONE + "[opcua]\nwrites = true", ("plant.toml: opcua: no way in", "writes = true")),
    (ONE + "[opcua]\nwrites = true\nanonymous = true", ("opcua.anonymous: got true", "users")),
    (
        ONE + "[opcua]\nendpoint = 'opc.tcp://10.0.0.1:4840/'\n" + USER,
        ("opcua.certificate: missing", "beyond the loopback"),
    ),
    (ONE + "[opcua]\ncertificate = 'c.pem'", ("opcua.private_key: missing", "both")),
    (
        ONE + "[opcua]\ncertificate = 'no-such.pem'\nprivate_key = 'no-such.key'",
        ("opcua.certificate: got 'no-such.pem'", "exists"),
    ),
    (ONE + "[[opcua.users]]\nname = 'op'", ("opcua.users[1].password: missing",)),
    ("machine = 3", ("plant.toml: machine: got 3", "array of tables")),
    ("[[machine]\n", ("plant.toml: not valid TOML",)),
    ("[plant]\n" + ONE, ("plant.toml: plant: unknown key",)),
]


@pytest.mark.parametrize(("text", "words"), BAD, ids=[w[0] for _, w in BAD])
def test_a_refusal_names_the_key_what_was_typed_and_what_is_expected(
    text: str, words: tuple[str, ...]
) -> None:
    message = refusal(text)
    assert message.startswith("plant.toml: ")
    assert "\n" not in message
    for word in words:
        assert word in message, (word, message)


def test_one_machine_and_its_defaults() -> None:
    (machine,) = parse_config(ONE, "plant.toml").machines
    assert (machine.name, machine.host, machine.port, machine.protocol) == (
        "mill-1", "127.0.0.1", 8193, "native",
    )  # fmt: skip
    assert machine.groups == GroupIntervals(1.0, 10.0, 1.0)
    assert machine.writes == WriteGates()
    assert machine.paths is None


def test_groups_default_for_every_machine_and_each_may_override() -> None:
    text = (
        "[groups]\nslow = 30\n"
        + ONE
        + "[machine.groups]\nfast = 0.5\n"
        + ONE.replace("mill-1", "mill-2")
    )
    first, second = parse_config(text).machines
    assert first.groups == GroupIntervals(0.5, 30.0, 1.0)
    assert second.groups == GroupIntervals(1.0, 30.0, 1.0)


def test_write_gates_are_ranges() -> None:
    text = ONE + "[machine.writes]\nmacros = [[500, 599], [100, 100]]\nparams = [[6711, 6713]]\n"
    text += "pmc = ['R0-R99', 'D100', 'e5-9']\n"
    (machine,) = parse_config(text).machines
    assert machine.writes == WriteGates(
        ((500, 599), (100, 100)), ((6711, 6713),), (("R", 0, 99), ("D", 100, 100), ("E", 5, 9))
    )


def test_a_fleet_is_machines_on_consecutive_ports() -> None:
    text = """
[[fleet]]
name_prefix = "cell"
host = "10.0.0.5"
first_port = 18193
count = 3
protocol = "packed"
paths = [1, 2]
[fleet.groups]
alarms = 2
[fleet.writes]
macros = [[500, 510]]
"""
    machines = parse_config(text).machines
    assert [(m.name, m.port) for m in machines] == [
        ("cell-0001", 18193), ("cell-0002", 18194), ("cell-0003", 18195),
    ]  # fmt: skip
    assert {(m.host, m.protocol, m.paths, m.groups.alarms) for m in machines} == {
        ("10.0.0.5", "packed", (1, 2), 2.0)
    }
    assert machines[2].writes.macros == ((500, 510),)


def test_shards_take_every_nth_machine_and_cover_the_file_once() -> None:
    text = "[[fleet]]\nname_prefix='m'\nhost='h'\nfirst_port=1000\ncount=10\n"
    config = parse_config(text)
    names = [[m.name for m in shard(config, i, 3).machines] for i in (1, 2, 3)]
    assert names[0] == ["m-0001", "m-0004", "m-0007", "m-0010"]
    assert sorted(n for part in names for n in part) == [m.name for m in config.machines]
    assert shard(config, 1, 1) == config
    for index, count, words in ((0, 3, "1..3"), (4, 3, "1..3"), (1, 0, "1 or more")):
        with pytest.raises(ConfigError, match=words):
            shard(config, index, count)
    with pytest.raises(ConfigError, match="no machine"):
        shard(parse_config(ONE), 2, 2)


def test_each_shard_has_its_own_opcua_port_and_mqtt_client_id() -> None:
    outputs = "[mqtt]\nclient_id='plant'\n[opcua]\nendpoint='opc.tcp://[::1]:4840/focas_net/'\n"
    text = "[[fleet]]\nname_prefix='m'\nhost='h'\nfirst_port=1000\ncount=4\n" + outputs
    config = parse_config(text)
    shards = [shard(config, i, 3) for i in (1, 2, 3)]
    assert [s.opcua.endpoint for s in shards if s.opcua] == [
        "opc.tcp://[::1]:4840/focas_net/",
        "opc.tcp://[::1]:4841/focas_net/",
        "opc.tcp://[::1]:4842/focas_net/",
    ]
    assert [s.mqtt.client_id for s in shards if s.mqtt] == ["plant-1", "plant-2", "plant-3"]
    assert shard(config, 1, 1) == config  # one shard: the file as written
    made_up = parse_config(text.replace("client_id='plant'\n", ""))
    made = [shard(made_up, i, 2).mqtt for i in (1, 2)]
    ids = [(m.client_id, m.gateway) for m in made if m is not None]
    assert ids == [(None, "focas-net-1"), (None, "focas-net-2")]  # (client ids made up each)
    top = parse_config(text.replace(":4840/", ":65534/"))
    second = shard(top, 2, 3).opcua
    assert second is not None and second.endpoint == "opc.tcp://[::1]:65535/focas_net/"
    with pytest.raises(ConfigError, match="passes 65535"):
        shard(top, 3, 3)
    anywhere = parse_config(text.replace(":4840/", ":0/"))  # any free port: each its own
    assert {s.opcua.endpoint for i in (1, 2, 3) if (s := shard(anywhere, i, 3)).opcua} == {
        "opc.tcp://[::1]:0/focas_net/"
    }


def test_mqtt_and_opcua_settings(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    (tmp_path / "server.pem").write_text("cert")
    (tmp_path / "server.key").write_text("key")
    monkeypatch.setenv("FOCAS_NET_TEST_SECRET", "s3cret")
    text = (
        ONE
        + """
[mqtt]
host = "broker.local"
prefix = "plant/a"
username = "collector"
password_env = "FOCAS_NET_TEST_SECRET"
qos = 0
[mqtt.deadbands]
feed = 5
absolute = 0.01

[opcua]
endpoint = "opc.tcp://0.0.0.0:4841/plant"
certificate = "server.pem"
private_key = "server.key"
writes = true
[[opcua.users]]
name = "operator"
password_env = "FOCAS_NET_TEST_SECRET"
"""
    )
    path = tmp_path / "plant.toml"
    path.write_text(text)
    config = load_config(path)
    assert config.mqtt is not None and config.opcua is not None
    mqtt = config.mqtt
    assert (mqtt.host, mqtt.prefix, mqtt.username, mqtt.password, mqtt.qos) == (
        "broker.local", "plant/a", "collector", "s3cret", 0,
    )  # fmt: skip
    assert config.mqtt.deadbands == {"feed": 5.0, "absolute": 0.01}
    assert config.opcua.anonymous is False  # beyond the loopback: off unless said
    assert config.opcua.certificate == tmp_path / "server.pem"
    assert [(u.name, u.password) for u in config.opcua.users] == [("operator", "s3cret")]
    assert config.opcua.writes is True
    loopback = parse_config(ONE + "[opcua]\n[mqtt]\n")
    assert loopback.opcua is not None and loopback.opcua.anonymous is True
    assert loopback.mqtt is not None and loopback.mqtt.password is None
    assert parse_config(ONE).opcua is None


def test_a_file_that_cannot_be_read_is_named(tmp_path: Path) -> None:
    with pytest.raises(ConfigError, match=r"missing\.toml: no such file"):
        load_config(tmp_path / "missing.toml")
    bad = tmp_path / "latin.toml"
    bad.write_bytes(b"name = '\xe9'")
    with pytest.raises(ConfigError, match=r"latin\.toml: not UTF-8"):
        load_config(bad)


def test_the_example_configuration_reads() -> None:
    config = load_config(EXAMPLE)
    assert len(config.machines) == 4
    assert config.mqtt is not None and config.opcua is not None
