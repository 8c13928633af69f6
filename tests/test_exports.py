"""The public surface of ``focas_net.protocol``: ``__all__`` is exact.

The top-level ``focas_net`` package is checked once its ``__init__.py`` exports are settled;
until then only the protocol layer is covered here.
"""

from __future__ import annotations

import importlib
import types

import pytest

import focas_net.protocol as protocol
from focas_net.errors import FocasError

SUBMODULES = ["alarms", "codecs", "commands", "frame", "values", "versamax"]


def test_all_names_exist() -> None:
    missing = [name for name in protocol.__all__ if not hasattr(protocol, name)]
    assert missing == []


def test_all_has_no_duplicates() -> None:
    assert len(protocol.__all__) == len(set(protocol.__all__))


def test_every_public_name_is_in_all() -> None:
    public = {
        name
        for name, value in vars(protocol).items()
        if not name.startswith("_") and not isinstance(value, types.ModuleType)
    }
    assert public - set(protocol.__all__) == set()


def test_star_import_gives_exactly_all() -> None:
    namespace: dict[str, object] = {}
    exec("from focas_net.protocol import *", namespace)
    namespace.pop("__builtins__", None)
    assert set(namespace) == set(protocol.__all__)


@pytest.mark.parametrize("name", SUBMODULES)
def test_submodule_all_is_exported_by_the_package(name: str) -> None:
    module = importlib.import_module(f"focas_net.protocol.{name}")
    declared = set(module.__all__)
    assert [n for n in declared if not hasattr(module, n)] == []
    assert declared - set(protocol.__all__) == set()
    for n in declared:
        assert getattr(protocol, n) is getattr(module, n)


@pytest.mark.parametrize("name", SUBMODULES)
def test_submodule_public_classes_and_functions_are_declared(name: str) -> None:
    """A class or function defined in a submodule without a leading underscore is public."""
    module = importlib.import_module(f"focas_net.protocol.{name}")
    defined_here = {
        n
        for n, v in vars(module).items()
        if not n.startswith("_")
        and isinstance(v, type | types.FunctionType)
        and getattr(v, "__module__", None) == module.__name__
    }
    assert defined_here - set(module.__all__) == set()


def test_protocol_exports_no_exceptions() -> None:
    """The exception tree lives in :mod:`focas_net.errors`, shared by both protocols."""
    errors = [
        n
        for n in protocol.__all__
        if isinstance(getattr(protocol, n), type) and issubclass(getattr(protocol, n), Exception)
    ]
    assert errors == []


def test_error_module_exceptions_share_one_base() -> None:
    import focas_net.errors as errors_module

    errors = [
        v
        for v in (getattr(errors_module, n) for n in errors_module.__all__)
        if isinstance(v, type) and issubclass(v, Exception)
    ]
    assert len(errors) >= 8
    assert all(issubclass(e, FocasError) for e in errors)


PACKAGES = [
    "focas_net",
    "focas_net.client",
    "focas_net.server",
    "focas_net.sim",
    "focas_net.native",
    "focas_net.cli",
    "focas_net.adapters",
    "focas_net.versamax",
]


@pytest.mark.parametrize("package", PACKAGES)
def test_package_all_names_exist_and_star_import_matches(package: str) -> None:
    module = importlib.import_module(package)
    assert [n for n in module.__all__ if not hasattr(module, n)] == []
    assert len(module.__all__) == len(set(module.__all__))
    namespace: dict[str, object] = {}
    exec(f"from {package} import *", namespace)
    namespace.pop("__builtins__", None)
    assert set(namespace) == set(module.__all__)


#: The machine, its adapters and the codecs: each public object has one home among them.
HOMES = [
    "focas_net.sim",
    "focas_net.adapters",
    "focas_net.versamax",
    "focas_net.native",
    "focas_net.protocol",
    "focas_net.errors",
    "focas_net.client",
    "focas_net.server",
    "focas_net.cli",
]


def test_each_name_is_exported_by_one_subpackage() -> None:
    """A public name means one thing: no two subpackages export the same name (the top level
    gathers some of them, as the same objects)."""
    homes: dict[str, list[str]] = {}
    for package in HOMES:
        for name in importlib.import_module(package).__all__:
            homes.setdefault(name, []).append(package)
    assert {n: where for n, where in homes.items() if len(where) > 1} == {}


def test_each_object_is_exported_by_one_subpackage() -> None:
    """No subpackage re-exports another's objects (the top level only gathers them)."""
    homes: dict[int, str] = {}
    for package in HOMES:
        module = importlib.import_module(package)
        for name in module.__all__:
            value = getattr(module, name)
            if isinstance(value, int | str | bytes | frozenset | tuple | bool) or value is None:
                continue  # constants: equal values are not a re-export
            other = homes.setdefault(id(value), f"{package}.{name}")
            assert other == f"{package}.{name}", f"{package}.{name} is also {other}"


def test_top_level_names_are_the_subpackages_objects() -> None:
    import focas_net

    homes = [importlib.import_module(p) for p in PACKAGES[1:]] + [protocol]
    homes.append(importlib.import_module("focas_net.errors"))
    for name in focas_net.__all__:
        if name == "__version__":
            continue
        value = getattr(focas_net, name)
        assert any(getattr(home, name, None) is value for home in homes), name


def test_top_level_exceptions_share_one_base() -> None:
    import focas_net

    errors = [
        v
        for v in (getattr(focas_net, n) for n in focas_net.__all__)
        if isinstance(v, type) and issubclass(v, Exception)
    ]
    assert {e.__name__ for e in errors} >= {"CncError", "FocasConnectionError", "FocasTimeoutError"}
    assert all(issubclass(e, focas_net.FocasError) for e in errors)
    assert issubclass(focas_net.NotSentError, focas_net.FocasConnectionError)


CLIENT_MODULES = [
    "client",
    "cnc",
    "connection",
    "many",
    "native",
    "projection",
    "reconnect",
    "sim_control",
    "_started",
    "_values",
]


def test_client_names_have_one_home() -> None:
    """Each public name of ``focas_net.client`` is declared in the ``__all__`` of exactly one
    of its modules and exported as that module's object; ``FaultKind`` and ``FaultScope`` (the
    arguments of ``client.sim.inject_fault``) are those of ``focas_net.protocol``."""
    import focas_net.client as client

    homes: dict[str, list[str]] = {}
    for name in CLIENT_MODULES:
        module = importlib.import_module(f"focas_net.client.{name}")
        for n in module.__all__:
            homes.setdefault(n, []).append(name)
            assert getattr(client, n) is getattr(module, n), n
    assert {n: m for n, m in homes.items() if len(m) > 1} == {}
    assert set(homes) == set(client.__all__)
