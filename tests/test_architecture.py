"""The import boundaries of ARCHITECTURE.md, checked on the source and in fresh interpreters.

Every rule is a function of a :class:`~architecture.Tree` (the package's source) that returns
the imports breaking it, so the same rules run on the package and on copies of it with one
forbidden import planted in each form a module can import another (the test of the tests, at
the end): relative imports, ``from roboscript import name``, ``from pkg import module``,
``importlib.import_module`` and ``__import__``, attributes of an imported package, and imports
inside functions.
"""

from __future__ import annotations

import ast
import subprocess
import sys
from collections.abc import Callable
from dataclasses import dataclass
from itertools import pairwise

import pytest
from architecture import PACKAGE, ROOT, Import, Tree

STDLIB = sys.stdlib_module_names
IO_MODULES = {"time", "socket", "select", "selectors", "threading", "asyncio", "os", "io", "serial"}
TREE = Tree.read()


def _under(prefix: str) -> Callable[[str], bool]:
    return lambda name: name == prefix or name.startswith(prefix + ".")


def _protocol(module: str) -> str | None:
    """``asip`` for ``roboscript.drivers.asip.codec``; ``None`` outside a protocol folder."""
    parts = module.split(".")
    if len(parts) >= 3 and parts[1] == "drivers" and f"roboscript.drivers.{parts[2]}" in TREE.paths:
        folder = f"roboscript.drivers.{parts[2]}"
        return parts[2] if TREE.is_package(folder) else None
    return None


def _is_codec(tree: Tree, module: str) -> bool:
    """A protocol's sans-IO code: all of its folder but the driver, the device, the built-in
    robots (``profiles.py``, data) and the descriptor."""
    if _protocol(module) is None:
        return False
    leaf = module.split(".")[-1]
    is_package = tree.is_package(module) if module in tree.paths else False
    return (
        not is_package
        and leaf not in {"driver", "device", "profiles"}
        and not leaf.startswith(("agent", "ble"))
    )


# ------------------------------------------------------------------ the rules, one function each


def codecs_import_only_the_standard_library(tree: Tree) -> list[str]:
    """Codecs are sans-IO: the standard library, no clock, no IO, no other roboscript code."""
    allowed_own = {"roboscript.errors", "roboscript.codec", "roboscript.drivers.options"}
    bad = []
    for module in tree.sources:
        if not _is_codec(tree, module):
            continue
        own = f"roboscript.drivers.{_protocol(module)}"
        for imp in tree.imports(module):
            if imp.own:
                if imp.target not in allowed_own and not _under(own)(imp.target):
                    bad.append(
                        f"{imp}: a codec imports only its own protocol and the codec contract"
                    )
            elif imp.target == "?" or imp.top not in STDLIB or imp.top in IO_MODULES:
                bad.append(
                    f"{imp}: codecs import the standard library only, and do no IO or timing"
                )
    return bad


SHARED_STDLIB_MODULES = (
    "roboscript.codec",
    "roboscript.drivers.options",
    "roboscript.drivers.unit",
)
"""The codec contract and the unit descriptor sit below transport and drivers alike."""


def shared_codec_helpers_import_only_the_standard_library(tree: Tree) -> list[str]:
    return [
        f"{imp}: standard library only"
        for module in SHARED_STDLIB_MODULES
        for imp in tree.imports(module)
        if imp.runtime  # a type named for annotations loads nothing
        and not (
            imp.target in ("roboscript.errors", "?")  # "?": a unit's references, imported late
            or (imp.top in STDLIB and imp.top not in IO_MODULES)
        )
    ]


LEAF_MODULES = ("roboscript.code_owner",)
"""Rules that modules importing each other both follow: standard library only, and nothing of
roboscript, so that any module can import them without a cycle."""


def leaf_modules_import_only_the_standard_library(tree: Tree) -> list[str]:
    return [
        f"{imp}: a leaf module imports the standard library only"
        for module in LEAF_MODULES
        for imp in tree.imports(module)
        if imp.runtime and (imp.own or imp.target == "?" or imp.top not in STDLIB)
    ]


