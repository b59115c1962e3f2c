"""The mission runner on fake capabilities (no robot, no simulator): routing and timing."""

from __future__ import annotations

import logging
import math
from pathlib import Path

import pytest

from roboscript.clock import SimClock
from roboscript.errors import CapabilityError, LinkError
from roboscript.mission import load_mission
from roboscript.mission.guards import compile_guard
from roboscript.mission.runner import MissionRunner
from roboscript.mission.yaml_loader import parse_yaml_mission
from roboscript.scheduler import Scheduler


class FakeBase:
    track_mm = 160.0
    max_speed_mm_s = 300.0
    odometry_is_estimated = False

    def __init__(self) -> None:
        self.speeds = (0.0, 0.0)
        self.travel = [0.0, 0.0]
        self.stops = 0
        self.blocked = False

    def set_wheel_speeds(self, left: float, right: float) -> None:
        self.speeds = (left, right)

    def stop(self) -> None:
        self.speeds = (0.0, 0.0)
        self.stops += 1

    def wheel_distances_mm(self) -> tuple[float, float]:
        return self.travel[0], self.travel[1]

    def tick(self, now: float, dt: float) -> None:
        if not self.blocked:
            self.travel[0] += self.speeds[0] * dt
            self.travel[1] += self.speeds[1] * dt


class FakeBumper:
    names = ("left", "right")

    def __init__(self) -> None:
        self.down: frozenset[str] = frozenset()

    def pressed(self) -> frozenset[str]:
        return self.down


class FakeSpeaker:
    def __init__(self) -> None:
        self.tones: list[tuple[float, float]] = []

    def beep(self, frequency_hz: float, duration_s: float) -> None:
        self.tones.append((frequency_hz, duration_s))


def run(text: str, max_s: float = 60.0, **caps: object) -> MissionRunner:
    spec, _ = parse_yaml_mission(text)
    base = caps.setdefault("drive_base", FakeBase())
    caps.setdefault("speaker", FakeSpeaker())
    clock = SimClock()
    sched = Scheduler(clock, 0.02)
    sched.add(base, "sense")  # type: ignore[arg-type]
    runner = MissionRunner(spec, caps)
    sched.add(runner)
    sched.run(until=lambda: runner.finished, max_duration_s=max_s)
    return runner


SQUARE = """
initial: side
states:
  side:
    do: {drive: {distance: 20 cm, speed: 10 cm/s}}
    on: {done: beep}
  beep:
    do: {play_tone: {frequency: 440 Hz, duration: 0.1 s}}
    on:
      done:
        - {if: "visits.side >= 3", goto: finished}
        - {goto: side}
  finished:
    final: success
"""


def test_conditional_on_entries_are_tried_in_order() -> None:
    speaker = FakeSpeaker()
    runner = run(SQUARE, speaker=speaker)
    assert runner.result.outcome == "success"
    names = [name for _, name in runner.result.states]
    assert names == ["side", "beep"] * 3 + ["finished"]
    assert speaker.tones == [(440.0, 0.1)] * 3


def test_state_times_are_on_the_scheduler_clock() -> None:
    runner = run(SQUARE)
    times = [t for t, _ in runner.result.states]
    # 200 mm at 100 mm/s is about 2 s per side; a tone 0.1 s.
    assert 1.9 < times[1] < 2.3
    assert 0.09 < times[2] - times[1] < 0.15
    assert runner.result.duration_s == times[-1]


def test_when_condition_interrupts_the_action_and_stops_the_wheels() -> None:
    bumper = FakeBumper()
    base = FakeBase()
    text = """
states:
  go:
    do: {drive: {distance: 5 m}}
    on: {done: end, failed: end}
    when:
      - {if: "bumper.any", goto: bumped}
  bumped:
    final: failure
  end:
    final: success
"""
    spec, _ = parse_yaml_mission(text)
    clock = SimClock()
    sched = Scheduler(clock, 0.02)
    sched.add(base, "sense")  # type: ignore[arg-type]
    runner = MissionRunner(spec, {"drive_base": base, "bumper": bumper})
    sched.add(runner)
    sched.add(
        lambda now, dt: setattr(bumper, "down", frozenset({"left"}) if now > 1.0 else bumper.down)
    )
    sched.run(until=lambda: runner.finished, max_duration_s=10)
    assert runner.result.outcome == "failure"
    assert runner.result.final_state == "bumped"
    assert (
        runner.result.reason
        == "ended in the failure state 'bumped' after 'bumper.any' held in state 'go'"
    )
    assert base.speeds == (0.0, 0.0)
    assert 1.0 < runner.result.duration_s < 1.1


