"""What must reach an installed wheel does: worlds and typing marker as package data, and the
example missions a user with only the wheel asks for."""

from __future__ import annotations

import ast
import os
import subprocess
import sys
import zipfile
from pathlib import Path

import pytest
from helpers import HANG_BOUND_S, MISSIONS, ROOT

from roboscript.sim.world import builtin_worlds


def test_builtin_worlds_are_found_through_the_package() -> None:
    assert {"empty", "square-room", "corridor"} <= set(builtin_worlds())


@pytest.fixture(scope="module")
def wheel(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """The wheel ``pip wheel .`` builds from the roboscript folder."""
    folder = tmp_path_factory.mktemp("wheel")
    subprocess.run(
        [sys.executable, "-m", "pip", "wheel", "--no-deps", "-w", str(folder), str(ROOT)],
        check=True,
        capture_output=True,
        timeout=HANG_BOUND_S,
    )
    return next(folder.glob("roboscript-*.whl"))


def test_wheel_contains_the_package_data_and_nothing_from_the_top_level(wheel: Path) -> None:
    names = set(zipfile.ZipFile(wheel).namelist())
    assert "roboscript/py.typed" in names
    for world in builtin_worlds():
        assert f"roboscript/sim/worlds/{world}.yaml" in names
    assert not any(n.startswith(("missions/", "drivers/", "tests/", "docs/")) for n in names)
    data_files = {
        str(path.relative_to(ROOT))
        for path in (ROOT / "roboscript").rglob("*")
        if path.is_file()
        and (
            path.suffix in {".yaml", ".json", ".js", ".mjs", ".css", ".html"}
            or "agent" in path.parts
        )
        and "__pycache__" not in path.parts
    }
    assert data_files <= names, data_files - names


def test_wheel_carries_every_example_mission_as_it_is(wheel: Path) -> None:
    examples = {
        path.relative_to(MISSIONS).as_posix(): path.read_bytes()
        for path in MISSIONS.rglob("*")
        if path.is_file() and "__pycache__" not in path.parts
    }
    with zipfile.ZipFile(wheel) as archive:
        carried = {
            name.removeprefix("roboscript/examples/"): archive.read(name)
            for name in archive.namelist()
            if name.startswith("roboscript/examples/")
        }
    assert carried == examples


def test_a_user_with_only_the_wheel_gets_the_examples_and_runs_the_quick_start(
    wheel: Path, tmp_path: Path
) -> None:
    # installed from the wheel, in a folder of the user's own, far from the roboscript folder
    site = tmp_path / "site"
    install = ["install", "--no-deps", "--no-index", "--target", str(site), str(wheel)]
    subprocess.run(
        [sys.executable, "-m", "pip", *install],
        check=True,
        capture_output=True,
        timeout=HANG_BOUND_S,
    )
    home = tmp_path / "my robots"
    home.mkdir()
    env = {**os.environ, "PYTHONPATH": str(site)}

    def roboscript(*args: str) -> subprocess.CompletedProcess[str]:
        return subprocess.run(
            [sys.executable, "-m", "roboscript", *args],
            cwd=home,
            env=env,
            capture_output=True,
            text=True,
            timeout=HANG_BOUND_S,
            check=False,
        )

    where = subprocess.run(
        [sys.executable, "-c", "import roboscript; print(roboscript.__file__)"],
        cwd=home,
        env=env,
        capture_output=True,
        text=True,
        check=True,
    )
    assert Path(where.stdout.strip()).is_relative_to(site)  # not the roboscript folder's
    before = roboscript("run", "missions/square.yaml")
    assert before.returncode == 2
    assert "`roboscript examples` writes the example missions here" in before.stderr
    done = roboscript("examples")
    assert done.returncode == 0, done.stderr
    done = roboscript("run", "missions/square.yaml")
    assert (done.returncode, done.stderr.splitlines()[-1]) == (
        0,
        "success: square ended in 'finished' after 23.66 s",
    )


# What the standard library gained after Python 3.10, the oldest Python pyproject.toml claims:
# imported at run time, each stops roboscript on 3.10 (annotations may name them under
# TYPE_CHECKING, from typing_extensions).
NEWER_THAN_3_10 = {
    "typing": {
        "Self", "LiteralString", "Never", "assert_never", "assert_type", "reveal_type",
        "Required", "NotRequired", "TypeVarTuple", "Unpack", "dataclass_transform",
        "get_overloads", "clear_overloads", "override", "TypeAliasType", "ReadOnly", "TypeIs",
    },
    "enum": {"StrEnum", "ReprEnum", "verify", "member", "nonmember", "global_enum"},
    "datetime": {"UTC"},
    "tomllib": {"*"},
    "wsgiref.types": {"*"},
    "contextlib": {"chdir"},
    "hashlib": {"file_digest"},
    "itertools": {"batched"},
    "operator": {"call"},
    "math": {"cbrt", "exp2"},
    "asyncio": {"TaskGroup", "timeout", "timeout_at", "Runner"},
    "inspect": {"getmembers_static", "markcoroutinefunction"},
    "logging": {"getLevelNamesMapping"},
    "sys": {"exception"},
    "re": {"NOFLAG"},
    "builtins": {"ExceptionGroup", "BaseExceptionGroup"},
}  # fmt: skip
NEWER_METHODS = {"add_note"}  # BaseException.add_note (3.11)
"""Methods Python gained after 3.10, called on objects of any name."""


def _imported_at_run_time(tree: ast.Module) -> list[tuple[int, str, str]]:
    """``(line, module, name)`` of each import that runs when the module loads (not those
    under ``if TYPE_CHECKING:``)."""
    found = []
    for node in ast.walk(tree):
        if isinstance(node, ast.If) and ast.unparse(node.test).endswith("TYPE_CHECKING"):
            node.body = []  # what it guards is for the type checker only
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom) and node.module:
            found += [(node.lineno, node.module, alias.name) for alias in node.names]
        elif isinstance(node, ast.Import):
            found += [(node.lineno, alias.name, "*") for alias in node.names]
    return found


