"""Golden messages for numbers out of range, as ``roboscript check`` shows them to students."""

from __future__ import annotations

import dataclasses
import textwrap
import tracemalloc
from collections.abc import Callable
from pathlib import Path
from types import SimpleNamespace
from typing import Any

import pytest

from roboscript.actions import ACTIONS
from roboscript.errors import MissionError
from roboscript.mission import load_mission, mission_for_robot
from roboscript.mission.limits import MIN_SPEED_MM_S, param_problems, profile_problems
from roboscript.mission.spec import MissionSpec

ONE_ACTION = """\
mission: m
states:
  go:
    do: ACTION
    on: {done: end, failed: end, timeout: end}
  end:
    final: success
"""


def report(path: Path, robot: str | None = None) -> list[str]:
    """What ``roboscript check`` prints for ``path``: its errors, or else its warnings."""
    try:
        _spec, _profile, warnings = mission_for_robot(path, robot)
    except MissionError as exc:
        found = getattr(exc, "problems", [exc])
    else:
        found = warnings
    return [p.format().replace(str(path), "M") for p in found]


def one_action(write_mission: Callable[..., Path], action: str) -> Path:
    return write_mission(ONE_ACTION.replace("ACTION", action))


@pytest.mark.parametrize(
    ("action", "expected"),
    [
        (
            "{drive: {distance: 1e400}}",
            (
                "M:4:28: error: drive distance: infinity is not a number the robot can use"
                " (write a distance such as '50 cm')"
            ),
        ),
        (
            "{drive: {distance: 200 m}}",
            (
                "M:4:28: error: drive distance: 200000 mm is farther than any room (at most 100 m)"
                " (write a distance such as '50 cm')"
            ),
        ),
        (
            "{play_tone: {frequency: inf Hz}}",
            (
                "M:4:33: error: play_tone frequency: 'inf Hz' is not a number the robot can use;"
                " write a frequency such as '880 Hz'"
            ),
        ),
        (
            "{play_tone: {frequency: 30 kHz}}",
            (
                "M:4:33: error: play_tone frequency: 30000 Hz is beyond what a buzzer can play"
                " (20 Hz to 20 kHz) (write a pitch such as '880 Hz')"
            ),
        ),
        (
            "{drive: {duration: -1 s}}",
            (
                "M:4:28: error: drive duration: -1 s is not a positive time, so it would end"
                " at once (write a positive time such as '2 s')"
            ),
        ),
        (
            "{wait: {duration: 0 s}}",
            (
                "M:4:27: error: wait duration: 0 s is not a positive time, so it would end at once"
                " (write a positive time such as '2 s')"
            ),
        ),
        (
            "{wait: {duration: 90 min}}",
            (
                "M:4:27: error: wait duration: 5400 s is longer than any run (at most 1 hour)"
                " (write a time of at most 3600 s)"
            ),
        ),
        (
            "{drive: {distance: 50 cm, speed: -10 cm/s}}",
            (
                "M:4:42: error: drive speed: -100 mm/s is not a positive speed"
                " (write a speed such as '15 cm/s'; a negative distance drives backward)"
            ),
        ),
        (
            "{drive: {distance: 50 cm, duration: 2 s}}",
            (
                "M:4:45: error: drive takes a distance or a duration, not both: it would drive the"
                " distance and ignore the duration (remove 'duration' to drive the distance, or"
                " 'distance' to drive for the time)"
            ),
        ),
        (
            "{rotate: {angle: 10000 deg}}",
            (
                "M:4:26: error: rotate angle: 10000 deg is more than ten whole turns"
                " (write an angle such as '90 deg'; a negative angle turns left)"
            ),
        ),
        (
            "{servo: {angle: 200 deg}}",
            (
                "M:4:25: error: servo angle: 200 deg is beyond a servo's travel (0 to 180 deg)"
                " (write an angle from 0 deg to 180 deg)"
            ),
        ),
        (
            "{set_led: {index: 99, color: red}}",
            (
                "M:4:27: error: set_led index: 99 is not an index a board has (0 to 63)"
                " (count from 0: the first one is index 0)"
            ),
        ),
        (
            '{wait_until: {condition: "range.distance_cm < 10**400", timeout: 2 s}}',
            (
                "M:4:55: error: wait_until condition: a condition cannot raise to a power ('**');"
                " only + - * / are allowed (write the number itself, at most 1e+09)"
            ),
        ),
        (
            '{wait_until: {condition: "range.distance_cm < 1e400", timeout: 2 s}}',
            (
                "M:4:55: error: wait_until condition: the number infinity is too large for a"
                " condition (at most 1e+09) (compare with a number a sensor can read,"
                " e.g. range.distance_cm < 20)"
            ),
        ),
        (
            '{wait_until: {condition: "elapsed > 12345678901234567890 s", timeout: 2 s}}',
            (
                "M:4:45: error: wait_until condition: a number of 20 digits is too large for a"
                " condition (at most 1e+09) (compare with a number a sensor can read,"
                " e.g. range.distance_cm < 20)"
            ),
        ),
        (
            '{wait_until: {condition: "bumper.any", timeout: 1e400}}',
            (
                "M:4:57: error: wait_until timeout: infinity is not a time the robot can wait"
                " (write a time such as '2 s', at most 3600 s)"
            ),
        ),
    ],
)
def test_a_number_out_of_range_is_an_error_at_the_parameter(
    write_mission: Callable[..., Path], action: str, expected: str
) -> None:
    assert report(one_action(write_mission, action)) == [expected]


