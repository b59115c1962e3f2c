"""A mission run as one state of another, in process.

The nested-state tests in ``test_composition.py`` run ``roboscript`` in a child process; these
run the outer machine here, with a behaviour that records what its inner machine gives it and
when it is stopped.
"""

from __future__ import annotations

from collections.abc import Iterator

import pytest

from roboscript import Action, ActionContext, Mission, Result, state
from roboscript.mission.python_compiler import compile_mission
from roboscript.mission.runner import MissionRunner
from roboscript.mission.yaml_loader import parse_yaml_mission

TICK_S = 0.1
GAINS = {"heading": (1.5, 0.25, 0.05)}


class Record(Action):
    """Runs until stopped (or until ``ticks`` updates), writing down what it saw."""

    name = "record"
    events: list[object] = []  # noqa: RUF012 - shared by the copies the runner makes
    ticks = 0  # 0: never ends on its own

    def start(self, ctx: ActionContext) -> None:
        self.seen = 0
        self.events.append(("started", ctx.robot_name, ctx.gain("heading", (0.0, 0.0, 0.0))))

    def update(self, ctx: ActionContext) -> Result | None:
        self.events.append(("tick", ctx.dt_s))
        self.seen += 1
        return Result.done() if self.seen == self.ticks else None

    def stop(self, ctx: ActionContext) -> None:
        self.events.append("stopped")


class Endless(Mission):
    work = state(Record(), initial=True, on_done="home")
    home = state(final="success")


class Patrol(Mission):
    """Gives its inner mission half a second."""

    patrol = state(Endless, initial=True, timeout_s=0.5, on_timeout="sad", on_done="happy")
    happy = state(final="success")
    sad = state(final="failure")


class Stumbles(Mission):
    first = state(Record(), initial=True, on_done="oops")
    oops = state(final="failure")


class Outer(Mission):
    patrol = state(Stumbles, initial=True, on_done="happy", on_failed="sad")
    happy = state(final="success")
    sad = state(final="failure")


@pytest.fixture(autouse=True)
def fresh_record() -> Iterator[None]:
    Record.events = []
    yield
    Record.ticks = 0


def run(cls: type[Mission], ticks: int) -> MissionRunner:
    spec, _ = compile_mission(cls)
    runner = MissionRunner(spec, {}, robot_name="Mirto", gains=GAINS)
    for n in range(ticks):
        runner.tick(round(n * TICK_S, 6), TICK_S)
        if runner.finished:
            break
    return runner


def test_the_inner_behaviour_sees_the_robot_its_gains_and_the_tick() -> None:
    runner = run(Patrol, 3)
    assert not runner.finished
    assert Record.events[0] == ("started", "Mirto", (1.5, 0.25, 0.05))
    assert Record.events[1:] == [("tick", TICK_S)] * 3


def test_the_status_line_shows_the_inner_state() -> None:
    runner = run(Patrol, 2)
    assert runner.state == "patrol"
    assert runner.action.feedback == "patrol.work"


def test_a_timed_out_outer_state_stops_the_inner_behaviour() -> None:
    """Else a tone, a motor or a student's behaviour would run on past its state."""
    runner = run(Patrol, 20)
    assert runner.finished and runner.result.outcome == "failure"
    assert runner.result.reason == (
        "ended in the failure state 'sad' after state 'patrol' timed out after 0.5 s"
    )
    assert Record.events.count("stopped") == 1
    assert Record.events[-1] == "stopped"
    assert [name for _, name in runner.result.states] == ["patrol", "patrol.work", "sad"]


def test_an_inner_failure_state_gives_its_reason_to_the_outer_mission() -> None:
    Record.ticks = 2
    runner = run(Outer, 10)
    assert runner.result.outcome == "failure"
    assert runner.result.reason == (
        "ended in the failure state 'sad' after states failed in state 'patrol':"
        " ended in the failure state 'oops'"
    )
    assert Record.events.count("stopped") == 1


REPEATED = """
states:
  loop:
    do:
      repeat:
        times: 2
        do:
          initial: a
          states:
            a:
              do: {wait: {duration: 0.2 s}}
              on: {done: bad}
            bad: {final: failure}
    on: {done: end, failed: sad}
  end: {final: success}
  sad: {final: failure}
"""


def test_an_inner_machine_that_fails_inside_a_repeat_ends_the_mission_cleanly() -> None:
    """The repeat stops its failed run once; leaving the state stops nothing more."""
    spec, _ = parse_yaml_mission(REPEATED)
    runner = MissionRunner(spec, {})
    for n in range(10):
        runner.tick(round(n * TICK_S, 6), TICK_S)
    assert runner.finished
    assert runner.result.reason == (
        "ended in the failure state 'sad' after repeat failed in state 'loop':"
        " ended in the failure state 'bad'"
    )
    assert runner.result.states == [
        (0.0, "loop"),
        (0.0, "loop.a"),
        (0.2, "loop.bad"),
        (0.2, "sad"),
    ]