def _used_at_run_time(tree: ast.Module) -> list[tuple[int, str, str]]:
    """``(line, module, name)`` of each ``module.name`` read (``contextlib.chdir``), each
    built-in name read (``ExceptionGroup``, as ``builtins``) and each method called by a name
    in NEWER_METHODS (as ``*``), outside ``if TYPE_CHECKING:``."""
    found = []
    for node in ast.walk(tree):
        if isinstance(node, ast.Attribute) and isinstance(node.value, ast.Name):
            found.append((node.lineno, node.value.id, node.attr))
        if isinstance(node, ast.Attribute) and node.attr in NEWER_METHODS:
            found.append((node.lineno, "*", node.attr))
        elif isinstance(node, ast.Name):
            found.append((node.lineno, "builtins", node.id))
    return found


def _shipped_python() -> list[Path]:
    """Every Python file a wheel installs and runs: the package (less the SPIKE hub's
    MicroPython agent) and the example missions it carries."""
    package = [p for p in (ROOT / "roboscript").rglob("*.py") if "agent" not in p.parts]
    return sorted([*package, *MISSIONS.rglob("*.py"), ROOT / "setup.py"])


def test_the_package_imports_nothing_the_oldest_python_it_claims_lacks() -> None:
    assert 'requires-python = ">=3.10"' in (ROOT / "pyproject.toml").read_text(encoding="utf-8")
    for path in _shipped_python():
        source = path.read_text(encoding="utf-8")
        # syntax of a later Python (except*, a `type` statement, class C[T]) is refused
        tree = ast.parse(source, filename=str(path), feature_version=(3, 10))
        for line, module, name in _imported_at_run_time(tree) + _used_at_run_time(tree):
            newer = NEWER_THAN_3_10.get(module, set()) | (NEWER_METHODS if module == "*" else set())
            assert name not in newer and "*" not in newer, f"{path}:{line}: {module}.{name}"
