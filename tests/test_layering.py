"""Who may import whom: every row of the table "Who may import whom" in docs/architecture.md,
the modules the table does not name, and no import cycle inside a package. Read from the source
with ``ast``, so nothing is imported to find out: for the rows every import statement (in a
function's body and under ``TYPE_CHECKING`` too), for the cycles every import that runs."""

from __future__ import annotations

import ast
import re
import sys
from collections.abc import Iterator
from pathlib import Path

import pytest

PACKAGE = Path(__file__).resolve().parent.parent / "focas_net"
ARCHITECTURE = PACKAGE.parent / "docs" / "architecture.md"


def _module_name(path: Path) -> str:
    parts = list(path.relative_to(PACKAGE.parent).with_suffix("").parts)
    if parts[-1] == "__init__":
        parts.pop()
    return ".".join(parts)


def _is_type_checking(node: ast.AST) -> bool:
    return isinstance(node, ast.If) and ast.unparse(node.test) in (
        "TYPE_CHECKING",
        "typing.TYPE_CHECKING",
    )


def _statements(node: ast.AST, typing: bool, lazy: bool) -> Iterator[ast.AST]:
    """The nodes below ``node``; without ``typing`` those only a type checker reads (``if
    TYPE_CHECKING:``) left out, without ``lazy`` the bodies of functions."""
    for child in ast.iter_child_nodes(node):
        if not typing and _is_type_checking(child):
            assert isinstance(child, ast.If)
            for other in child.orelse:
                yield other
                yield from _statements(other, typing, lazy)
            continue
        if not lazy and isinstance(child, ast.FunctionDef | ast.AsyncFunctionDef | ast.Lambda):
            continue
        yield child
        yield from _statements(child, typing, lazy)


def imports_of(path: Path, *, typing: bool = True, lazy: bool = True) -> set[str]:
    """Every module ``path`` imports, relative imports resolved (``from x import y`` counts as
    ``x`` and, when ``x.y`` is a module of focas_net, as ``x.y`` too). Without ``typing`` the
    imports made for a type checker only are left out, without ``lazy`` those in functions:
    what importing ``path`` itself imports."""
    name = _module_name(path)
    package = name if path.name == "__init__.py" else name.rpartition(".")[0]
    found: set[str] = set()
    for node in _statements(ast.parse(path.read_text(), str(path)), typing, lazy):
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


def _within(module: str, prefixes: tuple[str, ...]) -> bool:
    """``module`` is one of ``prefixes`` or below one of them."""
    return any(module == p or module.startswith(p + ".") for p in prefixes)


def _standard(module: str) -> bool:
    return module.split(".")[0] in sys.stdlib_module_names or module == "__future__"


def _files(module: str) -> list[Path]:
    """The source files of ``module``: a package's every file, or a module's own."""
    target = PACKAGE.parent.joinpath(*module.split("."))
    return sorted(target.rglob("*.py")) if target.is_dir() else [target.with_suffix(".py")]


#: The table, row by row: what each module (with everything below it) may import from focas_net
#: besides itself. Its first row names two modules, which get an entry each.
TABLE: dict[str, tuple[str, ...]] = {
    "focas_net.errors": (),
    "focas_net.versamax": ("focas_net.errors",),
    "focas_net.protocol": ("focas_net.errors", "focas_net.versamax"),
    # "the declarative payload base of focas_net.protocol"
    "focas_net.native": ("focas_net.errors", "focas_net.protocol._base"),
    "focas_net.sim": ("focas_net.errors", "focas_net.versamax"),
    "focas_net.adapters._common": ("focas_net.sim", "focas_net.errors"),
    "focas_net.adapters.packed": (
        "focas_net.sim",
        "focas_net.protocol",
        "focas_net.errors",
        "focas_net.adapters._common",
    ),
    "focas_net.adapters.native": (
        "focas_net.sim",
        "focas_net.native",
        "focas_net.errors",
        "focas_net.adapters._common",
        "focas_net.adapters._native_clock",
        "focas_net.adapters._native_cnc",
        "focas_net.adapters._native_data",
        "focas_net.adapters._native_programs",
        "focas_net.adapters._native_info",
        "focas_net.adapters._native_spindles",
        "focas_net.adapters._native_modal",
        "focas_net.adapters._native_offsets",
        "focas_net.adapters._native_files",
        "focas_net.adapters._native_spindles",
    ),
    "focas_net.server": (
        "focas_net.adapters",
        "focas_net.protocol",
        "focas_net.native",
        "focas_net.sim",
        "focas_net.errors",
    ),
    "focas_net.client": (
        "focas_net.protocol",
        "focas_net.native",
        "focas_net.errors",
        "focas_net.versamax",
    ),
    "focas_net.gateway": ("focas_net.client", "focas_net.protocol", "focas_net.errors"),
    # versamax (the module records the `versamax` command prints) is not in the table's row
    "focas_net.cli": (
        "focas_net.client",
        "focas_net.gateway",
        "focas_net.server",
        "focas_net.sim",
        "focas_net.protocol",
        "focas_net.errors",
        "focas_net.web",
        "focas_net.versamax",
    ),
    "focas_net.web": (
        "focas_net.sim",
        "focas_net.server",
        "focas_net.protocol",
        "focas_net.errors",
    ),
}