def test_a_state_timeout_must_be_finite(write_mission: Callable[..., Path]) -> None:
    path = write_mission(
        ONE_ACTION.replace("ACTION", "{drive: {distance: 50 cm}}").replace(
            "    on:", "    timeout: 1e400\n    on:"
        )
    )
    assert report(path) == [
        (
            "M:5:14: error: state 'go': timeout: infinity is not a time the robot can wait"
            " (write a time such as '2 s', at most 3600 s)"
        )
    ]


def test_plen_steps_out_of_range_are_refused_without_allocating(
    write_mission: Callable[..., Path],
) -> None:
    # A walk of a billion steps once queued every step: 1.9 GB, then the interpreter aborted.
    path = one_action(write_mission, "{walk: {steps: -1000000000}}")
    tracemalloc.start()
    try:
        found = report(path, "plen2")
        _current, peak = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    assert found == [
        (
            "M:4:24: error: walk steps: -1000000000 is more steps than a robot can take in one go"
            " (at most 1000 each way) (write steps from -1000 to 1000, or repeat a shorter walk)"
        )
    ]
    assert peak < 50_000_000


def test_python_values_are_checked_at_their_keyword(write_mission: Callable[..., Path]) -> None:
    path = write_mission(
        textwrap.dedent(
            """\
            from roboscript import Drive, Mission, Walk, state


            class Far(Mission):
                robot = "plen2"
                go = state(Walk(steps=-9.2e18), initial=True, on_done="end")
                back = state(Drive(distance_mm=10**400), on_done="end")
                end = state(final="success")
            """
        ),
        "far.py",
    )
    assert report(path) == [
        (
            "M:6:27: error: walk steps: -9200000000000000000 is more steps than a robot can take"
            " in one go (at most 1000 each way) (write steps from -1000 to 1000, or repeat a"
            " shorter walk)"
        ),
        (
            "M:7:36: error: drive distance: a number with about 401 digits is far too large for"
            " a distance"
        ),
    ]


