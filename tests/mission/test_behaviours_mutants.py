"""Behaviour files written wrong: the whole message a student reads, in-process.

These pin what ``load_mission`` and ``load_behaviour_file`` say about a behaviour class (its
name, its helper bases, its params and requires) and about the ``behaviours:`` list itself.
"""

from __future__ import annotations

from pathlib import Path

import pytest

from roboscript.errors import MissionError
from roboscript.mission import load_mission
from roboscript.mission.behaviours import load_behaviour_file

# The same behaviour and mission as tests/mission/test_behaviours.py.
SPIN = '''\
from roboscript import Action, ActionContext, Param, Result


class Spin(Action):
    """Spin on the spot for a while."""

    name = "spin"
    params = (Param("turns", "turns", "count", "how many turns", 1),)
    requires = frozenset({"drive_base"})

    def __init__(self, turns: int = 1) -> None:
        self.turns = turns
        self.ticks = 0

    def start(self, ctx: ActionContext) -> None:
        ctx.drive_base.set_wheel_speeds(100.0, -100.0)

    def update(self, ctx: ActionContext) -> Result | None:
        self.ticks += 1
        return Result.done() if self.ticks >= 10 * self.turns else None

    def stop(self, ctx: ActionContext) -> None:
        ctx.drive_base.stop()
'''

MISSION = """\
mission: go
behaviours: [spin.py]
initial: go
states:
  go:
    do: {spin: {turns: 2}}
    on: {done: end}
  end:
    final: success
"""


def write(folder: Path, behaviour: str = SPIN, mission: str = MISSION) -> Path:
    (folder / "spin.py").write_text(behaviour, encoding="utf-8")
    path = folder / "go.yaml"
    path.write_text(mission, encoding="utf-8")
    return path


def messages(path: Path) -> list[str]:
    with pytest.raises(MissionError) as info:
        load_mission(path)
    found = getattr(info.value, "problems", [info.value])
    text = [p.format() for p in found]
    return [t.replace(str(path), "M").replace(str(path.parent / "spin.py"), "B") for t in text]


OTHER = SPIN.replace("class Spin(", "class Twirl(").replace('name = "spin"', 'name = "twirl"')

TWO_FILES = """\
mission: go
behaviours: [spin.py, twirl.py]
initial: go
states:
  go:
    do: {spin: {turns: 2}}
    on: {done: twirl}
  twirl:
    do: {twirl: {turns: 1}}
    on: {done: end}
  end:
    final: success
"""


def test_a_behaviour_file_that_exits_is_called_a_behaviour_file(tmp_path: Path) -> None:
    behaviour = SPIN.replace("class Spin", "raise SystemExit(1)\n\n\nclass Spin")
    assert messages(write(tmp_path, behaviour)) == [
        "B:4:1: error: the behaviour file called exit() while it was loaded"
    ]


def test_a_nameless_helper_base_is_not_a_behaviour(tmp_path: Path) -> None:
    # Students factor shared code into a base class; only the named subclass is a behaviour.
    behaviour = SPIN.replace(
        "class Spin(Action):", "class Helper(Action):\n    pass\n\n\nclass Spin(Helper):"
    )
    load_mission(write(tmp_path, behaviour))
    found, problems = load_behaviour_file(tmp_path / "spin.py")
    assert (sorted(found), problems) == (["spin"], [])


def test_a_named_behaviour_others_extend_is_still_a_behaviour(tmp_path: Path) -> None:
    behaviour = SPIN + '\n\nclass FastSpin(Spin):\n    name = "fast_spin"\n'
    found, problems = load_behaviour_file(write(tmp_path, behaviour).parent / "spin.py")
    assert (sorted(found), problems) == (["fast_spin", "spin"], [])


def test_a_lone_class_without_a_name_gets_a_snake_case_hint(tmp_path: Path) -> None:
    behaviour = (
        SPIN + "\n\nclass SpinIt2Go(Action):\n    def update(self, ctx):\n        return None\n"
    )
    assert messages(write(tmp_path, behaviour)) == [
        (
            "B:26:1: error: behaviour SpinIt2Go needs a name, a lowercase word"
            " (add name = 'spin_it2_go' to the class)"
        )
    ]


def test_a_subclass_that_inherits_its_name_clashes_with_its_base(tmp_path: Path) -> None:
    behaviour = SPIN + "\n\nclass FastSpin(Spin):\n    pass\n"
    assert messages(write(tmp_path, behaviour)) == [
        "B:26:1: error: two behaviours are called 'spin' (rename one)"
    ]