def test_state_timeout_routes_or_fails() -> None:
    routed = run(
        "states:\n  w:\n    do: {wait: {duration: 10 s}}\n    timeout: 2 s\n"
        "    on: {done: a, timeout: b}\n  a: {final: success}\n  b: {final: failure}\n"
    )
    assert routed.result.final_state == "b"
    assert abs(routed.result.duration_s - 2.0) < 0.03
    unrouted = run(
        "states:\n  w:\n    do: {wait: {duration: 10 s}}\n    timeout: 2 s\n"
        "    on: {done: a}\n  a: {final: success}\n"
    )
    assert unrouted.result.outcome == "failure"
    assert unrouted.result.reason == "state 'w' timed out after 2 s"


def test_a_stalled_drive_fails_with_its_reason_when_not_routed() -> None:
    base = FakeBase()
    base.blocked = True
    runner = run(
        "states:\n  go:\n    do: {drive: {distance: 1 m}}\n    on: {done: end}\n"
        "  end: {final: success}\n",
        drive_base=base,
    )
    assert runner.result.outcome == "failure"
    assert runner.result.reason == "drive failed in state 'go': stalled"


def test_final_state_plays_its_action_before_ending() -> None:
    speaker = FakeSpeaker()
    runner = run(
        "states:\n  sad:\n    do: {play_tone: {frequency: 220 Hz, duration: 1 s}}\n"
        "    final: failure\n",
        speaker=speaker,
    )
    assert speaker.tones == [(220.0, 1.0)]
    assert runner.result.outcome == "failure"
    assert abs(runner.result.duration_s - 1.0) < 0.03


def test_guard_text_never_reaches_transitions_as_a_callback_name() -> None:
    spec, _ = parse_yaml_mission(
        "states:\n  a:\n    do: {wait: {duration: 0.1 s}}\n    on:\n      done:\n"
        '        - {if: "elapsed > 100", goto: b}\n        - {goto: b}\n  b: {final: success}\n'
    )
    runner = MissionRunner(spec, {})
    for event in runner._machine.events.values():
        for transitions in event.transitions.values():
            for transition in transitions:
                for condition in transition.conditions:
                    assert callable(condition.func), "only callables are handed to transitions"


# -------- What conditions read and how a mission ends, value by value
#
# What a mission's conditions read and how it ends, pinned value by value.
#
# Each test here fails when the runner reads a sensor through the wrong name or unit, measures
# the distance or the pose wrongly, or ends a mission in the wrong order: the changes mutation
# testing found that no other test noticed.


TRACK_MM = 160.0


class Base:
    """Wheels whose travel the test sets by hand, recording every call in order."""

    track_mm = TRACK_MM
    max_speed_mm_s = 300.0
    odometry_is_estimated = False

    def __init__(self, calls: list[str] | None = None) -> None:
        self.travel = [0.0, 0.0]
        self.speeds = (0.0, 0.0)
        self.calls = calls if calls is not None else []

    def set_wheel_speeds(self, left: float, right: float) -> None:
        self.speeds = (left, right)

    def stop(self) -> None:
        self.speeds = (0.0, 0.0)
        self.calls.append("wheels stopped")

    def wheel_distances_mm(self) -> tuple[float, float]:
        return self.travel[0], self.travel[1]


class Range:
    def __init__(self, reading_mm: float | None) -> None:
        self.reading_mm = reading_mm

    def distance_mm(self) -> float | None:
        return self.reading_mm


class Bumper:
    names = ("left", "right")

    def __init__(self) -> None:
        self.down: frozenset[str] = frozenset()

    def pressed(self) -> frozenset[str]:
        return self.down


class Line:
    dark_threshold = 500.0

    def __init__(self, names: tuple[str, ...], readings: tuple[float, ...] | None) -> None:
        self.names = names
        self.readings = readings

    def values(self) -> tuple[float, ...] | None:
        return self.readings


class Compass:
    def __init__(self, heading_deg: float | None) -> None:
        self.reading_deg = heading_deg

    def heading_deg(self) -> float | None:
        return self.reading_deg


TWO_STATES = """
states:
  first:
    when:
      - {if: visits.first > 5, goto: second}
  second:
    when:
      - {if: visits.second > 5, goto: end}
  end: {final: success}
"""


def _runner(text: str = TWO_STATES, /, **caps: object) -> MissionRunner:
    caps.setdefault("drive_base", Base())
    spec, _ = parse_yaml_mission(text)
    return MissionRunner(spec, caps)


def reads(runner: MissionRunner, condition: str) -> bool:
    """What a mission's ``when: {if: CONDITION}`` sees now."""
    return compile_guard(condition)(runner)


# ------------------------------------------------------------------------- driven and pose