@pytest.mark.parametrize(
    ("action", "robot", "expected"),
    [
        (
            "{drive: {distance: 50 cm, speed: 5 m/s}}",
            None,
            (
                "M:4:42: warning: drive speed: 5000 mm/s is faster than mirto can drive, so it will"
                " drive at its top speed of 300 mm/s (write speed: 300 mm/s or less)"
            ),
        ),
        (
            "{drive: {distance: 50 cm, speed: 5 m/s}}",
            "spike-prime",
            (
                "M:4:42: warning: drive speed: 5000 mm/s is faster than spike-prime can drive,"
                " so it will drive at its top speed of 350 mm/s (write speed: 350 mm/s or less)"
            ),
        ),
        (
            "{drive: {distance: 50 cm, speed: 1 mm/s}}",
            None,
            (
                "M:4:42: warning: drive speed: 1 mm/s is too slow to overcome the wheels'"
                " friction, so mirto may not move and 'drive' may fail (stalled)"
                " (write speed: 10 mm/s or more)"
            ),
        ),
        (
            "{follow_line: {speed: 1 m/s, duration: 5 s}}",
            None,
            (
                "M:4:31: warning: follow_line speed: 1000 mm/s is faster than mirto can drive,"
                " so it will drive at its top speed of 300 mm/s (write speed: 300 mm/s or less)"
            ),
        ),
        (
            "{rotate: {angle: 90 deg, turn_rate: 1000 deg/s}}",
            None,
            (
                "M:4:45: warning: rotate turn_rate: 1000 deg/s is faster than mirto can turn, so it"
                " will turn at its top turn rate of 212 deg/s (write turn_rate: 212 deg/s or less)"
            ),
        ),
        (
            "{rotate: {angle: 90 deg, turn_rate: 1 deg/s}}",
            None,
            (
                "M:4:45: warning: rotate turn_rate: 1 deg/s is too slow to overcome the wheels'"
                " friction, so mirto may not move and 'rotate' may fail (stalled)"
                " (write turn_rate: 8 deg/s or more)"
            ),
        ),
    ],
)
def test_a_speed_the_robot_cannot_hold_is_a_warning_that_says_what_happens(
    write_mission: Callable[..., Path], action: str, robot: str | None, expected: str
) -> None:
    assert report(one_action(write_mission, action), robot) == [expected]


def test_speeds_inside_parallel_and_repeat_are_checked(
    write_mission: Callable[..., Path],
) -> None:
    action = (
        "{parallel: {all: [{repeat: {times: 2, do: {drive: {distance: 50 cm, speed: 2 m/s}}}},"
        " {play_tone: {frequency: 440 Hz}}]}}"
    )
    found = report(one_action(write_mission, action))
    assert len(found) == 1 and "drive speed: 2000 mm/s is faster than mirto" in found[0]


@pytest.mark.parametrize("robot", ["mirto", "asip-basic", "spike-prime", "stackmod-rover"])
def test_the_slowest_speed_without_a_warning_moves_the_simulated_robot(
    write_mission: Callable[..., Path], robot: str
) -> None:
    from roboscript.session import run_session

    slowest = f"{{drive: {{distance: 3 cm, speed: {MIN_SPEED_MM_S:g} mm/s}}}}"
    spec, profile, warnings = mission_for_robot(one_action(write_mission, slowest), robot)
    assert warnings == []
    session = run_session(spec, profile, max_time_s=30.0)
    assert (session.result.outcome, session.result.final_state) == ("success", "end")


def test_below_the_slowest_speed_the_simulated_robot_stalls(
    write_mission: Callable[..., Path],
) -> None:
    from roboscript.session import run_session

    too_slow = f"{{drive: {{distance: 3 cm, speed: {MIN_SPEED_MM_S / 2:g} mm/s}}}}"
    text = ONE_ACTION.replace("ACTION", too_slow).replace("failed: end", "failed: stuck")
    path = write_mission(text + "  stuck:\n    final: failure\n")
    spec, profile, warnings = mission_for_robot(path, "mirto")
    assert "too slow to overcome the wheels' friction" in warnings[0].message
    session = run_session(spec, profile, max_time_s=30.0)
    assert session.result.final_state == "stuck"
    assert "stalled" in (session.result.reason or "")


def test_speeds_in_range_give_no_warning(write_mission: Callable[..., Path]) -> None:
    path = one_action(write_mission, "{drive: {distance: 50 cm, speed: 30 cm/s}}")
    assert report(path) == []
    path = one_action(write_mission, "{drive: {distance: 50 cm, speed: 1 cm/s}}")
    assert report(path) == []


