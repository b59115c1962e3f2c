"""Behaviours students write in Python: used by name from YAML, errors in their terms."""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import pytest
from helpers import MISSIONS, refusal, run_cli

from roboscript.clock import SimClock
from roboscript.mission import load_mission
from roboscript.mission.behaviours import load_behaviour_file
from roboscript.mission.runner import MissionRunner
from roboscript.mission.student_code import shown_path
from roboscript.scheduler import Scheduler

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
    return refusal(path, shown={str(path): "M", str(path.parent / "spin.py"): "B"})


class FakeBase:
    track_mm = 160.0
    max_speed_mm_s = 300.0
    odometry_is_estimated = False

    def __init__(self) -> None:
        self.speeds = (0.0, 0.0)

    def set_wheel_speeds(self, left: float, right: float) -> None:
        self.speeds = (left, right)

    def stop(self) -> None:
        self.speeds = (0.0, 0.0)

    def wheel_distances_mm(self) -> tuple[float, float]:
        return 0.0, 0.0


def run(path: Path) -> tuple[MissionRunner, FakeBase]:
    spec, _ = load_mission(path)
    base = FakeBase()
    sched = Scheduler(SimClock(), 0.02)
    runner = MissionRunner(spec, {"drive_base": base})
    sched.add(runner)
    sched.run(until=lambda: runner.finished, max_duration_s=10)
    return runner, base


def test_a_yaml_mission_uses_a_behaviour_by_name(tmp_path: Path) -> None:
    spec, _warnings = load_mission(write(tmp_path))
    action = spec.states["go"].action
    assert action is not None and action.name == "spin" and dict(action.kwargs) == {"turns": 2}
    assert action.requires == {"drive_base"}
    runner, base = run(tmp_path / "go.yaml")
    assert runner.result.outcome == "success"
    assert runner.result.duration_s == 0.38  # 20 updates, 20 ms apart, the first at 0 s
    assert base.speeds == (0.0, 0.0)


def test_the_zigzag_example_loads_with_its_parameters_in_units() -> None:
    spec, warnings = load_mission(MISSIONS / "zigzag.yaml")
    assert warnings == []
    action = spec.states["weave"].action
    assert action is not None and action.name == "zigzag"
    assert dict(action.kwargs) == {
        "leg_mm": 200.0,
        "legs": 4,
        "speed_mm_s": 150.0,
        "swerve_pct": 40.0,
    }


# ------------------------------------------------------------------------ golden messages


@pytest.mark.parametrize(
    ("behaviour", "expected"),
    [
        (
            SPIN.replace("def update(self, ctx: ActionContext) -> Result | None:", "def update("),
            ["B:18:15: error: syntax error: '(' was never closed"],
        ),
        (
            SPIN.replace("class Spin", "SPEED = 1 / 0\n\n\nclass Spin"),
            ["B:4:9: error: ZeroDivisionError: division by zero"],
        ),
        (
            "import math\n",
            [
                (
                    "B:1:1: error: this file holds no behaviour (write a class that extends Action,"
                    " with name = '...' and update(self, ctx))"
                ),
                "M:6:10: error: unknown action 'spin' (did you mean 'stop'?)",
            ],
        ),
        (
            SPIN.replace('name = "spin"', 'name = "drive"'),
            [
                (
                    "B:4:1: error: behaviour Spin is called 'drive', like the built-in action"
                    " (give it a name of its own)"
                ),
                "M:6:10: error: unknown action 'spin' (did you mean 'stop'?)",
            ],
        ),
        (
            SPIN.replace('{"drive_base"}', '{"drive_bsae"}'),
            [
                (
                    "B:4:1: error: behaviour 'spin' requires 'drive_bsae', which is not a"
                    " capability (did you mean 'drive_base'?)"
                )
            ],
        ),
        (
            SPIN.replace('"turns", "turns", "count"', '"turns", "turn_count", "cuont"'),
            [
                (
                    "B:4:1: error: behaviour 'spin' parameter 'turns': unknown kind 'cuont'"
                    " (did you mean 'count'?)"
                ),
                (
                    "B:4:1: error: behaviour 'spin' parameter 'turns' is passed as turn_count=...,"
                    " which its __init__ does not take (did you mean 'turns'?)"
                ),
            ],
        ),
        (
            SPIN.replace("def update(", "def updaet("),
            [
                (
                    "B:4:1: error: behaviour 'spin' has no update(self, ctx) method"
                    " (update() returns None while running, else Result.done()"
                    " or Result.failed(...))"
                )
            ],
        ),
        (
            SPIN.replace('name = "spin"', 'name = "Spin It"'),
            [
                (
                    "B:4:1: error: behaviour Spin needs a name, a lowercase word (got 'Spin It')"
                    " (add name = 'spin' to the class)"
                ),
                "M:6:10: error: unknown action 'spin' (did you mean 'stop'?)",
            ],
        ),
        (
            SPIN.replace("self.turns = turns", "self.turns = turns / 0"),
            [
                (
                    "M:6:10: error: your behaviour 'spin' raised ZeroDivisionError:"
                    " division by zero (B:12)"
                )
            ],
        ),
    ],
)
def test_golden_messages_for_a_bad_behaviour_file(
    tmp_path: Path, behaviour: str, expected: list[str]
) -> None:
    assert messages(write(tmp_path, behaviour)) == expected


def test_a_missing_behaviour_file_gets_a_did_you_mean(tmp_path: Path) -> None:
    path = write(tmp_path, mission=MISSION.replace("[spin.py]", "[spni.py]"))
    assert messages(path)[0] == (
        "M:2:14: error: there is no behaviour file 'spni.py' beside the mission"
        " (did you mean 'spin.py'?)"
    )


