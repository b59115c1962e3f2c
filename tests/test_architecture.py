"""The import boundaries of ARCHITECTURE.md, checked on the source and in fresh interpreters."""

from __future__ import annotations

import ast
import subprocess
import sys
from itertools import pairwise
from pathlib import Path

import pytest

PACKAGE = Path(__file__).resolve().parent.parent / "roboscript"
STDLIB = sys.stdlib_module_names
IO_MODULES = {"time", "socket", "select", "selectors", "threading", "asyncio", "os", "io", "serial"}


def _imports(path: Path) -> set[str]:
    tree = ast.parse(path.read_text(encoding="utf-8"))
    found: set[str] = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            found.update(alias.name for alias in node.names)
        elif isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
            found.add(node.module)
    return found


def _modules(folder: str) -> list[Path]:
    return sorted((PACKAGE / folder).rglob("*.py"))


SHARED_STDLIB_FILES = [
    PACKAGE / "codec.py",  # the codec contract, below transport and drivers alike
    PACKAGE / "drivers" / "options.py",
    PACKAGE / "drivers" / "unit.py",
]

CODEC_FILES = [
    p
    for p in _modules("drivers")
    if p.parent != PACKAGE / "drivers"
    and p.name not in {"driver.py", "device.py", "__init__.py"}
    and not p.name.startswith(("agent", "ble"))
    and p.parent.name != "agent"  # MicroPython run on the robot (the SPIKE hub agent)
]


@pytest.mark.parametrize("path", CODEC_FILES, ids=lambda p: str(p.relative_to(PACKAGE)))
def test_codecs_import_only_the_standard_library(path: Path) -> None:
    allowed_own = {"roboscript.errors", "roboscript.codec", "roboscript.drivers.options"}
    for name in _imports(path):
        top = name.split(".")[0]
        if top == "roboscript":
            own = f"roboscript.drivers.{path.parent.name}"
            own_protocol = name == own or name.startswith(own + ".")
            assert name in allowed_own or own_protocol, f"{path.name} imports {name}"
        else:
            assert top in STDLIB, f"{path.name} imports {name}"
            assert top not in IO_MODULES, f"{path.name} imports {name}: codecs do no IO or timing"


@pytest.mark.parametrize("path", SHARED_STDLIB_FILES, ids=lambda p: p.name)
def test_shared_codec_helpers_import_only_the_standard_library(path: Path) -> None:
    for name in _imports(path):
        top = name.split(".")[0]
        assert name == "roboscript.errors" or (top in STDLIB and top not in IO_MODULES), name


def _importers_of(prefix: str) -> set[str]:
    users = set()
    for path in PACKAGE.rglob("*.py"):
        if any(name == prefix or name.startswith(prefix + ".") for name in _imports(path)):
            users.add(str(path.relative_to(PACKAGE)))
    return users


def test_only_transport_imports_pyserial() -> None:
    assert {u for u in _importers_of("serial") if not u.startswith("transport/")} == set()


def test_only_mission_imports_transitions() -> None:
    assert {u for u in _importers_of("transitions") if not u.startswith("mission/")} == set()


def test_only_the_input_layer_reads_yaml() -> None:
    # missions, worlds, profiles and test specs are all read by roboscript.inputs, so every
    # file error has one form (file:line:col) and one did-you-mean
    assert {u for u in _importers_of("yaml") if not u.startswith("inputs/")} == set()


def test_the_input_layer_imports_only_errors_from_roboscript() -> None:
    for path in _modules("inputs"):
        own = {n for n in _imports(path) if n.split(".")[0] == "roboscript"}
        assert own <= {"roboscript.errors"} | {
            n for n in own if n.startswith("roboscript.inputs")
        }, path


def test_worlds_profiles_and_the_simulator_never_import_missions() -> None:
    for path in [*_modules("sim"), PACKAGE / "profiles.py"]:
        for name in _imports(path):
            assert not name.startswith("roboscript.mission"), f"{path} imports {name}"


def test_transport_never_imports_drivers_or_the_simulator() -> None:
    for path in _modules("transport"):
        for name in _imports(path):
            assert not name.startswith(("roboscript.drivers", "roboscript.sim")), (
                f"{path} imports {name}"
            )