def test_driven_counts_both_directions_in_mm_and_cm_and_restarts_in_each_state() -> None:
    base = Base()
    runner = _runner(drive_base=base)
    runner.tick(0.0, 0.02)
    base.travel = [100.0, 100.0]  # 10 cm ahead
    runner.tick(0.02, 0.02)
    base.travel = [40.0, 40.0]  # 6 cm back: 16 cm driven
    runner.tick(0.04, 0.02)
    assert reads(runner, "driven.total_mm == 160")
    assert reads(runner, "driven.total_cm == 16")
    assert reads(runner, "driven.state_mm == 160")
    assert reads(runner, "driven.state_cm == 16")
    # move on to the second state and drive 5 cm more there
    spec, _ = parse_yaml_mission(TWO_STATES.replace("visits.first > 5", "driven.total_cm > 15"))
    moving = MissionRunner(spec, {"drive_base": base})
    base.travel = [0.0, 0.0]
    moving.tick(0.0, 0.02)
    base.travel = [160.0, 160.0]
    moving.tick(0.02, 0.02)  # 16 cm: read before the conditions, which move on at once
    assert moving.state == "second"
    base.travel = [210.0, 210.0]
    moving.tick(0.04, 0.02)
    assert reads(moving, "driven.total_mm == 210")
    assert reads(moving, "driven.state_mm == 50")
    assert reads(moving, "driven.state_cm == 5")
    assert reads(moving, "driven.total_cm == 21")


def test_pose_follows_the_wheels_from_the_start_point() -> None:
    base = Base()
    runner = _runner(drive_base=base)
    runner.tick(0.0, 0.02)
    assert reads(runner, "pose.x_mm == 0 and pose.y_mm == 0 and pose.heading_deg == 0")
    base.travel = [300.0, 300.0]  # straight ahead 30 cm
    runner.tick(0.02, 0.02)
    assert reads(runner, "pose.y_mm == 300 and pose.x_mm == 0")
    # a quarter turn to the right on the spot: the left wheel forward, the right one back
    quarter_mm = math.pi * TRACK_MM / 4
    base.travel = [300.0 + quarter_mm, 300.0 - quarter_mm]
    runner.tick(0.04, 0.02)
    assert reads(runner, "pose.heading_deg > 89.999 and pose.heading_deg < 90.001")
    assert reads(runner, "heading_deg > 89.999 and heading_deg < 90.001")
    base.travel = [400.0 + quarter_mm, 400.0 - quarter_mm]  # 20 cm to the right now,
    runner.tick(0.06, 0.02)
    base.travel = [500.0 + quarter_mm, 500.0 - quarter_mm]  # in two ticks
    runner.tick(0.08, 0.02)
    assert reads(runner, "pose.x_mm > 199.999 and pose.x_mm < 200.001")
    assert reads(runner, "pose.y_mm > 299.999 and pose.y_mm < 300.001")


def test_an_arc_is_placed_along_its_chord() -> None:
    """One tick of an arc moves the robot along the mean of its two headings."""
    base = Base()
    runner = _runner(drive_base=base)
    runner.tick(0.0, 0.02)
    turn_mm = math.pi * TRACK_MM / 4  # a quarter turn to the right while driving 100 mm
    base.travel = [100.0 + turn_mm, 100.0 - turn_mm]
    runner.tick(0.02, 0.02)
    along = 100.0 / math.sqrt(2)  # at 45 degrees, the middle of 0 and 90
    assert reads(runner, f"pose.x_mm > {along - 0.001} and pose.x_mm < {along + 0.001}")
    assert reads(runner, f"pose.y_mm > {along - 0.001} and pose.y_mm < {along + 0.001}")


def test_a_compass_gives_the_heading_wrapped_to_plus_minus_180() -> None:
    compass = Compass(270.0)
    runner = _runner(heading=compass)
    runner.tick(0.0, 0.02)
    assert reads(runner, "heading_deg == -90")
    assert reads(runner, "pose.heading_deg == -90")
    compass.reading_deg = None  # no reading yet: straight ahead
    assert reads(runner, "heading_deg == 0")


def test_the_heading_counts_from_where_the_wheels_were_at_the_start() -> None:
    base = Base()
    base.travel = [1000.0, 2000.0]  # the encoders were not at zero when the mission began
    runner = _runner(drive_base=base)
    runner.tick(0.0, 0.02)
    assert reads(runner, "heading_deg == 0 and pose.x_mm == 0 and driven.total_mm == 0")


# --------------------------------------------------------------------------------- sensors


@pytest.mark.parametrize("root", ["range", "side_range"])
def test_a_distance_reads_in_mm_and_cm_and_no_echo_is_infinitely_far(root: str) -> None:
    sensor = Range(250.0)
    runner = _runner(**{root: sensor})
    runner.tick(0.0, 0.02)
    assert reads(runner, f"{root}.distance_mm == 250")
    assert reads(runner, f"{root}.distance_cm == 25")
    sensor.reading_mm = None
    assert reads(runner, f"{root}.distance_mm > 1000000")
    assert reads(runner, f"{root}.distance_cm > 1000000")