# The edge of every range, numbers too large or not finite, and speed warnings for every action.


@pytest.mark.parametrize(
    ("action", "robot", "expected"),
    [
        (
            # 2**64 has 65 bits: too long to show digit by digit.
            "{walk: {steps: 18446744073709551616}}",
            "plen2",
            (
                "M:4:24: error: walk steps: a number with about 20 digits is more steps than a"
                " robot can take in one go (at most 1000 each way)"
                " (write steps from -1000 to 1000, or repeat a shorter walk)"
            ),
        ),
        (
            # 2**63 has 64 bits: still shown as written.
            "{walk: {steps: 9223372036854775808}}",
            "plen2",
            (
                "M:4:24: error: walk steps: 9223372036854775808 is more steps than a robot can"
                " take in one go (at most 1000 each way)"
                " (write steps from -1000 to 1000, or repeat a shorter walk)"
            ),
        ),
        (
            "{drive: {distance: .nan}}",
            None,
            (
                "M:4:28: error: drive distance: not a number is not a number the robot can use"
                " (write a distance such as '50 cm')"
            ),
        ),
        (
            "{drive: {distance: -1e400}}",
            None,
            (
                "M:4:28: error: drive distance: minus infinity is not a number the robot can use"
                " (write a distance such as '50 cm')"
            ),
        ),
        (
            "{rotate: {angle: inf deg}}",
            None,
            (
                "M:4:26: error: rotate angle: 'inf deg' is not a number the robot can use;"
                " write an angle such as '90 deg'"
            ),
        ),
        (
            "{rotate: {angle: 90 deg, turn_rate: inf deg/s}}",
            None,
            (
                "M:4:45: error: rotate turn_rate: 'inf deg/s' is not a number the robot can use;"
                " write a turn rate such as '90 deg/s'"
            ),
        ),
        (
            "{wait: {duration: nan s}}",
            None,
            (
                "M:4:27: error: wait duration: 'nan s' is not a number the robot can use;"
                " write a time such as '2 s'"
            ),
        ),
        (
            "{rotate: {angle: 90 deg, turn_rate: 0 deg/s}}",
            None,
            (
                "M:4:45: error: rotate turn_rate: 0 deg/s is not a positive turn rate"
                " (write a turn rate such as '90 deg/s'; a negative angle turns left)"
            ),
        ),
        (
            "{drive: {distance: 1 m, speed: 0 cm/s}}",
            None,
            (
                "M:4:40: error: drive speed: 0 mm/s is not a positive speed"
                " (write a speed such as '15 cm/s'; a negative distance drives backward)"
            ),
        ),
        (
            "{wait: {duration: 3601 s}}",
            None,
            (
                "M:4:27: error: wait duration: 3601 s is longer than any run (at most 1 hour)"
                " (write a time of at most 3600 s)"
            ),
        ),
        (
            # Half a mm/s over the top speed: the warning has no slack of a whole unit.
            "{drive: {distance: 1 m, speed: 300.5 mm/s}}",
            None,
            (
                "M:4:40: warning: drive speed: 300.5 mm/s is faster than mirto can drive, so it"
                " will drive at its top speed of 300 mm/s (write speed: 300 mm/s or less)"
            ),
        ),
        (
            "{drive: {distance: 1 m, speed: 9.5 mm/s}}",
            None,
            (
                "M:4:40: warning: drive speed: 9.5 mm/s is too slow to overcome the wheels'"
                " friction, so mirto may not move and 'drive' may fail (stalled)"
                " (write speed: 10 mm/s or more)"
            ),
        ),
    ],
)
def test_golden_messages_for_numbers_out_of_range(
    write_mission: Callable[..., Path], action: str, robot: str | None, expected: str
) -> None:
    path = write_mission(ONE_ACTION.replace("ACTION", action))
    assert report(path, robot) == [expected]