def test_only_control_imports_simple_pid() -> None:
    assert {u for u in _importers_of("simple_pid") if not u.startswith("control/")} == set()


def test_actions_never_import_drivers_or_transport() -> None:
    for path in _modules("actions"):
        for name in _imports(path):
            assert not name.startswith(("roboscript.drivers", "roboscript.transport")), path


def test_simulator_never_imports_host_drivers() -> None:
    device_files = [p for p in _modules("drivers") if p.name == "device.py"]
    for path in _modules("sim") + device_files:
        # the sim:// port is the one place the simulator meets transport: it is a port
        is_port = path.parent == PACKAGE / "sim" / "urlhandler"
        for name in _imports(path):
            assert not name.endswith(".driver"), f"{path} imports {name}"
            if is_port:
                assert name != "serial" and not name.startswith("serial."), path
            else:
                assert not name.startswith("roboscript.transport"), f"{path} imports {name}"


def test_no_eval_or_exec_in_the_package() -> None:
    for path in PACKAGE.rglob("*.py"):
        tree = ast.parse(path.read_text(encoding="utf-8"))
        for node in ast.walk(tree):
            if isinstance(node, ast.Call) and isinstance(node.func, ast.Name):
                assert node.func.id not in {"eval", "exec"}, f"{path} calls {node.func.id}"


@pytest.mark.parametrize(
    "module",
    [
        "roboscript.drivers.asip.codec",
        "roboscript.drivers.spike.codec",
        "roboscript.drivers.stackmod.codec",
        "roboscript.drivers.plen.codec",
    ],
)
def test_codecs_load_with_third_party_libraries_absent(module: str) -> None:
    # Blocked libraries would raise ImportError; nothing outside the stdlib may load either.
    code = (
        "import sys\n"
        "sys.modules.update(serial=None, transitions=None, yaml=None, simple_pid=None)\n"
        f"import {module}\n"
        "loaded = {n.split('.')[0] for n, m in sys.modules.items() if m is not None}\n"
        "third = loaded - set(sys.stdlib_module_names) - {'__main__', '_distutils_hack'}\n"
        # an editable install (pip install -e) adds its own import hook module
        "third = {n for n in third if not n.startswith('__editable__')}\n"
        "assert third == {'roboscript'}, third\n"
    )
    subprocess.run([sys.executable, "-c", code], check=True, cwd=PACKAGE.parent)


# ------------------------------------------------------------------ the one-way import flow

MODULES = {
    ".".join(p.relative_to(PACKAGE.parent).with_suffix("").parts).removesuffix(".__init__"): p
    for p in PACKAGE.rglob("*.py")
    if "agent" not in p.relative_to(PACKAGE).parts  # MicroPython for the SPIKE hub
}


def _is_type_checking(test: ast.expr) -> bool:
    return (isinstance(test, ast.Name) and test.id == "TYPE_CHECKING") or (
        isinstance(test, ast.Attribute) and test.attr == "TYPE_CHECKING"
    )


def _runtime_imports(module: str) -> set[str]:
    """The roboscript modules ``module`` imports when it runs: top-level and function-local
    imports alike, but not those under ``if TYPE_CHECKING:`` (annotations only)."""
    path = MODULES[module]
    package = module if path.name == "__init__.py" else module.rpartition(".")[0]
    found: set[str] = set()

    def visit(node: ast.AST) -> None:
        for child in ast.iter_child_nodes(node):
            if isinstance(child, ast.If) and _is_type_checking(child.test):
                for other in child.orelse:
                    visit(other)
                continue
            if isinstance(child, ast.Import):
                found.update(alias.name for alias in child.names)
            elif isinstance(child, ast.ImportFrom):
                base = child.module or ""
                if child.level:
                    parent = package.split(".")[: len(package.split(".")) - child.level + 1]
                    base = ".".join([*parent, *([child.module] if child.module else [])])
                for alias in child.names:
                    # `from roboscript import capabilities` imports the module capabilities;
                    # `from roboscript.x import name` imports roboscript.x
                    sub = f"{base}.{alias.name}"
                    found.add(sub if sub in MODULES else base)
            visit(child)

    visit(ast.parse(path.read_text(encoding="utf-8")))
    resolved = set()
    for name in found:
        while name and name not in MODULES:
            name = name.rpartition(".")[0]
        if name and name != module:
            resolved.add(name)
    return resolved