def test_range_and_side_range_are_two_sensors() -> None:
    runner = _runner(range=Range(100.0), side_range=Range(700.0))
    runner.tick(0.0, 0.02)
    assert reads(runner, "range.distance_mm == 100 and side_range.distance_mm == 700")


def test_bumpers_read_each_switch_and_any() -> None:
    bumper = Bumper()
    runner = _runner(bumper=bumper)
    runner.tick(0.0, 0.02)
    assert reads(runner, "not bumper.any and not bumper.left and not bumper.right")
    bumper.down = frozenset({"left"})
    assert reads(runner, "bumper.any and bumper.left and not bumper.right")


def test_line_sensors_read_each_value_and_any_over_the_dark_threshold() -> None:
    line = Line(("left", "center", "right"), (100.0, 500.0, 300.0))
    runner = _runner(line=line)
    runner.tick(0.0, 0.02)
    assert reads(runner, "line.left == 100 and line.center == 500 and line.right == 300")
    assert not reads(runner, "line.any")  # 500 is the threshold itself: not over it
    line.readings = (100.0, 501.0, 300.0)
    assert reads(runner, "line.any")
    line.readings = None  # no reading yet: all white
    assert reads(runner, "not line.any and line.left == 0")


def test_a_single_colour_sensor_reads_white_for_a_side_it_does_not_have() -> None:
    runner = _runner(line=Line(("center",), (900.0,)))
    runner.tick(0.0, 0.02)
    assert reads(runner, "line.center == 900 and line.left == 0 and line.any")


def test_elapsed_and_state_time_are_on_the_scheduler_clock() -> None:
    spec, _ = parse_yaml_mission(TWO_STATES.replace("visits.first > 5", "elapsed >= 1"))
    runner = MissionRunner(spec, {"drive_base": Base()})
    runner.tick(10.0, 0.5)  # the mission starts at 10 s on the scheduler's clock
    runner.tick(10.5, 0.5)
    assert reads(runner, "elapsed == 0.5 and state_time == 0.5")
    runner.tick(11.0, 0.5)
    assert runner.state == "second"
    runner.tick(11.5, 0.5)
    assert reads(runner, "elapsed == 1.5 and state_time == 0.5")
    assert runner.start_time_s == 10.0


# ------------------------------------------------------------------------ how it all ends

SPIN = '''\
from roboscript import Action, ActionContext, Result


class Spin(Action):
    """Spin on the spot until stopped."""

    name = "spin"
    requires = frozenset({"drive_base"})

    def start(self, ctx: ActionContext) -> None:
        ctx.drive_base.set_wheel_speeds(100.0, -100.0)

    def update(self, ctx: ActionContext) -> Result | None:
        return None

    def stop(self, ctx: ActionContext) -> None:
        STOP
'''


def _spinning(tmp_path: Path, stop: str, mission: str) -> tuple[MissionRunner, Base]:
    (tmp_path / "spin.py").write_text(SPIN.replace("STOP", stop), encoding="utf-8")
    path = tmp_path / "go.yaml"
    path.write_text(mission, encoding="utf-8")
    spec, _ = load_mission(path)
    base = Base()
    runner = MissionRunner(spec, {"drive_base": base})
    scheduler = Scheduler(SimClock(), 0.02)
    scheduler.add(runner)
    scheduler.run(until=lambda: runner.finished, max_duration_s=10)
    return runner, base


TIMES_OUT = """\
mission: go
behaviours: [spin.py]
states:
  go:
    do: {spin: {}}
    timeout: 0.1 s
    on: {done: end}
  end: {final: success}
"""

DURING = """\
mission: go
behaviours: [spin.py]
states:
  go:
    do: {wait: {duration: 0.1 s}}
    during: [{spin: {}}]
    on: {done: end}
  end: {final: success}
"""


def test_a_stop_that_raises_while_a_mission_fails_keeps_the_first_reason(tmp_path: Path) -> None:
    runner, base = _spinning(tmp_path, "raise RuntimeError('oops')", TIMES_OUT)
    assert runner.result.outcome == "failure"
    assert runner.result.reason == "state 'go' timed out after 0.1 s"
    assert runner.result.code_error  # the grader still scores the run as crashed
    assert runner.result.final_state == "go"
    assert base.speeds == (0.0, 0.0)


def test_a_stop_that_raises_in_a_during_action_fails_the_mission_naming_it(
    tmp_path: Path,
) -> None:
    runner, base = _spinning(tmp_path, "raise RuntimeError('oops')", DURING)
    assert runner.result.outcome == "failure"
    assert runner.result.reason is not None
    assert runner.result.reason.startswith(
        "your behaviour 'spin' raised RuntimeError in state 'go': oops ("
    )
    assert runner.result.code_error
    assert runner.result.final_state == "go"
    assert base.speeds == (0.0, 0.0)