@pytest.mark.parametrize(
    ("action", "kwargs"),
    [
        ("walk", {"steps": 1000}),
        ("walk", {"steps": -1000}),
        ("set_led", {"index": 63}),
        ("drive", {"distance_mm": 100_000.0}),
        ("servo", {"angle_deg": 0.0}),
        ("servo", {"angle_deg": 180.0}),
        ("rotate", {"angle_deg": 3600.0}),
        ("play_tone", {"frequency_hz": 20.0}),
        ("play_tone", {"frequency_hz": 20_000.0}),
        ("wait", {"duration_s": 3600.0}),
    ],
)
def test_the_edge_of_every_range_is_allowed(action: str, kwargs: dict[str, Any]) -> None:
    params = ACTIONS[action].params
    assert {p.kwarg for p in params} >= set(kwargs)  # the keyword is the action's own
    assert param_problems(action, params, kwargs, built_in=True) == []


def _spec(write_mission: Callable[..., Path], action: str) -> MissionSpec:
    spec, _warnings = load_mission(write_mission(ONE_ACTION.replace("ACTION", action)))
    return spec


def _slow_robot(**overrides: Any) -> SimpleNamespace:
    robot = {
        "name": "crawler",
        "capabilities": frozenset({"drive_base"}),
        "max_speed_mm_s": 100.0,
        "track_mm": 160.0,
    }
    return SimpleNamespace(**(robot | overrides))


def test_a_default_speed_too_fast_for_the_robot_is_warned_at_the_action(
    write_mission: Callable[..., Path],
) -> None:
    path = write_mission(ONE_ACTION.replace("ACTION", "{drive: {distance: 1 m}}"))
    spec, _warnings = load_mission(path)
    found = [p.format().replace(str(path), "M") for p in profile_problems(spec, _slow_robot())]
    assert found == [
        (
            "M:4:10: warning: drive speed: 150 mm/s is faster than crawler can drive, so it will"
            " drive at its top speed of 100 mm/s (write speed: 100 mm/s or less)"
        )
    ]


def test_an_action_written_nowhere_is_warned_about_the_mission(
    write_mission: Callable[..., Path],
) -> None:
    # A mission built in code may carry no locations; the warning still names a place.
    spec = _spec(write_mission, "{drive: {distance: 1 m}}")
    go = spec.states["go"]
    assert go.action is not None
    bare = dataclasses.replace(go.action, location=None, param_locations={})
    spec = dataclasses.replace(
        spec, states={**spec.states, "go": dataclasses.replace(go, action=bare)}
    )
    found = [p.format() for p in profile_problems(spec, _slow_robot())]
    assert found == [
        (
            "<mission>: warning: drive speed: 150 mm/s is faster than crawler can drive, so it"
            " will drive at its top speed of 100 mm/s (write speed: 100 mm/s or less)"
        )
    ]


def test_a_robot_without_a_capability_list_gets_no_speed_warnings(
    write_mission: Callable[..., Path],
) -> None:
    spec = _spec(write_mission, "{drive: {distance: 1 m, speed: 2 m/s}}")
    assert profile_problems(spec, SimpleNamespace(name="box")) == []


@pytest.mark.parametrize("speed", [0.0, -5.0, float("inf"), float("nan")])
def test_speeds_the_parameter_checks_refuse_get_no_robot_warning_but_later_ones_do(
    write_mission: Callable[..., Path], speed: float
) -> None:
    # The bad speed already has its error; the next state's speed must still be checked.
    spec = _spec(write_mission, "{drive: {distance: 1 m, speed: 2 m/s}}")
    go = spec.states["go"]
    assert go.action is not None
    bad = dataclasses.replace(go.action, kwargs={**go.action.kwargs, "speed_mm_s": speed})
    first = dataclasses.replace(go, name="first", action=bad)
    spec = dataclasses.replace(spec, states={"first": first, **spec.states})
    found = [p.message for p in profile_problems(spec, _slow_robot())]
    assert found == [
        (
            "drive speed: 2000 mm/s is faster than crawler can drive, so it will drive at its"
            " top speed of 100 mm/s"
        )
    ]