IMPORTS = {module: _runtime_imports(module) for module in MODULES}


def _package(module: str) -> str:
    """``roboscript.<pkg>``: a subpackage, or a top-level module."""
    return ".".join(module.split(".")[:2])


def _package_edges() -> dict[tuple[str, str], list[str]]:
    """Package-level import edges, each with the module imports that make it."""
    edges: dict[tuple[str, str], list[str]] = {}
    for module, targets in IMPORTS.items():
        for target in targets:
            if target == "roboscript":
                continue  # the root package imports nothing at run time (lazy attributes)
            edge = (_package(module), _package(target))
            if edge[0] != edge[1]:
                edges.setdefault(edge, []).append(f"{module} -> {target}")
    return edges


KNOWN_PACKAGE_CYCLE_EDGES: dict[tuple[str, str], str] = {}
"""Edges that close an import cycle today, each with the change that removes it (none: keep it
so). The test fails when one of them no longer exists, so the list only shrinks."""


def _find_cycle(edges: set[tuple[str, str]]) -> list[str] | None:
    graph: dict[str, set[str]] = {}
    for a, b in edges:
        graph.setdefault(a, set()).add(b)
    colour: dict[str, int] = {}
    stack: list[str] = []

    def dfs(node: str) -> list[str] | None:
        colour[node] = 1
        stack.append(node)
        for nxt in sorted(graph.get(node, ())):
            if colour.get(nxt) == 1:
                return [*stack[stack.index(nxt) :], nxt]
            if nxt not in colour and (cycle := dfs(nxt)) is not None:
                return cycle
        stack.pop()
        colour[node] = 2
        return None

    for start in sorted(graph):
        if start not in colour and (cycle := dfs(start)) is not None:
            return cycle
    return None


def test_no_import_cycles_between_packages() -> None:
    edges = _package_edges()
    stale = [edge for edge in KNOWN_PACKAGE_CYCLE_EDGES if edge not in edges]
    assert not stale, f"fixed, remove from KNOWN_PACKAGE_CYCLE_EDGES: {stale}"
    remaining = set(edges) - set(KNOWN_PACKAGE_CYCLE_EDGES)
    cycle = _find_cycle(remaining)
    if cycle is not None:
        detail = [m for a, b in pairwise(cycle) for m in edges[(a, b)]]
        pytest.fail("import cycle " + " -> ".join(cycle) + "\n  " + "\n  ".join(detail))


def test_no_import_cycles_between_modules() -> None:
    edges = {(module, target) for module, targets in IMPORTS.items() for target in targets}
    cycle = _find_cycle(edges - _KNOWN_MODULE_CYCLE_EDGES)
    assert cycle is None, "import cycle " + " -> ".join(cycle or [])


_KNOWN_MODULE_CYCLE_EDGES: set[tuple[str, str]] = set()
"""Module-level edges that close a cycle today (none: keep it so)."""


LAYERS: tuple[tuple[str, ...], ...] = (
    (
        "roboscript",
        "roboscript.errors",
        "roboscript.angles",
        "roboscript.clock",
        "roboscript.capabilities",
        "roboscript.status",
        "roboscript.codec",
        "roboscript.interrupts",
        "roboscript.watchdog",
    ),
    ("roboscript.inputs",),
    ("roboscript.profiles", "roboscript.scheduler"),
    ("roboscript.control",),
    ("roboscript.transport",),
    ("roboscript.drivers",),
    ("roboscript.sim",),
    ("roboscript.actions",),
    ("roboscript.mission",),
    ("roboscript.robot",),
    ("roboscript.replay",),
    ("roboscript.session",),
    ("roboscript.grading",),
    # the browser app's bridge calls what the command line calls (check, run, graph)
    ("roboscript.cli", "roboscript.__main__", "roboscript.api", "roboscript.web"),
)
"""The one-way flow, lowest first: a module imports only from its own layer or below.

The root package and the stdlib-only basics at the bottom (the root package's attributes load
lazily); the inputs (YAML and quantities) and robot profiles; host control loops; transport;
drivers (and the device side of each protocol); the simulator; actions; missions; the robot;
recording a run (the replay format, its taps and its viewer); one mission run; grading; the
command line (docs/development/architecture.md)."""