#: What the rows say a module never imports (implied by what it may import; said again so that
#: widening a row above cannot let one of these in unnoticed).
NEVER: dict[str, tuple[str, ...]] = {
    "focas_net.sim": ("focas_net.protocol", "focas_net.native"),
    "focas_net.client": ("focas_net.sim", "focas_net.adapters", "focas_net.server"),
    "focas_net.web": ("focas_net.client", "focas_net.adapters"),
}

#: The modules the table does not name, and what they may import from focas_net.
BEYOND_THE_TABLE: dict[str, tuple[str, ...]] = {
    # the package gathers some public names of its subpackages (and says its version)
    "focas_net": (
        "focas_net.client",
        "focas_net.errors",
        "focas_net.protocol",
        "focas_net.server",
        "focas_net.sim",
        "focas_net.versamax",
    ),
    "focas_net.__main__": ("focas_net.cli",),
    # the adapters' package gathers its two adapters
    "focas_net.adapters": ("focas_net.adapters.packed", "focas_net.adapters.native"),
    # the native adapter's handlers, by area (its row: "and its _native_* modules")
    **{
        f"focas_net.adapters._native_{area}": (
            "focas_net.sim",
            "focas_net.native",
            "focas_net.errors",
            "focas_net.adapters._common",
            "focas_net.adapters._native_clock",
            "focas_net.adapters._native_cnc",
            "focas_net.adapters._native_data",
            "focas_net.adapters._native_programs",
            "focas_net.adapters._native_offsets",
        )
        for area in (
            "clock",
            "cnc",
            "data",
            "programs",
            "offsets",
            "files",
            "modal",
            "info",
            "spindles",
        )
    },
    # bounded memos: no protocol, no machine
    "focas_net._memo": (),
    # the read buffer of every connection, the server's and the clients'
    "focas_net._receive": (),
    # a bit parameter's value written as its bits: the machine file, the clients, the page
    "focas_net._bits": (),
    # what a user types: a macro value as the wire carries it and the words for one that does
    # not fit (the machine, the clients and the page), a program number (the command line and
    # the page), an alarm's message (the machine and the text every front end encodes), whether
    # a host is the loopback (the page and the gateway), the words of the system's refusal of a
    # file or address (every layer), a value named as typed (the codecs' words and the page)
    "focas_net._typed": (),
    # TLS as a client: a CA file's context (the command line's --tls-ca, the gateway's
    # mqtt.tls_ca), PEM files told by their content, OpenSSL's words without their tags (the
    # clients' and the server's handshake failures too)
    "focas_net._tls": ("focas_net._typed",),
    # why a CNC refused a parameter or macro write, in words: the command line and the gateway
    # (and parameter 1020's number, the machine's too; a path the CNC has not, the clients' too;
    # an item the CNC has not, the machine's and the page's too)
    "focas_net._refusals": ("focas_net.errors",),
    # an address typed: the host and port checks of the clients, the server's bind address,
    # the command line, the gateway's file and the dashboard's --web; a typed value shown
    # as the user typed it (the machine's refusals)
    "focas_net._address": (),
}

