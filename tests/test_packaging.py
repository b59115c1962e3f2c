"""What must reach an installed wheel does: worlds and typing marker as package data."""

from __future__ import annotations

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
