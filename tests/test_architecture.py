"""The import boundaries of ARCHITECTURE.md, checked on the source and in fresh interpreters."""

from __future__ import annotations

import ast
import subprocess
import sys
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


SHARED_STDLIB_FILES = [PACKAGE / "drivers" / "codec.py", PACKAGE / "drivers" / "options.py"]

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
    allowed_own = {"roboscript.errors", "roboscript.drivers.codec", "roboscript.drivers.options"}
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


def test_only_mission_imports_transitions_and_yaml() -> None:
    for library in ("transitions", "yaml"):
        assert {u for u in _importers_of(library) if not u.startswith("mission/")} == set()


def test_only_control_imports_simple_pid() -> None:
    assert {u for u in _importers_of("simple_pid") if not u.startswith("control/")} == set()


def test_actions_never_import_drivers_or_transport() -> None:
    for path in _modules("actions"):
        for name in _imports(path):
            assert not name.startswith(("roboscript.drivers", "roboscript.transport")), path


def test_simulator_never_imports_host_drivers() -> None:
    device_files = [p for p in _modules("drivers") if p.name == "device.py"]
    for path in _modules("sim") + device_files:
        for name in _imports(path):
            assert not name.endswith(".driver"), f"{path} imports {name}"
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