def test_a_clean_stop_is_no_code_error(tmp_path: Path) -> None:
    runner, base = _spinning(tmp_path, "ctx.drive_base.stop()", TIMES_OUT)
    assert runner.result.outcome == "failure"
    assert not runner.result.code_error
    assert base.speeds == (0.0, 0.0)


class Order:
    """A ``during`` action and a main action that log when they are stopped."""

    def __init__(self, calls: list[str], name: str) -> None:
        self.calls = calls
        self.name = name

    def start(self, ctx: object) -> None:
        self.calls.append(f"{self.name} started")

    def update(self, ctx: object) -> None:
        return None

    def stop(self, ctx: object) -> None:
        self.calls.append(f"{self.name} stopped")


def test_finish_stops_the_during_actions_then_the_action_then_the_wheels() -> None:
    calls: list[str] = []
    spec, _ = parse_yaml_mission(
        "states:\n  go:\n    do: {wait: {duration: 5 s}}\n    during: [{wait: {duration: 5 s}}]\n"
        "    on: {done: end}\n  end: {final: success}\n"
    )
    state = spec.states["go"]
    assert state.action is not None
    object.__setattr__(state.action, "factory", lambda: Order(calls, "action"))
    object.__setattr__(state.during[0], "factory", lambda: Order(calls, "during"))
    base = Base(calls)
    runner = MissionRunner(spec, {"drive_base": base})
    runner.tick(0.0, 0.02)
    runner.tick(0.02, 0.02)
    assert not runner.finished
    runner.finish("error", "stopped by Ctrl-C")
    assert calls == [
        "action started",
        "during started",
        "during stopped",
        "action stopped",
        "wheels stopped",
    ]
    assert runner.finished
    assert runner.result.outcome == "error"
    assert runner.result.reason == "stopped by Ctrl-C"
    assert runner.result.final_state == "go"
    assert runner.result.duration_s == 0.02
    runner.finish("failure", "again")  # a second end changes nothing
    assert runner.result.outcome == "error"
    assert calls.count("wheels stopped") == 1


class BrokenStop(Order):
    def stop(self, ctx: object) -> None:
        raise LinkError("the link was lost")


def test_a_lost_link_while_stopping_the_action_reaches_the_caller_then_ends_in_error() -> None:
    calls: list[str] = []
    spec, _ = parse_yaml_mission(
        "states:\n  go:\n    do: {wait: {duration: 5 s}}\n    on: {done: end}\n"
        "  end: {final: success}\n"
    )
    state = spec.states["go"]
    assert state.action is not None
    object.__setattr__(state.action, "factory", lambda: BrokenStop(calls, "action"))
    runner = MissionRunner(spec, {"drive_base": Base(calls)})
    runner.tick(0.0, 0.02)
    with pytest.raises(LinkError):
        runner.finish("success")
    assert not runner.finished
    runner.finish("error", "the link was lost")  # the caller's own end: stops pass now
    assert runner.finished
    assert runner.result.outcome == "error"
    assert runner.result.reason == "the link was lost"


def test_a_final_state_ends_the_mission_on_the_tick_its_action_ends() -> None:
    spec, _ = parse_yaml_mission(
        "states:\n  go:\n    when:\n      - {if: elapsed >= 0.1, goto: end}\n"
        "  end:\n    final: success\n    do: {wait: {duration: 0.2 s}}\n"
    )
    runner = MissionRunner(spec, {"drive_base": Base()})
    scheduler = Scheduler(SimClock(), 0.02)
    scheduler.add(runner)
    scheduler.run(until=lambda: runner.finished, max_duration_s=10)
    assert runner.result.states == [(0.0, "go"), (0.1, "end")]
    assert runner.result.outcome == "success"
    assert runner.result.duration_s == 0.3


def test_a_during_action_that_ends_is_stopped_and_the_state_goes_on(tmp_path: Path) -> None:
    """``during: [spin]`` whose spin ends first: its stop() stops the wheels at once, while
    the state's own action runs on to its end."""
    behaviour = SPIN.replace("return None", "return Result.done()").replace(
        "STOP", "ctx.drive_base.stop()"
    )
    (tmp_path / "spin.py").write_text(behaviour, encoding="utf-8")
    path = tmp_path / "go.yaml"
    path.write_text(DURING.replace("0.1 s", "1 s"), encoding="utf-8")
    spec, _ = load_mission(path)
    base = Base()
    runner = MissionRunner(spec, {"drive_base": base})
    runner.tick(0.0, 0.02)  # the spin starts and ends on its first update
    assert base.calls == ["wheels stopped"]
    assert base.speeds == (0.0, 0.0)
    assert not runner.finished
    runner.tick(0.02, 0.02)
    assert base.calls == ["wheels stopped"]  # stopped once, not again on every tick
    assert runner.state == "go"