def test_a_misspelt_behaviour_name_gets_a_did_you_mean(tmp_path: Path) -> None:
    path = write(tmp_path, mission=MISSION.replace("{spin:", "{spni:"))
    assert messages(path) == ["M:6:10: error: unknown action 'spni' (did you mean 'spin'?)"]


def test_behaviours_are_only_known_to_missions_that_list_them(tmp_path: Path) -> None:
    path = write(tmp_path, mission=MISSION.replace("behaviours: [spin.py]\n", ""))
    assert messages(path) == ["M:5:10: error: unknown action 'spin' (did you mean 'stop'?)"]


# ---------------------------------------------------------------------------- at run time

RAISES_IN_UPDATE = SPIN.replace(
    "        self.ticks += 1\n",
    "        self.ticks += 1\n        if self.ticks > 3:\n            self.turns = 1 / 0\n",
)


def test_an_exception_in_a_behaviour_ends_the_mission_in_one_sentence(tmp_path: Path) -> None:
    write(tmp_path, RAISES_IN_UPDATE)
    result = run_cli("run", "go.yaml", "--json", cwd=tmp_path)
    assert result.returncode == 1, result.stderr
    summary = json.loads(result.stdout)
    assert summary["outcome"] == "failure"
    assert summary["final_state"] == "go"
    assert summary["reason"] == (
        "your behaviour 'spin' raised ZeroDivisionError in state 'go': division by zero"
        " (spin.py:21)"
    )
    assert "Traceback" not in result.stderr


def test_the_traceback_is_there_with_debug(tmp_path: Path) -> None:
    write(tmp_path, RAISES_IN_UPDATE)
    result = run_cli("--debug", "run", "go.yaml", cwd=tmp_path)
    assert result.returncode == 1
    assert "Traceback" in result.stderr and "self.turns = 1 / 0" in result.stderr


def test_the_wheels_stop_when_a_behaviour_raises(tmp_path: Path) -> None:
    runner, base = run(write(tmp_path, RAISES_IN_UPDATE))
    assert runner.result.outcome == "failure"
    assert base.speeds == (0.0, 0.0)


def test_a_behaviour_that_calls_exit_fails_the_run_and_stops_the_wheels(tmp_path: Path) -> None:
    behaviour = RAISES_IN_UPDATE.replace("self.turns = 1 / 0", "raise SystemExit(0)")
    runner, base = run(write(tmp_path, behaviour))
    assert runner.result.outcome == "failure"
    assert runner.result.reason == (
        "your behaviour 'spin' called exit() in state 'go': a mission ends by going to a final"
        f" state, not by ending the program ({shown_path(tmp_path / 'spin.py')}:21)"
    )
    assert base.speeds == (0.0, 0.0)


def test_an_exception_in_stop_fails_a_mission_that_would_have_succeeded(tmp_path: Path) -> None:
    behaviour = SPIN.replace(
        "        ctx.drive_base.stop()\n", "        raise RuntimeError('oops')\n"
    )
    runner, base = run(write(tmp_path, behaviour))
    assert runner.result.outcome == "failure"
    assert runner.result.reason is not None
    assert runner.result.reason.startswith(
        "your behaviour 'spin' raised RuntimeError in state 'go': oops ("
    )
    assert base.speeds == (0.0, 0.0)


def test_a_behaviour_inside_parallel_is_the_one_blamed(tmp_path: Path) -> None:
    mission = MISSION.replace(
        "{spin: {turns: 2}}", "{parallel: {all: [{spin: {turns: 2}}, {wait: {duration: 1 s}}]}}"
    )
    runner, _ = run(write(tmp_path, RAISES_IN_UPDATE, mission))
    assert runner.result.reason is not None
    assert runner.result.reason.startswith("your behaviour 'spin' raised ZeroDivisionError")


def test_a_python_mission_imports_a_behaviour(tmp_path: Path) -> None:
    (tmp_path / "behaviours").mkdir()
    shutil.copy(MISSIONS / "behaviours" / "zigzag.py", tmp_path / "behaviours" / "zigzag.py")
    (tmp_path / "weave.py").write_text(
        "from behaviours.zigzag import ZigZag\n"
        "from roboscript import Mission, state\n"
        "\n"
        "\n"
        "class Weave(Mission):\n"
        "    go = state(ZigZag(leg_mm=150, legs=2), initial=True, on_done='end',"
        " on_failed='end')\n"
        "    end = state(final='success')\n",
        encoding="utf-8",
    )
    result = run_cli("run", "weave.py", "--json", cwd=tmp_path)
    assert result.returncode == 0, result.stderr
    summary = json.loads(result.stdout)
    assert summary["outcome"] == "success"
    assert 290 < summary["sim"]["distance_travelled_mm"] < 320


def test_the_tutorial_shows_the_example_as_it_is() -> None:
    tutorial = (MISSIONS.parent / "docs" / "tutorial" / "write-your-own-behaviour.md").read_text(
        encoding="utf-8"
    )
    for example in (MISSIONS / "behaviours" / "zigzag.py", MISSIONS / "zigzag.yaml"):
        text = example.read_text(encoding="utf-8")
        assert text in tutorial, f"the tutorial's copy of {example.name} is out of date"


# Behaviour files written wrong: the whole message a student reads, in-process.

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
        (
            "M:9:10: error: unknown action 'twirl' (actions: display, drive, follow_line,"
            " follow_wall, motor, play_tone, rotate, servo, set_led, spin, stop, turn, wait,"
            " wait_until, walk)"
        ),
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
