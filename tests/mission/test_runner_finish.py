"""How a mission ends: the robot is stopped before the mission counts as finished, and the
record of a mission that loops for hours stays bounded."""

from __future__ import annotations

import pytest

from roboscript.clock import SimClock
from roboscript.errors import LinkError
from roboscript.mission.runner import STATES_KEPT_AT_EACH_END, MissionRunner
from roboscript.mission.yaml_loader import parse_yaml_mission
from roboscript.scheduler import Scheduler

DRIVE = """
states:
  go:
    do: {drive: {distance: 5 m}}
    on: {done: end}
  end: {final: success}
"""


class LosingBase:
    """A drive base whose link is lost when it is told to stop (the first ``failures`` times)."""

    track_mm = 160.0
    max_speed_mm_s = 300.0
    odometry_is_estimated = False

    def __init__(self, failures: int) -> None:
        self.failures = failures
        self.speeds = (0.0, 0.0)

    def set_wheel_speeds(self, left: float, right: float) -> None:
        self.speeds = (left, right)

    def stop(self) -> None:
        if self.failures > 0:
            self.failures -= 1
            raise LinkError("the connection to sim://mirto was lost 1.2 s after connecting")
        self.speeds = (0.0, 0.0)

    def wheel_distances_mm(self) -> tuple[float, float]:
        return 0.0, 0.0


def _driving(base: LosingBase) -> MissionRunner:
    spec, _ = parse_yaml_mission(DRIVE)
    runner = MissionRunner(spec, {"drive_base": base})
    for step in range(5):
        runner.tick(step * 0.02, 0.02)
    assert base.speeds != (0.0, 0.0)
    return runner


@pytest.mark.parametrize("failures", [1, 99])
def test_a_link_lost_while_stopping_ends_the_mission_in_error_with_the_links_reason(
    failures: int,
) -> None:
    runner = _driving(LosingBase(failures))
    with pytest.raises(LinkError):
        runner.finish("success")
    assert not runner.finished  # not stopped, so not finished: the caller says why
    runner.finish("error", "the connection to sim://mirto was lost 1.2 s after connecting")
    assert runner.finished
    assert runner.result.outcome == "error"
    assert runner.result.reason == "the connection to sim://mirto was lost 1.2 s after connecting"
    assert runner.result.final_state == "go"


def test_the_second_finish_stops_the_wheels_when_the_link_is_back() -> None:
    base = LosingBase(1)
    runner = _driving(base)
    with pytest.raises(LinkError):
        runner.finish("failure", "stop")
    runner.finish("error", "lost")
    assert base.speeds == (0.0, 0.0)


LOOP = """
states:
  a:
    do: {wait: {duration: 0.02 s}}
    on: {done: b}
  b:
    do: {wait: {duration: 0.02 s}}
    on:
      done:
        - {if: "visits.a >= LIMIT", goto: end}
        - {goto: a}
  end: {final: success}
"""


class StillBase(LosingBase):
    def __init__(self) -> None:
        super().__init__(0)


def test_a_long_loop_keeps_the_first_and_last_states_and_counts_the_rest() -> None:
    loops = STATES_KEPT_AT_EACH_END * 2
    spec, _ = parse_yaml_mission(LOOP.replace("LIMIT", str(loops)))
    runner = MissionRunner(spec, {"drive_base": StillBase()})
    scheduler = Scheduler(SimClock(), 0.02)
    scheduler.add(runner)
    scheduler.run(until=lambda: runner.finished, max_duration_s=10_000)
    result = runner.result
    entered = 2 * loops + 1  # a, b per loop, then end
    assert result.outcome == "success"
    assert runner.visits("a") == loops  # counts stay exact
    assert len(result.states) == 2 * STATES_KEPT_AT_EACH_END
    assert result.states_dropped == entered - 2 * STATES_KEPT_AT_EACH_END
    assert [name for _, name in result.states[:4]] == ["a", "b", "a", "b"]
    assert result.states[0][0] == 0.0
    assert result.states[-1][1] == "end"
    assert result.states[-1][0] == result.duration_s
    times = [t for t, _ in result.states]
    assert times == sorted(times)
    # the gap is between the halves: the last kept early state and the first kept late one
    gap = times[STATES_KEPT_AT_EACH_END] - times[STATES_KEPT_AT_EACH_END - 1]
    assert gap > result.states_dropped * 0.02 * 0.9


def test_a_short_mission_keeps_every_state() -> None:
    spec, _ = parse_yaml_mission(LOOP.replace("LIMIT", "3"))
    runner = MissionRunner(spec, {"drive_base": StillBase()})
    scheduler = Scheduler(SimClock(), 0.02)
    scheduler.add(runner)
    scheduler.run(until=lambda: runner.finished, max_duration_s=100)
    assert [name for _, name in runner.result.states] == ["a", "b"] * 3 + ["end"]
    assert runner.result.states_dropped == 0