#: Private modules that know no protocol and no machine: every layer may use them.
SHARED: dict[str, tuple[str, ...]] = {
    "focas_net._memo": tuple(TABLE),
    "focas_net._receive": ("focas_net.server", "focas_net.client"),
    "focas_net._bits": ("focas_net.sim", "focas_net.client", "focas_net.web", "focas_net.cli"),
    "focas_net._address": (
        "focas_net.sim",
        "focas_net.server",
        "focas_net.client",
        "focas_net.web",
        "focas_net.cli",
        "focas_net.gateway",
    ),
    "focas_net._tls": (
        "focas_net.server",
        "focas_net.client",
        "focas_net.cli",
        "focas_net.gateway",
    ),
    "focas_net._refusals": (
        "focas_net.sim",
        "focas_net.client",
        "focas_net.web",
        "focas_net.cli",
        "focas_net.gateway",
    ),
    "focas_net._typed": (
        "focas_net.sim",
        "focas_net.server",
        "focas_net.client",
        "focas_net.web",
        "focas_net.cli",
        "focas_net.protocol",
        "focas_net.native",
        "focas_net.gateway",
    ),
}

#: Packages from outside the standard library, and the modules that may import them: the shells
#: only (the codecs, the adapters and the machine need nothing more).
THIRD_PARTY: dict[str, tuple[str, ...]] = {
    "anyio": ("focas_net.server", "focas_net.cli"),
    "aiohttp": ("focas_net.web.shell",),
    # the gateway's OPC UA server and its information model
    "asyncua": (
        "focas_net.gateway.opcua",
        "focas_net.gateway._opcua_model",
        "focas_net.gateway._opcua_types",
        "focas_net.gateway._opcua_conditions",
        "focas_net.gateway._opcua_methods",
        "focas_net.gateway._opcua_sessions",
    ),
    "aiomqtt": ("focas_net.gateway.mqtt",),
}

#: Modules a row may import themselves, nothing below them (not in the table either).
EXACTLY: dict[str, tuple[str, ...]] = {
    # `focas-net --version`: the version the package says (importing focas_net.cli imports the
    # package first anyway)
    "focas_net.cli": ("focas_net",),
}

RULES = {**TABLE, **BEYOND_THE_TABLE}


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


def _rule_of(module: str) -> str:
    """The most specific rule ``module`` falls under."""
    covering = [key for key in RULES if module == key or module.startswith(key + ".")]
    assert covering, f"{module} falls under no rule: add it to the table"
    return max(covering, key=len)


def _offending(path: Path) -> set[str]:
    module = _module_name(path)
    rule = _rule_of(module)
    allowed = (rule, *RULES[rule])
    exactly = EXACTLY.get(rule, ())
    shared = tuple(m for m, users in SHARED.items() if _within(module, users))
    outside = tuple(p for p, users in THIRD_PARTY.items() if _within(module, users))
    offending: set[str] = set()
    for imported in imports_of(path):
        if _standard(imported) or imported in exactly:
            continue
        if _within(imported, allowed + shared + outside):
            continue
        offending.add(imported)
    if rule in NEVER:
        offending |= {m for m in imports_of(path) if _within(m, NEVER[rule])}
    return offending


ALL_FILES = sorted(PACKAGE.rglob("*.py"))


@pytest.mark.parametrize("path", ALL_FILES, ids=lambda p: str(p.relative_to(PACKAGE)))
def test_each_module_imports_what_its_row_allows(path: Path) -> None:
    assert _offending(path) == set()


def _table_rows() -> list[str]:
    """The rows of the table in docs/architecture.md, its header and rule left out."""
    lines = ARCHITECTURE.read_text().split("Who may import whom", 1)[1].splitlines()
    first = next(i for i, line in enumerate(lines) if line.startswith("|"))
    rows: list[str] = []
    for line in lines[first:]:
        if not line.startswith("|"):
            break
        rows.append(line)
    return rows[2:]


def test_every_row_of_the_table_is_checked() -> None:
    """The modules the table names are exactly those of :data:`TABLE`."""
    named = [re.findall(r"`(focas_net[\w.]*)`", row.split("|")[1]) for row in _table_rows()]
    assert all(named)  # every row names its modules
    assert sorted(m for row in named for m in row) == sorted(TABLE)


def test_the_rules_never_allow_what_they_forbid() -> None:
    for module, forbidden in NEVER.items():
        assert not [m for m in TABLE[module] if _within(m, forbidden)]


def test_every_row_covers_some_source() -> None:
    for module in RULES:
        assert all(path.exists() for path in _files(module)), module


