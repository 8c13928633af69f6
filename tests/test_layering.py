"""Who may import whom: the machine knows no protocol, each adapter knows the machine and its
own codec only. Read from the source with ``ast``, so nothing is imported to find out."""

from __future__ import annotations

import ast
import sys
from pathlib import Path

import pytest

PACKAGE = Path(__file__).resolve().parent.parent / "focas_net"


def _module_name(path: Path) -> str:
    parts = list(path.relative_to(PACKAGE.parent).with_suffix("").parts)
    if parts[-1] == "__init__":
        parts.pop()
    return ".".join(parts)


def imports_of(path: Path) -> set[str]:
    """Every module ``path`` imports, relative imports resolved (``from x import y`` counts as
    ``x`` and, when ``x.y`` is a module of focas_net, as ``x.y`` too)."""
    name = _module_name(path)
    package = name if path.name == "__init__.py" else name.rpartition(".")[0]
    found: set[str] = set()
    for node in ast.walk(ast.parse(path.read_text(), str(path))):
        if isinstance(node, ast.Import):
            found.update(alias.name for alias in node.names)
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = package.split(".")
                base = base[: len(base) - node.level + 1]
                target = ".".join([*base, node.module] if node.module else base)
            else:
                assert node.module is not None
                target = node.module
            found.add(target)
            for alias in node.names:
                candidate = f"{target}.{alias.name}"
                parts = candidate.split(".")
                if (PACKAGE.parent.joinpath(*parts).with_suffix(".py")).exists():
                    found.add(candidate)
    return found


def _allowed(module: str, prefixes: tuple[str, ...]) -> bool:
    if module.split(".")[0] in sys.stdlib_module_names or module == "__future__":
        return True
    return any(module == p or module.startswith(p + ".") for p in prefixes)


def _files(relative: str) -> list[Path]:
    target = PACKAGE / relative
    return sorted(target.rglob("*.py")) if target.is_dir() else [target]


#: Modules that know no protocol and no machine: anyone may import them.
NEUTRAL = ("focas_net.errors", "focas_net.versamax", "focas_net._memo")


@pytest.mark.parametrize("path", _files("sim"), ids=lambda p: p.name)
def test_the_machine_imports_no_protocol(path: Path) -> None:
    found = imports_of(path)
    assert {m for m in found if not _allowed(m, ("focas_net.sim", *NEUTRAL))} == set()
    assert not any(m.startswith(("focas_net.protocol", "focas_net.native")) for m in found)


#: The machine's components: ``sim/machine.py`` is a facade over them.
COMPONENTS = sorted((PACKAGE / "sim").glob("_[a-z]*.py"))
#: What builds machines or is the facade itself: no component imports them.
FACADE = (
    "focas_net.sim",
    "focas_net.sim.machine",
    "focas_net.sim.default",
    "focas_net.sim.machinefile",
)


def test_every_component_is_part_of_the_machine() -> None:
    """Each component is imported by the machine or by another component: none is left over."""
    users = imports_of(PACKAGE / "sim" / "machine.py").union(*map(imports_of, COMPONENTS))
    assert COMPONENTS
    assert {f"focas_net.sim.{p.stem}" for p in COMPONENTS} - users == set()


@pytest.mark.parametrize("path", COMPONENTS, ids=lambda p: p.name)
def test_a_machine_component_never_imports_the_facade(path: Path) -> None:
    """Components import each other, :mod:`focas_net.sim.nc` and the neutral modules; the
    machine imports them, never the other way round."""
    assert set(imports_of(path)) & set(FACADE) == set()


@pytest.mark.parametrize("path", _files("sim/nc"), ids=lambda p: p.name)
def test_the_part_program_package_needs_only_the_standard_library(path: Path) -> None:
    assert {m for m in imports_of(path) if not _allowed(m, ("focas_net.sim.nc",))} == set()


def test_the_versamax_record_is_neutral() -> None:
    found = imports_of(PACKAGE / "versamax.py")
    assert {m for m in found if not _allowed(m, ("focas_net.errors",))} == set()


def test_what_the_adapters_share_knows_no_protocol() -> None:
    found = imports_of(PACKAGE / "adapters" / "_common.py")
    assert {m for m in found if not _allowed(m, ("focas_net.sim", *NEUTRAL))} == set()


def test_the_packed_adapter_imports_the_machine_and_its_codec_only() -> None:
    found = imports_of(PACKAGE / "adapters" / "packed.py")
    own = ("focas_net.sim", "focas_net.protocol", "focas_net.adapters._common", *NEUTRAL)
    assert {m for m in found if not _allowed(m, own)} == set()


NATIVE_ADAPTER = sorted(
    [PACKAGE / "adapters" / "native.py", *(PACKAGE / "adapters").glob("_native_*.py")]
)


@pytest.mark.parametrize("path", NATIVE_ADAPTER, ids=lambda p: p.name)
def test_the_native_adapter_imports_the_machine_and_its_codec_only(path: Path) -> None:
    found = imports_of(path)
    own = (
        "focas_net.sim",
        "focas_net.native",
        "focas_net.adapters._common",
        *(f"focas_net.adapters.{p.stem}" for p in NATIVE_ADAPTER),
        *NEUTRAL,
    )
    assert {m for m in found if not _allowed(m, own)} == set()


def test_the_import_reader_sees_relative_imports() -> None:
    found = imports_of(PACKAGE / "sim" / "default.py")
    assert "focas_net.sim.machine" in found and "focas_net.versamax" in found
    assert "focas_net.protocol" in imports_of(PACKAGE / "client" / "client.py")


def test_the_native_client_never_sees_the_machine() -> None:
    """The native client reaches the CNC through the codecs only: no machine, adapter or
    server."""
    found = imports_of(PACKAGE / "client" / "native.py")
    assert "focas_net.native.calls" in found
    assert not any(
        m.startswith(("focas_net.sim", "focas_net.adapters", "focas_net.server")) for m in found
    )


TESTS = Path(__file__).resolve().parent


@pytest.mark.parametrize("path", sorted(TESTS.glob("*.py")), ids=lambda p: p.name)
def test_no_test_module_imports_another_or_conftest(path: Path) -> None:
    """Shared test helpers live in support modules (``support``, ``peers``, ``cli_support``,
    ``fwlib_support``), never in a test module or ``conftest``."""
    imported: set[str] = set()
    for node in ast.walk(ast.parse(path.read_text(), str(path))):
        if isinstance(node, ast.Import):
            imported.update(alias.name for alias in node.names)
        elif isinstance(node, ast.ImportFrom) and node.module and not node.level:
            imported.add(node.module)
    offending = {m for m in imported if m.startswith("test_") or m == "conftest"}
    assert not offending, f"{path.name} imports {sorted(offending)}"