# ----------------------------------------------------------------- inner machines, regions

NESTED = """
states:
  first:
    when:
      - {if: driven.total_cm > 15, goto: inner}
  inner:
    do:
      initial: wait
      states:
        wait:
          when:
            - if: >-
                driven.state_mm == 50 and driven.state_cm == 5 and driven.total_mm == 250
                and driven.total_cm == 25 and pose.x_mm == 0 and pose.y_mm == 250
              goto: ok
            - {if: state_time > 0.1, goto: wrong}
        ok: {final: success}
        wrong: {final: failure}
    on: {done: end, failed: lost}
  end: {final: success}
  lost: {final: failure}
"""

TICK_S = 0.01234  # a tick that needs four decimals, to tell a time rounded to three


def test_an_inner_machine_reads_its_own_state_distance_and_the_missions_pose() -> None:
    spec, _ = parse_yaml_mission(NESTED)
    base = Base()
    seen: list[tuple[float, str]] = []
    runner = MissionRunner(
        spec, {"drive_base": base}, on_state=lambda t, s, _why: seen.append((t, s))
    )
    start_s = 100.0
    for step, travel_mm in enumerate([0.0, 160.0, 200.0, 250.0, 250.0, 250.0]):
        base.travel = [travel_mm, travel_mm]
        runner.tick(start_s + step * TICK_S, TICK_S)
    # the outer state was entered at 160 mm, the inner machine started at 200 mm
    names = [name for _, name in runner.result.states]
    assert names == ["first", "inner", "inner.wait", "inner.ok", "end"]
    times = [time_s for time_s, _ in runner.result.states]
    assert times == [0.0, 0.012, 0.025, 0.037, 0.037]  # 3 decimals: rounded to the ms
    assert [name for _, name in seen] == names
    assert [time_s for time_s, _ in seen] == pytest.approx(
        [0.0, TICK_S, 2 * TICK_S, 3 * TICK_S, 3 * TICK_S]
    )


class Spot:
    """A region holding one point of the world, give or take 1 mm."""

    def __init__(self, x_mm: float, y_mm: float) -> None:
        self.x_mm, self.y_mm = x_mm, y_mm

    def contains(self, x_mm: float, y_mm: float) -> bool:
        return math.hypot(x_mm - self.x_mm, y_mm - self.y_mm) < 1.0


def test_in_region_turns_and_moves_the_odometry_to_the_start_pose() -> None:
    """30 cm ahead, then 20 cm to the right, from (1000, 500) facing 30 degrees east of north."""
    h = math.radians(30.0)
    spot = Spot(
        1000 + 200 * math.cos(h) + 300 * math.sin(h), 500 - 200 * math.sin(h) + 300 * math.cos(h)
    )
    base = Base()
    runner = MissionRunner(
        parse_yaml_mission(TWO_STATES)[0],
        {"drive_base": base},
        regions={"spot": spot},
        origin=(1000.0, 500.0, 30.0),
    )
    runner.tick(0.0, 0.02)
    assert not runner.in_region("spot")
    quarter_mm = math.pi * TRACK_MM / 4
    for step, (left, right) in enumerate(
        [
            (300.0, 300.0),
            (300.0 + quarter_mm, 300.0 - quarter_mm),
            (500.0 + quarter_mm, 500.0 - quarter_mm),
        ]
    ):
        base.travel = [left, right]
        runner.tick(0.02 * (step + 1), 0.02)
    assert runner.in_region("spot")


def test_an_inner_machine_reads_the_regions_of_the_whole_mission() -> None:
    text = NESTED.replace(
        """driven.state_mm == 50 and driven.state_cm == 5 and driven.total_mm == 250
                and driven.total_cm == 25 and pose.x_mm == 0 and pose.y_mm == 250""",
        "in_region.spot",
    )
    spec, _ = parse_yaml_mission(text)
    base = Base()
    runner = MissionRunner(
        spec, {"drive_base": base}, regions={"spot": Spot(-250.0, 0.0)}, origin=(0.0, 0.0, -90.0)
    )
    for step, travel_mm in enumerate([0.0, 160.0, 200.0, 250.0, 250.0, 250.0]):
        base.travel = [travel_mm, travel_mm]
        runner.tick(step * 0.02, 0.02)
    assert [name for _, name in runner.result.states][-2:] == ["inner.ok", "end"]