KNOWN_LAYER_VIOLATIONS = set(KNOWN_PACKAGE_CYCLE_EDGES)
"""Upward imports that exist today: those of :data:`KNOWN_PACKAGE_CYCLE_EDGES`."""


def _layer(module: str) -> int:
    for depth in (2, 1):
        name = ".".join(module.split(".")[:depth])
        for index, layer in enumerate(LAYERS):
            if name in layer:
                return index
    raise AssertionError(f"{module} is in no layer: add its package to LAYERS")


def test_every_package_has_a_layer() -> None:
    for module in MODULES:
        _layer(module)


def test_imports_flow_one_way_down_the_layers() -> None:
    upward = []
    for module, targets in sorted(IMPORTS.items()):
        for target in sorted(targets):
            edge = (_package(module), _package(target))
            if _layer(target) > _layer(module) and edge not in KNOWN_LAYER_VIOLATIONS:
                upward.append(f"{module} -> {target}")
    assert upward == []


def test_function_local_imports_do_not_hide_cycles() -> None:
    # a deferred import is fine for start-up time or an optional library, but one between
    # roboscript modules must also be legal at the top of the file
    for module, path in MODULES.items():
        tree = ast.parse(path.read_text(encoding="utf-8"))
        for function in ast.walk(tree):
            if not isinstance(function, ast.FunctionDef | ast.AsyncFunctionDef):
                continue
            for node in ast.walk(function):
                if isinstance(node, ast.ImportFrom) and (node.module or "").startswith(
                    "roboscript"
                ):
                    target = node.module or ""
                    while target not in MODULES:
                        target = target.rpartition(".")[0]
                    edge = (_package(module), _package(target))
                    assert _layer(target) <= _layer(module) or edge in KNOWN_LAYER_VIOLATIONS, (
                        f"{module}:{node.lineno} imports {target} inside a function"
                    )


DECLARED = {"serial", "simple_pid", "transitions", "yaml"}
OPTIONAL = {"bleak", "matplotlib"}  # extras: imported inside the functions that need them


def _outside_imports(path: Path) -> list[tuple[str, bool]]:
    """(top-level name, imported at module level) of each import not from roboscript,
    leaving out ``if TYPE_CHECKING:`` blocks."""
    found: list[tuple[str, bool]] = []

    def visit(node: ast.AST, top: bool) -> None:
        for child in ast.iter_child_nodes(node):
            if isinstance(child, ast.If) and _is_type_checking(child.test):
                for other in child.orelse:
                    visit(other, top)
                continue
            if isinstance(child, ast.Import):
                found.extend((alias.name.split(".")[0], top) for alias in child.names)
            elif isinstance(child, ast.ImportFrom) and child.level == 0 and child.module:
                found.append((child.module.split(".")[0], top))
            inner = isinstance(child, ast.FunctionDef | ast.AsyncFunctionDef | ast.Lambda)
            visit(child, top and not inner)

    visit(ast.parse(path.read_text(encoding="utf-8")), True)
    return [(name, top) for name, top in found if name != "roboscript"]


def test_only_declared_dependencies_are_imported_at_run_time() -> None:
    # `pip install roboscript` without extras must import: typing_extensions, for one, is not
    # a dependency (an annotation-only import belongs under `if TYPE_CHECKING:`)
    for module, path in MODULES.items():
        for name, top in _outside_imports(path):
            allowed = STDLIB | DECLARED | (set() if top else OPTIONAL)
            assert name in allowed, f"{module} imports {name}, which is not a dependency"


def test_the_package_imports_without_typing_extensions() -> None:
    code = (
        "import sys\n"
        "sys.modules['typing_extensions'] = None\n"
        "import roboscript.cli, roboscript.robot, roboscript.session, roboscript.grading.batch\n"
    )
    subprocess.run([sys.executable, "-c", code], check=True, cwd=PACKAGE.parent)
