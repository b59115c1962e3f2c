"""The mission runner on fake capabilities (no robot, no simulator): routing and timing."""

from __future__ import annotations

from roboscript.clock import SimClock
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
