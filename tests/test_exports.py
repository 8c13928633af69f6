"""The public surface of focas_net: each package's ``__all__`` is exact, each public name is
exported by exactly one subpackage (the top level only gathers some of them, as the same
objects), and each codec package (``focas_net.protocol``, ``focas_net.native``) is the one
surface of its modules.

``focas_net.web`` needs nothing beyond the standard library to be imported (aiohttp only when a
dashboard starts); should that change, it is left out when aiohttp is absent.
"""

from __future__ import annotations

import importlib
import pkgutil
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
    "focas_net.web",
    "focas_net.gateway",
    "focas_net.errors",
]


def _import(name: str) -> types.ModuleType:
    """Module ``name``; the test is skipped when importing it needs aiohttp, not installed."""
    try:
        return importlib.import_module(name)
    except ModuleNotFoundError as exc:
        if exc.name != "aiohttp":
            raise
        pytest.skip(f"{name} needs aiohttp, not installed")


def _importable(names: list[str]) -> list[types.ModuleType]:
    """The modules of ``names`` that import: those needing aiohttp are left out without it."""
    modules = []
    for name in names:
        try:
            modules.append(importlib.import_module(name))
        except ModuleNotFoundError as exc:
            if exc.name != "aiohttp":
                raise
    return modules


@pytest.mark.parametrize("package", PACKAGES)
def test_package_all_names_exist_and_star_import_matches(package: str) -> None:
    module = _import(package)
    assert [n for n in module.__all__ if not hasattr(module, n)] == []
    assert len(module.__all__) == len(set(module.__all__))
    namespace: dict[str, object] = {}
    exec(f"from {package} import *", namespace)
    namespace.pop("__builtins__", None)
    assert set(namespace) == set(module.__all__)


@pytest.mark.parametrize("package", PACKAGES)
def test_package_objects_it_holds_are_exported(package: str) -> None:
    """A class or function of its own a package holds under a public name is in its
    ``__all__``: nothing of it is reachable without being exported."""
    module = _import(package)
    held = {
        name
        for name, value in vars(module).items()
        if not name.startswith("_")
        and isinstance(value, type | types.FunctionType)
        and f"{getattr(value, '__module__', '')}.".startswith(f"{package}.")
    }
    assert held - set(module.__all__) == set()


#: Every subpackage and module of focas_net that exports names: each public object has one home
#: among them.
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
    "focas_net.web",
    "focas_net.gateway",
]


def test_every_package_of_focas_net_has_a_home() -> None:
    """A new package of focas_net is added to :data:`HOMES` (and so checked here)."""
    import focas_net

    packages = {f"focas_net.{m.name}" for m in pkgutil.iter_modules(focas_net.__path__)}
    packages = {p for p in packages if not p.rpartition(".")[2].startswith("_")}
    assert packages == set(HOMES)


def test_each_name_is_exported_by_one_subpackage() -> None:
    """A public name means one thing: no two subpackages export the same name (the top level
    gathers some of them, as the same objects)."""
    homes: dict[str, list[str]] = {}
    for module in _importable(HOMES):
        for name in module.__all__:
            homes.setdefault(name, []).append(module.__name__)
    assert {n: where for n, where in homes.items() if len(where) > 1} == {}


def test_each_object_is_exported_by_one_subpackage() -> None:
    """No subpackage re-exports another's objects (the top level only gathers them)."""
    homes: dict[int, str] = {}
    for module in _importable(HOMES):
        package = module.__name__
        for name in module.__all__:
            value = getattr(module, name)
            if isinstance(value, int | str | bytes | frozenset | tuple | bool) or value is None:
                continue  # constants: equal values are not a re-export
            other = homes.setdefault(id(value), f"{package}.{name}")
            assert other == f"{package}.{name}", f"{package}.{name} is also {other}"


def test_top_level_names_are_the_subpackages_objects() -> None:
    """Each name the top level gathers is exported by exactly one subpackage, as its object."""
    import focas_net

    homes = _importable(HOMES)
    for name in focas_net.__all__:
        if name == "__version__":
            continue
        value = getattr(focas_net, name)
        exporters = [h.__name__ for h in homes if name in h.__all__]
        assert len(exporters) == 1, (name, exporters)
        assert getattr(importlib.import_module(exporters[0]), name) is value, name


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
    "_native_offsets",
    "projection",
    "reconnect",
    "sim_control",
    "_native_info",
    "_native_modal",
    "_started",
    "_values",
    "_native_files",
    "_native_spindles",
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


#: The codec packages: each is the one public surface of its modules.
CODECS = ["focas_net.protocol", "focas_net.native"]


def _modules(package: types.ModuleType) -> list[types.ModuleType]:
    return [
        importlib.import_module(f"{package.__name__}.{m.name}")
        for m in pkgutil.iter_modules(package.__path__)
    ]


@pytest.mark.parametrize("name", CODECS)
def test_codec_names_are_exported_once_each_from_its_module(name: str) -> None:
    """Every name a codec module declares public is exported by the package, as that module's
    object; no two modules declare the same name (no module gathers another's)."""
    package = importlib.import_module(name)
    homes: dict[str, list[str]] = {}
    for module in _modules(package):
        if module.__name__.rpartition(".")[2].startswith("_"):
            continue  # a private module: its __all__ is for its siblings
        for n in module.__all__:
            homes.setdefault(n, []).append(module.__name__)
            assert getattr(package, n) is getattr(module, n), f"{module.__name__}.{n}"
    assert {n: where for n, where in homes.items() if len(where) > 1} == {}
    assert set(homes) - set(package.__all__) == set()


def test_the_native_package_exports_exactly_its_modules_names() -> None:
    """``focas_net.native`` exports what its modules declare and nothing else (and ``calls``,
    the module of the library's calls, as itself)."""
    import focas_net.native as native

    declared = [n for module in _modules(native) for n in module.__all__]
    assert sorted(native.__all__) == sorted([*declared, "calls"])
    assert native.calls is importlib.import_module("focas_net.native.calls")


@pytest.mark.parametrize("name", CODECS)
def test_codec_modules_declare_only_what_they_define(name: str) -> None:
    """A class or function in a codec module's ``__all__`` is defined there: no module of a
    codec is a second export list of another's."""
    for module in _modules(importlib.import_module(name)):
        foreign = [
            n
            for n in module.__all__
            if isinstance(getattr(module, n), type | types.FunctionType)
            and getattr(module, n).__module__ != module.__name__
        ]
        assert foreign == [], module.__name__


def test_adapter_names_have_one_home() -> None:
    """Each public name of ``focas_net.adapters`` is declared in the ``__all__`` of exactly one
    of its modules and exported as that module's object."""
    import focas_net.adapters as adapters

    homes: dict[str, list[str]] = {}
    for module in _modules(adapters):
        for n in set(module.__all__) & set(adapters.__all__):
            homes.setdefault(n, []).append(module.__name__)
            assert getattr(adapters, n) is getattr(module, n), n
    assert {n: m for n, m in homes.items() if len(m) > 1} == {}
    assert set(homes) == set(adapters.__all__)