def test_the_import_reader_sees_relative_late_and_type_only_imports() -> None:
    found = imports_of(PACKAGE / "sim" / "default.py")
    assert "focas_net.sim.machine" in found and "focas_net.versamax" in found
    assert "focas_net.protocol" in imports_of(PACKAGE / "client" / "client.py")
    cli = PACKAGE / "cli" / "__init__.py"  # imports serve in build_parser
    assert "focas_net.cli.serve" in imports_of(cli)
    assert "focas_net.cli.serve" not in imports_of(cli, lazy=False)
    packed = PACKAGE / "server" / "_packed.py"  # its adapter's class for the type checker
    assert "focas_net.adapters" in imports_of(packed)
    assert "focas_net.adapters" not in imports_of(packed, typing=False)


@pytest.mark.parametrize("path", _files("focas_net.sim.nc"), ids=lambda p: p.name)
def test_the_part_program_package_needs_only_the_standard_library(path: Path) -> None:
    found = imports_of(path)
    assert {m for m in found if not (_standard(m) or _within(m, ("focas_net.sim.nc",)))} == set()


def test_the_dashboard_imports_aiohttp_only_when_it_starts() -> None:
    shell = _files("focas_net.web.shell")[0]
    assert any(_within(m, ("aiohttp",)) for m in imports_of(shell))
    assert not any(_within(m, ("aiohttp",)) for m in imports_of(shell, typing=False, lazy=False))


@pytest.mark.parametrize(
    "module", ["focas_net.protocol", "focas_net.native", "focas_net.adapters", "focas_net.sim"]
)
def test_codecs_adapters_and_the_machine_do_no_io(module: str) -> None:
    """No event loop and no socket below the shells."""
    io = ("asyncio", "socket", "selectors", "ssl", "anyio")
    found = {m for path in _files(module) for m in imports_of(path) if _within(m, io)}
    assert found == set()


def cycles(graph: dict[str, set[str]]) -> list[list[str]]:
    """The cycles of ``graph`` (each node to the nodes it imports): every set of two or more
    nodes that reach each other, sorted (Tarjan's strongly connected components)."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    found: list[list[str]] = []

    def visit(node: str) -> None:
        index[node] = low[node] = len(index)
        stack.append(node)
        for nxt in sorted(graph[node]):
            if nxt not in index:
                visit(nxt)
                low[node] = min(low[node], low[nxt])
            elif nxt in stack:
                low[node] = min(low[node], index[nxt])
        if low[node] == index[node]:
            component = stack[stack.index(node) :]
            del stack[stack.index(node) :]
            if len(component) > 1:
                found.append(sorted(component))

    for node in sorted(graph):
        if node not in index:
            visit(node)
    return sorted(found)


def import_graph(package: str) -> dict[str, set[str]]:
    """The modules of ``package``, each to those of the package it imports when it runs: at its
    top or in a function (a cycle broken only by importing late is still one), not for a type
    checker alone. An import of a package above the module is left out: importing a submodule
    imports its packages first, whoever asks."""
    modules = {_module_name(path): path for path in _files(package)}
    graph: dict[str, set[str]] = {}
    for name, path in modules.items():
        above = {name.rsplit(".", n)[0] for n in range(1, name.count(".") + 1)}
        found = imports_of(path, typing=False)
        graph[name] = {m for m in found if m in modules and m != name} - above
    return graph


def test_the_cycle_finder_finds_every_cycle() -> None:
    graph = {"a": {"b"}, "b": {"a", "c"}, "c": set(), "d": {"e"}, "e": {"f"}, "f": {"d", "a"}}
    assert cycles(graph) == [["a", "b"], ["d", "e", "f"]]
    assert cycles({"a": {"b"}, "b": {"c"}, "c": set()}) == []


def test_the_import_graph_holds_late_imports_not_the_packages_above() -> None:
    cli = import_graph("focas_net.cli")
    assert "focas_net.cli.serve" in cli["focas_net.cli"]  # imported in build_parser
    # `from . import _format` names the package too, which was imported before read_cmds
    assert "focas_net.cli" in imports_of(PACKAGE / "cli" / "read_cmds.py")
    assert "focas_net.cli" not in cli["focas_net.cli.read_cmds"]
    assert "focas_net.cli._format" in cli["focas_net.cli.read_cmds"]


PACKAGES = sorted(_module_name(path) for path in PACKAGE.rglob("__init__.py"))


@pytest.mark.parametrize("package", PACKAGES)
def test_no_import_cycle_inside_a_package(package: str) -> None:
    assert cycles(import_graph(package)) == []


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
