"""Every file roboscript reads reports a mistake the same way: ``file:line:col: error: ...``."""

from __future__ import annotations

import re
from collections.abc import Callable
from pathlib import Path

import pytest

from roboscript.errors import InputError, MissionError, ProfileError, SpecError, WorldError
from roboscript.grading.spec import load_test_spec
from roboscript.mission import load_mission
from roboscript.profiles import get_profile
from roboscript.sim.world import load_world

# The same mistake in each kind of file: a key misspelt (on line 2, column 1).
CASES: list[tuple[str, str, Callable[[str], object], type[InputError], str, str]] = [
    (
        "mission.yaml",
        "initial: a\ndescripton: a square\nstates:\n  a: {final: success}\n",
        load_mission,
        MissionError,
        "descripton",
        "description",
    ),
    ("world.yaml", "world: room\nwals: []\n", load_world, WorldError, "wals", "walls"),
    (
        "robot.yaml",
        "extends: mirto\ntrak_mm: 120\n",
        get_profile,
        ProfileError,
        "trak_mm",
        "track_mm",
    ),
    (
        "spec.yaml",
        "test: square\nrobto: mirto\nexpect:\n  - outcome: success\n",
        load_test_spec,
        SpecError,
        "robto",
        "robot",
    ),
]

SHAPE = re.compile(
    r"^(?P<path>.+):(?P<line>\d+):(?P<col>\d+): error: "
    r"unknown key '(?P<key>[^']+)' in (?P<what>[^(]+) \(did you mean '(?P<near>[^']+)'\?\)$"
)


@pytest.mark.parametrize(
    ("name", "text", "load", "kind", "key", "near"), CASES, ids=[c[0] for c in CASES]
)
def test_an_unknown_key_reads_the_same_in_every_kind_of_file(
    tmp_path: Path,
    name: str,
    text: str,
    load: Callable[[str], object],
    kind: type[InputError],
    key: str,
    near: str,
) -> None:
    path = tmp_path / name
    path.write_text(text, encoding="utf-8")
    with pytest.raises(kind) as info:
        load(str(path))
    message = str(info.value).splitlines()[0]
    found = SHAPE.match(message)
    assert found, message
    assert found["path"] == str(path)
    assert (found["line"], found["col"]) == ("2", "1")
    assert (found["key"], found["near"]) == (key, near)
    assert (info.value.line, info.value.col, info.value.hint) == (2, 1, f"did you mean '{near}'?")


def test_the_input_layer_does_not_import_missions_worlds_or_profiles() -> None:
    import ast

    folder = Path(__file__).parents[2] / "roboscript" / "inputs"
    for path in folder.glob("*.py"):
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.ImportFrom) and (node.module or "").startswith("roboscript."):
                assert node.module == "roboscript.errors" or str(node.module).startswith(
                    "roboscript.inputs"
                ), f"{path.name} imports {node.module}"