THIRD_PARTY_OWNERS = {
    "serial": "roboscript.transport",
    "transitions": "roboscript.mission",
    "yaml": "roboscript.inputs",
    "simple_pid": "roboscript.control",
}
"""Each third-party library has one package that uses it: pyserial the transport, transitions
the mission runner, YAML the input layer (so every file error has one form, file:line:col),
simple-pid the control loops."""


def third_party_libraries_stay_in_their_package(tree: Tree) -> list[str]:
    return [
        f"{imp}: only {THIRD_PARTY_OWNERS[imp.top]} uses {imp.top}"
        for imp in tree.all_imports()
        if imp.top in THIRD_PARTY_OWNERS and not _under(THIRD_PARTY_OWNERS[imp.top])(imp.source)
    ]


def the_input_layer_imports_only_errors(tree: Tree) -> list[str]:
    return [
        f"{imp}: the input layer imports only roboscript.errors"
        for imp in tree.all_imports()
        if _under("roboscript.inputs")(imp.source)
        and imp.own
        and imp.target != "roboscript.errors"
        and not _under("roboscript.inputs")(imp.target)
    ]


@dataclass(frozen=True)
class Forbidden:
    """A pair of packages that must not meet, though the layer order would allow it.

    Attributes:
        source: Which importing modules the rule covers.
        target: ``(source, target) -> True`` for an import the rule forbids.
        why: The reason, as a failure says it.
    """

    source: Callable[[str], bool]
    target: Callable[[str, str], bool]
    why: str


def _device_side(module: str) -> bool:
    return _under("roboscript.sim")(module) or module.endswith(".device")


def _other_protocol(source: str, target: str) -> bool:
    mine, theirs = _protocol(source), _protocol(target)
    return mine is not None and theirs is not None and mine != theirs


def _sim_port(module: str) -> bool:
    return _under("roboscript.sim.urlhandler")(module)


FORBIDDEN: tuple[Forbidden, ...] = (
    Forbidden(
        _under("roboscript.actions"),
        lambda _, t: _under("roboscript.drivers")(t) or _under("roboscript.transport")(t),
        "actions see capabilities, never drivers or transport",
    ),
    Forbidden(
        lambda s: _is_codec(TREE, s) or s in SHARED_STDLIB_MODULES,
        lambda _, t: (
            t
            in {
                "roboscript.clock",
                "roboscript.scheduler",
                "roboscript.watchdog",
                "roboscript.line_alarm",
            }
        ),
        "codecs never read a clock",
    ),
    Forbidden(
        _device_side,
        lambda _, t: t.endswith(".driver"),
        "the simulator never imports a host driver: it is a second implementation of each "
        "protocol's device side",
    ),
    Forbidden(
        lambda s: _device_side(s) and not _sim_port(s),
        lambda _, t: _under("roboscript.transport")(t),
        "the simulator meets transport only in its sim:// port",
    ),
    Forbidden(
        lambda s: _protocol(s) is not None,
        _other_protocol,
        "one protocol's folder never imports another's: each is a unit",
    ),
    Forbidden(
        lambda s: _under("roboscript.sim")(s) or s == "roboscript.profiles",
        lambda _, t: _under("roboscript.mission")(t),
        "worlds, profiles and the simulator never import missions",
    ),
    Forbidden(
        _under("roboscript.transport"),
        lambda _, t: _under("roboscript.drivers")(t) or _under("roboscript.sim")(t),
        "transport never imports drivers or the simulator",
    ),
    Forbidden(
        lambda s: s == "roboscript.grading.mission_host",
        lambda _, t: _under("roboscript.grading")(t) or _under("roboscript.sim")(t),
        "the student's process holds no world and no teacher's code",
    ),
)
"""What ARCHITECTURE.md forbids that the layer order cannot say."""