def test_in_region_without_a_start_pose_or_a_region_says_what_is_missing() -> None:
    spec, _ = parse_yaml_mission(TWO_STATES)
    no_start = MissionRunner(spec, {"drive_base": Base()}, regions={"goal": Spot(0, 0)})
    with pytest.raises(LookupError) as info:
        no_start.in_region("goal")
    assert str(info.value) == (
        "in_region('goal') needs a world map, which a robot on a port does not have"
    )
    empty = MissionRunner(spec, {"drive_base": Base()}, regions={}, origin=(0.0, 0.0, 0.0))
    with pytest.raises(KeyError) as missing:
        empty.in_region("goal")
    assert missing.value.args == ("the world has no region 'goal' (its regions: none)",)
    two = MissionRunner(
        spec, {"drive_base": Base()}, regions={"b": Spot(0, 0), "a": Spot(0, 0)}, origin=(0, 0, 0)
    )
    with pytest.raises(KeyError) as other:
        two.in_region("goal")
    assert other.value.args == ("the world has no region 'goal' (its regions: a, b)",)


# --------------------------------------------------------------- reasons, and ending cleanly

FINAL_SPIN = """\
mission: go
behaviours: [spin.py]
states:
  go:
    when:
      - {if: elapsed >= 0.04, goto: end}
  end:
    final: success
    do: {spin: {}}
"""


def test_a_stop_that_raises_in_a_final_states_action_fails_the_mission(tmp_path: Path) -> None:
    behaviour = SPIN.replace("return None", "return Result.done()")
    (tmp_path / "spin.py").write_text(
        behaviour.replace("STOP", "raise RuntimeError('oops')"), encoding="utf-8"
    )
    path = tmp_path / "go.yaml"
    path.write_text(FINAL_SPIN, encoding="utf-8")
    spec, _ = load_mission(path)
    base = Base()
    runner = MissionRunner(spec, {"drive_base": base})
    for step in range(5):
        runner.tick(step * 0.02, 0.02)
    assert runner.finished
    assert runner.result.outcome == "failure"
    assert runner.result.reason is not None
    assert runner.result.reason.startswith(
        "your behaviour 'spin' raised RuntimeError in state 'end': oops ("
    )
    assert runner.result.code_error
    assert base.calls == ["wheels stopped"]


def test_a_during_action_stopped_cleanly_on_leaving_its_state_is_no_failure(
    tmp_path: Path,
) -> None:
    runner, base = _spinning(tmp_path, "ctx.drive_base.stop()", DURING)
    assert runner.result.outcome == "success"
    assert not runner.result.code_error
    assert base.speeds == (0.0, 0.0)


def _ended(text: str, **options: object) -> MissionRunner:
    spec, _ = parse_yaml_mission(text)
    runner = MissionRunner(spec, {"drive_base": Base()}, **options)  # type: ignore[arg-type]
    scheduler = Scheduler(SimClock(), 0.02)
    scheduler.add(runner)
    scheduler.run(until=lambda: runner.finished, max_duration_s=10)
    return runner


@pytest.mark.parametrize(
    ("text", "reason"),
    [
        (
            (
                "states:\n  go:\n    timeout: 0.1 s\n    on: {timeout: lost}\n"
                "  lost: {final: failure}\n"
            ),
            "ended in the failure state 'lost' after state 'go' timed out after 0.1 s",
        ),
        (
            (
                "states:\n  go:\n    when:\n      - {if: elapsed > 0.05, goto: lost}\n"
                "  lost: {final: failure}\n"
            ),
            "ended in the failure state 'lost' after 'elapsed > 0.05' held in state 'go'",
        ),
        (
            (
                "states:\n  go:\n    do: {wait: {duration: 0.1 s}}\n    on: {done: lost}\n"
                "  lost: {final: failure}\n"
            ),
            "ended in the failure state 'lost'",
        ),
        (
            (
                "states:\n  go:\n    do: {wait: {duration: 0.1 s}}\n    on: {done: lost}\n"
                "  lost:\n    final: failure\n    do: {wait: {duration: 0.1 s}}\n"
            ),
            "ended in the failure state 'lost'",
        ),
        (
            (
                "states:\n  go:\n    timeout: 0.1 s\n    on: {timeout: lost}\n"
                "  lost:\n    final: failure\n    do: {wait: {duration: 0.1 s}}\n"
            ),
            "ended in the failure state 'lost' after state 'go' timed out after 0.1 s",
        ),
        (
            (
                "states:\n  go:\n    do: {wait: {duration: 0.1 s}}\n"
                "    when:\n      - {if: elapsed > 5, goto: end}\n    on: {done: lost}\n"
                "  lost: {final: failure}\n  end: {final: success}\n"
            ),
            "ended in the failure state 'lost'",  # a condition that never held is no cause
        ),
        (
            (
                "states:\n  go:\n    do: {wait: {duration: 0.1 s}}\n    on: {done: end}\n"
                "  end: {final: success}\n"
            ),
            None,
        ),
        (
            (
                "states:\n  go:\n    do: {wait: {duration: 0.1 s}}\n    on: {done: end}\n"
                "  end:\n    final: success\n    do: {wait: {duration: 0.1 s}}\n"
            ),
            None,
        ),
    ],
)
def test_the_reason_a_mission_ended_names_the_state_and_what_led_there(
    text: str, reason: str | None
) -> None:
    runner = _ended(text)
    assert runner.result.outcome == ("success" if reason is None else "failure")
    assert runner.result.reason == reason