def test_two_files_with_the_same_behaviour_name_say_where_the_other_is(tmp_path: Path) -> None:
    (tmp_path / "twirl.py").write_text(SPIN, encoding="utf-8")
    path = write(tmp_path, mission=TWO_FILES)
    assert [m.replace(str(tmp_path / "twirl.py"), "T") for m in messages(path)] == [
        "T:4:1: error: two behaviours are called 'spin' (the other is in B)",
        "M:9:10: error: unknown action 'twirl'",
    ]


def test_params_must_be_param_objects(tmp_path: Path) -> None:
    behaviour = SPIN.replace(
        'params = (Param("turns", "turns", "count", "how many turns", 1),)',
        'params = ("turns",)',
    )
    assert messages(write(tmp_path, behaviour)) == [
        (
            "B:4:1: error: behaviour 'spin': params is a tuple of Param(...)"
            " (e.g. params = (Param('speed', 'speed_mm_s', 'speed', 'how fast', 150.0),))"
        )
    ]


def test_an_unknown_kind_far_from_any_lists_the_kinds(tmp_path: Path) -> None:
    behaviour = SPIN.replace('"turns", "turns", "count"', '"turns", "turns", "zzzzzz"')
    assert messages(write(tmp_path, behaviour)) == [
        (
            "B:4:1: error: behaviour 'spin' parameter 'turns': unknown kind 'zzzzzz'"
            " (kinds: angle, choice, color, count, distance, frequency, guard, percent, speed,"
            " text, time, turn_rate)"
        )
    ]
    # A behaviour with a problem is not usable, even though the mission names it.
    assert load_behaviour_file(tmp_path / "spin.py")[0] == {}


def test_an_unknown_capability_far_from_any_lists_the_capabilities(tmp_path: Path) -> None:
    behaviour = SPIN.replace('{"drive_base"}', '{"qqqqqq"}')
    assert messages(write(tmp_path, behaviour)) == [
        (
            "B:4:1: error: behaviour 'spin' requires 'qqqqqq', which is not a capability"
            " (capabilities: drive_base, range, side_range, bumper, line, speaker, display,"
            " heading, leds, servos, walker, joints, force, color, buttons, motors)"
        )
    ]
    assert load_behaviour_file(tmp_path / "spin.py")[0] == {}


@pytest.mark.parametrize("kind", ["text", "choice"])
def test_text_and_choice_parameters_are_known_kinds(tmp_path: Path, kind: str) -> None:
    behaviour = SPIN.replace('"turns", "turns", "count"', f'"turns", "turns", "{kind}"')
    found, problems = load_behaviour_file(write(tmp_path, behaviour).parent / "spin.py")
    assert (sorted(found), problems) == (["spin"], [])


def test_requires_may_be_one_capability_written_as_a_string(tmp_path: Path) -> None:
    behaviour = SPIN.replace('frozenset({"drive_base"})', '"drive_base"')
    found, problems = load_behaviour_file(write(tmp_path, behaviour).parent / "spin.py")
    assert problems == []
    assert found["spin"].requires == frozenset({"drive_base"})


def test_behaviours_may_be_one_path_rather_than_a_list(tmp_path: Path) -> None:
    # Loads without a problem: the single path is not read as a list of letters.
    load_mission(write(tmp_path, mission=MISSION.replace("[spin.py]", "spin.py")))


def test_bad_entries_are_reported_and_the_rest_still_load(tmp_path: Path) -> None:
    (tmp_path / "twirl.py").write_text(OTHER, encoding="utf-8")
    mission = TWO_FILES.replace(
        "[spin.py, twirl.py]", "[5, notes.txt, ../up.py, spin.py, twirl.py]"
    )
    found = [m.replace(tmp_path.name, "F") for m in messages(write(tmp_path, mission=mission))]
    assert found == [
        "M:2:14: error: behaviours lists .py files, got 5 (e.g. behaviours: [my_behaviours.py])",
        (
            "M:2:17: error: behaviours lists .py files, got 'notes.txt'"
            " (e.g. behaviours: [my_behaviours.py])"
        ),
        (
            "M:2:28: error: the behaviour file '../up.py' is outside the mission's folder"
            " (put it in the folder of the mission (F) or below, and name it from there)"
        ),
    ]


def test_the_errors_of_every_broken_file_are_not_doubled_by_unknown_actions(
    tmp_path: Path,
) -> None:
    (tmp_path / "twirl.py").write_text(
        OTHER.replace('name = "twirl"', 'name = "twirl"\n    wheels = 1 / 0'), encoding="utf-8"
    )
    broken = SPIN.replace('name = "spin"', 'name = "spin"\n    wheels = 1 / 0')
    path = write(tmp_path, broken, mission=TWO_FILES)
    assert [m.replace(str(tmp_path / "twirl.py"), "T") for m in messages(path)] == [
        "B:8:14: error: ZeroDivisionError: division by zero",
        "T:8:14: error: ZeroDivisionError: division by zero",
    ]
