"""What must reach an installed wheel does: worlds and typing marker as package data."""

from __future__ import annotations

import ast
import subprocess
import sys
import zipfile
from pathlib import Path

from helpers import HANG_BOUND_S, ROOT

from roboscript.sim.world import builtin_worlds


def test_builtin_worlds_are_found_through_the_package() -> None:
    assert {"empty", "square-room", "corridor"} <= set(builtin_worlds())


def test_wheel_contains_the_package_data_and_nothing_from_the_top_level(tmp_path: Path) -> None:
    subprocess.run(
        [
            sys.executable,
            "-m",
            "pip",
            "wheel",
            "--no-deps",
            "-w",
            str(tmp_path),
            str(ROOT),
        ],
        check=True,
        capture_output=True,
        timeout=HANG_BOUND_S,
    )
    wheel = next(tmp_path.glob("roboscript-*.whl"))
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
}  # fmt: skip


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


def test_the_package_imports_nothing_the_oldest_python_it_claims_lacks() -> None:
    assert 'requires-python = ">=3.10"' in (ROOT / "pyproject.toml").read_text(encoding="utf-8")
    for path in sorted((ROOT / "roboscript").rglob("*.py")):
        if "agent" in path.parts:
            continue  # MicroPython for the SPIKE hub
        tree = ast.parse(path.read_text(encoding="utf-8"))
        for line, module, name in _imported_at_run_time(tree):
            newer = NEWER_THAN_3_10.get(module, set())
            assert name not in newer and "*" not in newer, f"{path}:{line}: {module}.{name}"