def test_on_start_gets_the_scheduler_time_the_mission_started() -> None:
    started: list[float] = []
    spec, _ = parse_yaml_mission(TWO_STATES)
    runner = MissionRunner(spec, {"drive_base": Base()}, on_start=started.append)
    assert runner.elapsed() == 0.0 and runner.start_time_s == 0.0  # not started yet
    runner.tick(7.5, 0.02)
    runner.tick(7.52, 0.02)
    assert started == [7.5]
    assert runner.elapsed() == 0.02


def test_an_error_the_robot_reports_fails_the_running_action_with_its_words() -> None:
    errors = iter([None, None, "motor 2 overheated"])
    runner = _ended(
        "states:\n  go:\n    do: {wait: {duration: 5 s}}\n    on: {done: end}\n"
        "  end: {final: success}\n",
        device_errors=lambda: next(errors, None),
    )
    assert runner.result.outcome == "failure"
    assert runner.result.reason == "wait failed in state 'go': motor 2 overheated"
    assert runner.result.duration_s == 0.04


def test_a_state_whose_action_is_done_still_times_out_on_time() -> None:
    runner = _ended(
        "states:\n  go:\n    do: {wait: {duration: 0.1 s}}\n    timeout: 0.1 s\n"
        "    on: {timeout: end}\n  end: {final: success}\n"
    )
    assert runner.result.states == [(0.0, "go"), (0.1, "end")]


def test_an_action_failing_as_its_state_times_out_ends_the_mission_there() -> None:
    """The failure ends the mission; the timeout of the same tick does not move it on."""
    errors = iter([None, None, None, None, None, "motor 2 overheated"])
    base = Base()
    spec, _ = parse_yaml_mission(
        "states:\n  go:\n    do: {wait: {duration: 5 s}}\n    timeout: 0.1 s\n"
        "    on: {timeout: away, done: away}\n"
        "  away:\n    do: {drive: {distance: 1 m}}\n    on: {done: end}\n"
        "  end: {final: success}\n"
    )
    runner = MissionRunner(spec, {"drive_base": base}, device_errors=lambda: next(errors, None))
    for step in range(8):
        runner.tick(step * 0.02, 0.02)
    assert runner.result.outcome == "failure"
    assert runner.result.final_state == "go"
    assert [name for _, name in runner.result.states] == ["go"]
    assert base.speeds == (0.0, 0.0)


def test_times_are_kept_to_the_microsecond() -> None:
    runner = _runner()
    runner.tick(1.0, 0.02)
    runner.tick(1.1234567, 0.02)
    assert runner.elapsed() == 0.123457
    runner.finish("error", "stopped")
    assert runner.result.duration_s == 0.123457


def test_the_record_carries_the_missions_name() -> None:
    spec, _ = parse_yaml_mission("mission: square\n" + TWO_STATES)
    assert MissionRunner(spec, {"drive_base": Base()}).result.mission == "square"


def test_a_missing_sensor_is_named_for_the_robot() -> None:
    anonymous = _runner()
    anonymous.tick(0.0, 0.02)
    with pytest.raises(CapabilityError) as info:
        reads(anonymous, "range.distance_mm < 20")
    assert str(info.value).startswith("the robot has no range (")
    spec, _ = parse_yaml_mission(TWO_STATES)
    named = MissionRunner(spec, {"drive_base": Base()}, robot_name="mirto")
    named.tick(0.0, 0.02)
    with pytest.raises(CapabilityError) as info:
        reads(named, "bumper.any")
    assert str(info.value).startswith("mirto has no bumper (")


def test_a_condition_without_its_text_is_named_condition_in_the_reason() -> None:
    """A mission built in code may give a guard without its text."""
    spec, _ = parse_yaml_mission(
        "states:\n  go:\n    when:\n      - {if: elapsed > 0.05, goto: lost}\n"
        "  lost: {final: failure}\n"
    )
    transition = spec.states["go"].when[0]
    object.__setattr__(transition, "guard_text", None)
    runner = MissionRunner(spec, {"drive_base": Base()})
    for step in range(5):
        runner.tick(step * 0.02, 0.02)
    assert runner.result.reason == (
        "ended in the failure state 'lost' after 'condition' held in state 'go'"
    )


def test_building_a_runner_logs_no_note_from_the_state_machine_library(
    caplog: pytest.LogCaptureFixture,
) -> None:
    caplog.set_level(logging.DEBUG)
    runner = _runner()
    runner.tick(0.0, 0.02)
    runner.tick(0.02, 0.02)
    assert not [r for r in caplog.records if "model override" in r.getMessage()]