def forbidden_pairs(tree: Tree) -> list[str]:
    bad = []
    for imp in tree.all_imports():
        if not imp.own:
            continue
        for rule in FORBIDDEN:
            if rule.source(imp.source) and rule.target(imp.source, imp.target):
                bad.append(f"{imp}: {rule.why}")
    return bad


def no_eval_or_exec(tree: Tree) -> list[str]:
    return [
        f"{module}:{node.lineno} calls {node.func.id}"
        for module in tree.sources
        for node in ast.walk(tree.tree(module))
        if isinstance(node, ast.Call)
        and isinstance(node.func, ast.Name)
        and node.func.id in {"eval", "exec"}
    ]


# ------------------------------------------------------------------ the one-way import flow

LAYERS: tuple[tuple[str, ...], ...] = (
    (
        "roboscript",
        "roboscript.errors",
        "roboscript.code_owner",
        "roboscript.angles",
        "roboscript.clock",
        "roboscript.capabilities",
        "roboscript.status",
        "roboscript.codec",
        "roboscript.interrupts",
        "roboscript.line_alarm",
        "roboscript.watchdog",
        "roboscript.robot_profile",
        "roboscript.run_record",
    ),
    ("roboscript.inputs",),
    ("roboscript.scheduler",),
    ("roboscript.control",),
    ("roboscript.transport",),
    ("roboscript.drivers",),
    ("roboscript.profiles",),
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

The root package and the stdlib-only basics at the bottom (the robot profile type and the
run record among them); the inputs (YAML and quantities); the scheduler; host control loops;
transport; drivers (each protocol's folder: codec, host driver, device side and built-in
robots); the profiles found through them (and profile files); the simulator; actions;
missions; the robot;
recording a run (the replay format, its taps and its viewer); one mission run; grading; the
command line (docs/development/architecture.md).

The root package is the one face above them all: ``import roboscript`` loads nothing, and its
attributes (``roboscript.run``, ``roboscript.Drive``) load their modules when first used. So
an import *of* the root resolves to the module the attribute comes from, and the root's own
lazy loads are not edges of the graph."""


def _layer(module: str) -> int:
    for depth in (2, 1):
        name = ".".join(module.split(".")[:depth])
        if depth == 1 and name != module:
            continue  # only the root package itself is in the root's layer
        for index, layer in enumerate(LAYERS):
            if name in layer:
                return index
    raise AssertionError(f"{module} is in no layer: add its package to LAYERS")


def _package(module: str) -> str:
    """``roboscript.<pkg>``: a subpackage, or a top-level module."""
    return ".".join(module.split(".")[:2])


def _graph_edges(tree: Tree) -> list[Import]:
    """Run-time imports between the package's modules (function-level ones included)."""
    return [
        imp
        for imp in tree.all_imports()
        if imp.runtime and imp.own and imp.target not in (ROOT, "?") and imp.source != ROOT
    ]


def every_module_has_a_layer(tree: Tree) -> list[str]:
    bad = []
    for module in tree.sources:
        try:
            _layer(module)
        except AssertionError as exc:
            bad.append(str(exc))
    return bad


def imports_flow_one_way_down_the_layers(tree: Tree) -> list[str]:
    return [
        f"{imp}: {_package(imp.source)} sits below {_package(imp.target)}"
        for imp in _graph_edges(tree)
        if _layer(imp.target) > _layer(imp.source)
    ]


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


def no_import_cycles_between_packages(tree: Tree) -> list[str]:
    edges: dict[tuple[str, str], list[Import]] = {}
    for imp in _graph_edges(tree):
        edge = (_package(imp.source), _package(imp.target))
        if edge[0] != edge[1]:
            edges.setdefault(edge, []).append(imp)
    cycle = _find_cycle(set(edges))
    if cycle is None:
        return []
    detail = [str(imp) for a, b in pairwise(cycle) for imp in edges[(a, b)]]
    return ["import cycle " + " -> ".join(cycle) + "\n  " + "\n  ".join(detail)]


def no_import_cycles_between_modules(tree: Tree) -> list[str]:
    cycle = _find_cycle({(imp.source, imp.target) for imp in _graph_edges(tree)})
    return [] if cycle is None else ["import cycle " + " -> ".join(cycle)]


# ------------------------------------------------------------------ what is imported late

DYNAMIC_IMPORTS = {
    "roboscript": "its attributes load their modules when first used",
    "roboscript.drivers": "each protocol folder is found and imported by name",
    "roboscript.drivers.unit": "a unit names its code by 'module:attribute', imported when asked",
    "roboscript.grading.jail_server": "the jail's fork server warms the module it is given",
    "roboscript.grading.worker": "the fork server imports each protocol's simulated device",
    "roboscript.transport.ble": "bleak, an optional dependency, is imported only for BLE",
    "roboscript.web.build": "the browser app's build packs the packages it lists, by name",
}
"""The modules that import a module by a name computed at run time, and why. Anywhere else a
dynamic import names its module as a constant, so the graph sees it."""


def dynamic_imports_are_resolved(tree: Tree) -> list[str]:
    return [
        f"{imp}: name the module as a constant, or add the module to DYNAMIC_IMPORTS with why"
        for imp in tree.all_imports()
        if imp.target == "?" and imp.source not in DYNAMIC_IMPORTS
    ]


FUNCTION_LEVEL_IMPORTS: dict[str, int] = {
    "roboscript.api": 3,
    "roboscript.__main__": 1,
    "roboscript.cli": 50,
    "roboscript.grading.autograder": 1,
    "roboscript.grading.mission_host": 13,
    "roboscript.grading.pool": 1,
    "roboscript.mission": 7,
    "roboscript.mission.checks": 1,
    "roboscript.mission.nested": 1,
    "roboscript.mission.python_api": 2,
    "roboscript.mission.references": 1,
    "roboscript.mission.roboscript_kept": 1,
    "roboscript.profiles": 3,
    "roboscript.replay.header": 1,
    "roboscript.replay.viewer": 1,
    "roboscript.transport.ports": 1,
}
"""How many of the package's own modules each module imports inside a function. Each buys
start-up time (the command line answers ``--help`` without loading the simulator) or keeps an
optional part optional, and says so in a comment on the line above or at its end; a new one
fails this count until it is written here, with its reason beside it in the code."""


def _has_reason(tree: Tree, imp: Import) -> bool:
    """A comment at the end of the import's line, or above it (or above its group)."""
    lines = tree.sources[imp.source].splitlines()
    if "#" in lines[imp.line - 1]:
        return True
    above = imp.line - 2
    while above >= 0 and lines[above].strip().startswith(("from ", "import ")):
        above -= 1  # one comment serves a group of imports
    return above >= 0 and lines[above].strip().startswith("#")


def function_level_imports_are_counted_and_explained(tree: Tree) -> list[str]:
    bad = []
    counted: dict[str, int] = {}
    seen: set[tuple[str, int]] = set()
    for imp in tree.all_imports():
        if not (imp.in_function and imp.own and imp.runtime and imp.form != "attribute"):
            continue
        if imp.source == ROOT or (imp.source, imp.line) in seen:
            continue  # the root's lazy attributes; one statement counts once
        seen.add((imp.source, imp.line))
        counted[imp.source] = counted.get(imp.source, 0) + 1
        if not _has_reason(tree, imp):
            bad.append(f"{imp}: say in a comment why it is imported here and not at the top")
    for module in sorted(set(counted) | set(FUNCTION_LEVEL_IMPORTS)):
        have, listed = counted.get(module, 0), FUNCTION_LEVEL_IMPORTS.get(module, 0)
        if have != listed:
            bad.append(f"{module} imports {have} of its own modules in functions; listed: {listed}")
    return bad


DECLARED = {"serial", "simple_pid", "transitions", "yaml"}
OPTIONAL = {"bleak", "matplotlib"}  # extras: imported inside the functions that need them
BROWSER = {"js", "pyodide"}
"""Pyodide's own modules, which exist only in a browser tab: imported inside the functions of
the web ports (``roboscript.transport.webport``) and nowhere else."""


def only_declared_dependencies_are_imported_at_run_time(tree: Tree) -> list[str]:
    # `pip install roboscript` without extras must import: typing_extensions, for one, is not
    # a dependency (an annotation-only import belongs under `if TYPE_CHECKING:`)
    return [
        f"{imp}: {imp.top} is not a dependency"
        for imp in tree.all_imports()
        if imp.runtime
        and not imp.own
        and imp.target != "?"
        and imp.top not in STDLIB | DECLARED | (OPTIONAL if imp.in_function else set())
        and not (
            imp.top in BROWSER and imp.in_function and imp.source == "roboscript.transport.webport"
        )
    ]


RULES: tuple[Callable[[Tree], list[str]], ...] = (
    codecs_import_only_the_standard_library,
    shared_codec_helpers_import_only_the_standard_library,
    leaf_modules_import_only_the_standard_library,
    third_party_libraries_stay_in_their_package,
    the_input_layer_imports_only_errors,
    forbidden_pairs,
    no_eval_or_exec,
    every_module_has_a_layer,
    imports_flow_one_way_down_the_layers,
    no_import_cycles_between_packages,
    no_import_cycles_between_modules,
    dynamic_imports_are_resolved,
    function_level_imports_are_counted_and_explained,
    only_declared_dependencies_are_imported_at_run_time,
)


@pytest.mark.parametrize("rule", RULES, ids=lambda rule: rule.__name__)
def test_the_package_keeps_the_rule(rule: Callable[[Tree], list[str]]) -> None:
    assert rule(TREE) == []


# ------------------------------------------------------------------ in fresh interpreters


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


def test_the_package_imports_without_typing_extensions() -> None:
    code = (
        "import sys\n"
        "sys.modules['typing_extensions'] = None\n"
        "import roboscript.cli, roboscript.robot, roboscript.session, roboscript.grading.batch\n"
    )
    subprocess.run([sys.executable, "-c", code], check=True, cwd=PACKAGE.parent)


# ------------------------------------------------------------------ the test of the tests

PLANTED = [
    # (form, module planted in, code, rule that must catch it)
    ("relative", "roboscript.actions.motion", "from ..drivers import base", forbidden_pairs),
    ("relative", "roboscript.actions.motion", "from ..transport.link import Link", forbidden_pairs),
    (
        "relative",
        "roboscript.mission.spec",
        "from .. import session",
        imports_flow_one_way_down_the_layers,
    ),
    (
        "package name",
        "roboscript.mission.spec",
        "from roboscript import run",
        imports_flow_one_way_down_the_layers,
    ),
    (
        "package name",
        "roboscript.mission.spec",
        "from roboscript import api",
        imports_flow_one_way_down_the_layers,
    ),
    (
        "from pkg import module",
        "roboscript.actions.timing",
        "from roboscript.drivers import base",
        forbidden_pairs,
    ),
    (
        "from pkg import module",
        "roboscript.transport.link",
        "from roboscript.sim import body",
        forbidden_pairs,
    ),
    ("import", "roboscript.actions.timing", "import roboscript.transport.link", forbidden_pairs),
    (
        "importlib",
        "roboscript.mission.spec",
        "import importlib\nimportlib.import_module('roboscript.api')",
        imports_flow_one_way_down_the_layers,
    ),
    (
        "importlib",
        "roboscript.actions.timing",
        "from importlib import import_module\nimport_module('roboscript.drivers.base')",
        forbidden_pairs,
    ),
    (
        "__import__",
        "roboscript.actions.timing",
        "__import__('roboscript.transport.link')",
        forbidden_pairs,
    ),
    (
        "importlib, computed name",
        "roboscript.mission.spec",
        "import importlib\nNAME = 'roboscript.' + 'api'\nimportlib.import_module(NAME)",
        dynamic_imports_are_resolved,
    ),
    (
        "attribute",
        "roboscript.mission.spec",
        "import roboscript\n\ndef go():  # planted\n    return roboscript.api.main",
        imports_flow_one_way_down_the_layers,
    ),
    (
        "lazy attribute",
        "roboscript.mission.spec",
        "import roboscript as rs\nrun = rs.run",
        imports_flow_one_way_down_the_layers,
    ),
    (
        "in a function",
        "roboscript.mission.spec",
        (
            "def go():\n"
            "    from roboscript.session import run_session  # planted\n"
            "    return run_session"
        ),
        imports_flow_one_way_down_the_layers,
    ),
    (
        "in a function, unexplained",
        "roboscript.mission.spec",
        "def go():\n    from roboscript.errors import MissionError\n    return MissionError",
        function_level_imports_are_counted_and_explained,
    ),
    (
        "codec clock",
        "roboscript.drivers.asip.framing",
        "from roboscript.clock import SimClock",
        codecs_import_only_the_standard_library,
    ),
    (
        "codec clock",
        "roboscript.drivers.plen.codec",
        "from roboscript import clock",
        forbidden_pairs,
    ),
    (
        "codec time",
        "roboscript.drivers.spike.cobs",
        "import time",
        codecs_import_only_the_standard_library,
    ),
    (
        "another protocol",
        "roboscript.drivers.asip.driver",
        "from roboscript.drivers.spike import messages",
        forbidden_pairs,
    ),
    (
        "host driver in the simulator",
        "roboscript.drivers.plen.device",
        "from . import driver",
        forbidden_pairs,
    ),
    (
        "student's process",
        "roboscript.grading.mission_host",
        "from roboscript.grading import spec",
        forbidden_pairs,
    ),
    (
        "pyserial",
        "roboscript.mission.runner",
        "import serial.tools",
        third_party_libraries_stay_in_their_package,
    ),
    (
        "yaml",
        "roboscript.mission.spec",
        "def go():\n    import yaml  # planted\n    return yaml",
        third_party_libraries_stay_in_their_package,
    ),
    (
        "cycle",
        "roboscript.errors",
        "from roboscript import codec",
        no_import_cycles_between_modules,
    ),
    ("new package", "roboscript.gadgets", "X = 1", every_module_has_a_layer),
    (
        "leaf",
        "roboscript.code_owner",
        "from roboscript.errors import MissionError",
        leaf_modules_import_only_the_standard_library,
    ),
    ("eval", "roboscript.mission.guards", "eval('1')", no_eval_or_exec),
    (
        "undeclared",
        "roboscript.mission.spec",
        "import typing_extensions",
        only_declared_dependencies_are_imported_at_run_time,
    ),
]


@pytest.mark.parametrize(
    ("form", "module", "code", "rule"),
    PLANTED,
    ids=[f"{form}: {code.splitlines()[-1].strip()}" for form, _, code, _ in PLANTED],
)
def test_a_planted_forbidden_import_fails_its_rule(
    form: str, module: str, code: str, rule: Callable[[Tree], list[str]]
) -> None:
    assert rule(TREE) == []
    found = rule(TREE.planted(module, code))
    assert found, f"{form}: {code!r} in {module} passed {rule.__name__}"
    assert any(module in problem for problem in found), found


def test_an_import_for_annotations_only_is_not_an_edge() -> None:
    # under `if TYPE_CHECKING:` nothing is imported when the program runs
    planted = TREE.planted(
        "roboscript.mission.spec",
        "from typing import TYPE_CHECKING\n"
        "if TYPE_CHECKING:\n"
        "    from roboscript.api import RunResult",
    )
    assert imports_flow_one_way_down_the_layers(planted) == []
    assert no_import_cycles_between_modules(planted) == []


def test_the_root_package_resolves_to_the_module_of_its_attribute() -> None:
    module = "roboscript.actions.timing"
    planted = TREE.planted(module, "from roboscript import Mission, Drive")
    line = len(TREE.sources[module].splitlines()) + 2
    targets = {imp.target for imp in planted.imports(module) if imp.line == line}
    assert targets == {"roboscript.mission.python_api", "roboscript.actions"}