DIM = """\
from roboscript import Action, ActionContext, Param, Result


class Dim(Action):
    name = "dim"
    params = (Param("level", "level_pct", "percent", "how bright", 50.0),)

    def __init__(self, level_pct: float = 50.0) -> None:
        self.level_pct = level_pct

    def update(self, ctx: ActionContext) -> Result | None:
        return Result.done()
"""


def test_a_student_percent_that_is_not_a_number_gets_a_percent_example(
    write_mission: Callable[..., Path],
) -> None:
    mission = ONE_ACTION.replace("ACTION", "{dim: {level: inf %}}")
    path = write_mission("behaviours: [dim.py]\n" + mission)
    (path.parent / "dim.py").write_text(DIM, encoding="utf-8")
    assert report(path) == [
        (
            "M:5:23: error: dim level: 'inf %' is not a number the robot can use;"
            " write a percent such as '50 %'"
        )
    ]


def test_a_student_default_of_false_is_not_read_as_a_time(
    write_mission: Callable[..., Path],
) -> None:
    # ``False`` is an int to Python, but a student who writes it means "none", not 0 s.
    nap = DIM.replace('name = "dim"', 'name = "nap"').replace(
        'Param("level", "level_pct", "percent", "how bright", 50.0)',
        'Param("pause", "level_pct", "time", "wait first", False)',
    )
    path = write_mission("behaviours: [nap.py]\n" + ONE_ACTION.replace("ACTION", "{nap: {}}"))
    (path.parent / "nap.py").write_text(nap, encoding="utf-8")
    assert report(path) == []


@pytest.mark.parametrize(
    ("action", "expected"),
    [
        (
            "{drive: {distance: 0 cm}}",
            (
                "M:4:28: error: drive distance: 0 mm does not move the robot, so 'drive' ends at"
                " once (write a distance such as '50 cm'; a negative one drives backward; to stay"
                " still, use wait)"
            ),
        ),
        (
            "{rotate: {angle: 0}}",
            (
                "M:4:26: error: rotate angle: 0 deg does not turn the robot, so 'rotate' ends at"
                " once (write an angle such as '90 deg'; a negative one turns left; to stay"
                " still, use wait)"
            ),
        ),
    ],
)
def test_a_drive_or_rotate_of_zero_is_an_error_that_says_it_would_end_at_once(
    write_mission: Callable[..., Path], action: str, expected: str
) -> None:
    assert report(one_action(write_mission, action)) == [expected]


def test_a_servo_at_zero_degrees_is_no_mistake(write_mission: Callable[..., Path]) -> None:
    assert report(one_action(write_mission, "{servo: {angle: 0 deg}}"), "mirto") == []


@pytest.mark.parametrize(
    ("transport", "duration", "expected"),
    [
        (
            "uart",
            "40 s",
            [
                (
                    "M:4:51: warning: play_tone duration: 40 s is longer than mirto-uno's board"
                    " can play a tone (32.767 s): it keeps a tone's length in a small number that"
                    " runs over, so the tone is cut short or not played at all (write duration:"
                    " 32 s or less; for a longer sound, repeat a shorter play_tone)"
                )
            ],
        ),
        ("uart", "32.767 s", []),
        ("usb", "40 s", []),  # the MIRTO's Teensy keeps it in 32 bits
    ],
    ids=["uart-over", "uart-at-the-edge", "usb"],
)
def test_a_tone_longer_than_the_asip_board_plays_is_a_warning(
    write_mission: Callable[..., Path],
    tmp_path: Path,
    transport: str,
    duration: str,
    expected: list[str],
) -> None:
    robot = tmp_path / "mirto-uno.yaml"
    robot.write_text(f"extends: mirto\nname: mirto-uno\noptions:\n  transport: {transport}\n")
    action = f"{{play_tone: {{frequency: 440 Hz, duration: {duration}}}}}"
    assert report(one_action(write_mission, action), str(robot)) == expected
