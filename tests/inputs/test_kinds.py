"""Which kind of YAML file a file is (roboscript/inputs/kinds.py)."""

from __future__ import annotations

import pickle
from pathlib import Path

import pytest
from helpers import run_cli

from roboscript.errors import InputError
from roboscript.grading import spec as test_spec
from roboscript.inputs.kinds import (
    OWN_KEYS,
    FileKind,
    file_kind,
    kind_of_keys,
    not_a_mission,
    not_the_kind_expected,
    refuse_another_kind,
)
from roboscript.inputs.source import load_yaml
from roboscript.mission import yaml_loader
from roboscript.sim import world

ROOT = Path(__file__).resolve().parents[2]


@pytest.mark.parametrize(
    ("path", "kind"),
    [
        ("roboscript/sim/worlds/square-room.yaml", "world"),
        ("roboscript/sim/worlds/empty.yaml", "world"),
        ("missions/teacher/square/test.yaml", "test spec"),
        ("missions/square.yaml", "mission"),
    ],
)
def test_the_projects_own_files_are_recognised(path: str, kind: str) -> None:
    assert file_kind(ROOT / path) == kind


def test_a_profile_file_is_a_profile(tmp_path: Path) -> None:
    path = tmp_path / "fast.yaml"
    path.write_text("extends: mirto\nname: fast\nmax_speed_mm_s: 300\n")
    assert file_kind(path) == "profile"


@pytest.mark.parametrize(
    "text",
    ["states: [\n", "- a list\n", "just text\n", "", "description: nothing else\n"],
)
def test_what_nothing_tells_apart_is_a_mission_for_the_mission_reader(
    tmp_path: Path, text: str
) -> None:
    path = tmp_path / "m.yaml"
    path.write_text(text)
    assert file_kind(path) == "mission"


def test_a_world_with_a_misspelt_key_is_still_a_world() -> None:
    assert kind_of_keys({"world", "start", "wals", "regions"}) == "world"
    assert kind_of_keys({"world", "description"}) == "world"
    assert kind_of_keys({"mission", "world", "states"}) == "mission"


def test_python_files_are_missions(tmp_path: Path) -> None:
    assert file_kind(tmp_path / "m.py") == "mission"


def test_each_readers_own_keys_are_known_here() -> None:
    # the readers' key lists and this table must not drift apart
    shared = {"description", "world", "robot", "name"}
    assert set(yaml_loader._TOP_KEYS) - shared == OWN_KEYS["mission"]
    assert set(test_spec._TOP_KEYS) - shared == OWN_KEYS["test spec"]
    world_keys = {"world", "description", "start", "walls", "lines", "regions"}
    assert world_keys - shared == OWN_KEYS["world"]
    assert "regions" in Path(world.__file__).read_text()


def test_the_message_says_what_the_file_is_and_how_to_use_it() -> None:
    assert not_a_mission("w.yaml", "world").format() == (
        "w.yaml:1:1: error: this is a world file, not a mission (it is a simulator world: "
        "run a mission in it with 'roboscript run MISSION --world w.yaml')"
    )


def test_the_error_crosses_to_another_process_with_what_the_file_is() -> None:
    error = not_a_mission("w.yaml", "world")
    again = pickle.loads(pickle.dumps(error))
    assert (type(again), again.kind, again.format()) == (type(error), "world", error.format())


def test_a_front_end_says_how_the_file_is_used_in_its_own_words() -> None:
    advised = not_a_mission("w.yaml", "world").advised({"world": "a world: pick {path}"})
    assert advised.format() == (
        "w.yaml:1:1: error: this is a world file, not a mission (it is a world: pick w.yaml)"
    )


@pytest.mark.parametrize(
    ("path", "kind"),
    [
        ("roboscript/sim/worlds/empty.yaml", "world"),
        ("missions/teacher/square/test.yaml", "test spec"),
        ("missions/square.yaml", "mission"),
    ],
)
def test_a_file_of_another_kind_is_named_in_one_sentence_where_a_mission_or_a_run_belongs(
    path: str, kind: FileKind
) -> None:
    # one sentence for every reader that tells kinds apart: the mission readers, the
    # readers of a world, a robot or a spec, and the commands that read a recorded run
    done = run_cli("view", str(ROOT / path))
    assert f"error: {not_the_kind_expected(kind, 'a recorded run')} (" in done.stderr
    assert not_a_mission(path, kind).message == not_the_kind_expected(kind, "a mission")
    with pytest.raises(InputError) as info:
        refuse_another_kind(load_yaml(ROOT / path), path, "profile", InputError)
    assert info.value.message == not_the_kind_expected(kind, "a robot profile")
