"""parallel and repeat: which child's ending ends the whole, and every child stopped."""

from __future__ import annotations

import re

import pytest

from roboscript import Drive, PlayTone, Rotate
from roboscript import capabilities as cap
from roboscript.actions import ActionContext, Outcome, Result, Stop
from roboscript.actions.base import Action, UnderSpecifiedError
from roboscript.actions.composite import Parallel, Repeat
from roboscript.mission.limits import MAX_TIME_S
from roboscript.robot import DEFAULT_PERIOD_S


class Log(list[str]):
    """The lifecycle log, shared by every copy a composite makes of its children."""

    def __deepcopy__(self, memo: object) -> Log:
        return self


class Scripted(Action):
    """Ends with ``result`` after ``ticks`` updates (``None``: never); logs its lifecycle."""

    name = "scripted"
    requires = frozenset({cap.SPEAKER})

    def __init__(self, ticks: int | None, result: Result, log: list[str], label: str) -> None:
        self.ticks = ticks
        self.result = result
        self.log = log
        self.label = label
        self.updates = 0
        self.history: list[float] = []

    def start(self, ctx: ActionContext) -> None:
        self.updates = 0
        self.log.append(f"start {self.label} at {ctx.now_s:g}")

    def update(self, ctx: ActionContext) -> Result | None:
        self.updates += 1
        self.history.append(ctx.now_s)
        self.feedback = f"{self.label} {self.updates}"
        if self.ticks is not None and self.updates >= self.ticks:
            return self.result
        return None

    def stop(self, ctx: ActionContext) -> None:
        self.log.append(f"stop {self.label} at {ctx.now_s:g}")


class Driving(Scripted):
    name = "driving"
    requires = frozenset({cap.DRIVE_BASE})


def run(action: Action, limit: int = 50) -> tuple[Result | None, int]:
    """Tick ``action`` at 1 Hz from 0 s; log lines read "start a at 0", "stop a at 2"."""
    ctx = ActionContext({})
    action.start(ctx)
    for tick in range(1, limit + 1):
        ctx.now_s = float(tick)
        result = action.update(ctx)
        if result is not None:
            return result, tick
    action.stop(ctx)
    return None, limit


DONE = Result.done()


def test_parallel_all_is_done_when_every_child_is_and_stops_each_once() -> None:
    log = Log()
    both = Parallel([Scripted(2, DONE, log, "a"), Scripted(4, DONE, log, "b")])
    assert run(both) == (DONE, 4)
    assert log == ["start a at 0", "start b at 0", "stop a at 2", "stop b at 4"]


def test_parallel_all_fails_with_the_first_failing_child_and_stops_the_others() -> None:
    log = Log()
    both = Parallel(
        [
            Scripted(None, DONE, log, "tune"),
            Driving(3, Result.failed("stalled"), log, "drive"),
            Scripted(1, DONE, log, "led"),
        ]
    )
    assert run(both) == (Result.failed("driving: stalled"), 3)
    assert log == [
        "start tune at 0",
        "start drive at 0",
        "start led at 0",
        "stop led at 1",
        "stop drive at 3",
        "stop tune at 3",
    ]


def test_parallel_all_names_a_child_timeout_by_its_outcome_when_it_gives_no_reason() -> None:
    log = Log()
    both = Parallel([Scripted(2, Result(Outcome.TIMEOUT), log, "a"), Scripted(9, DONE, log, "b")])
    assert run(both) == (Result.failed("scripted: timeout"), 2)


def test_parallel_any_is_done_with_the_first_child_done_and_stops_the_rest() -> None:
    log = Log()
    race = Parallel(
        [
            Scripted(1, Result.failed("lost line"), log, "a"),
            Scripted(3, DONE, log, "b"),
            Scripted(None, DONE, log, "c"),
        ],
        mode="any",
    )
    assert run(race) == (DONE, 3)
    assert log == [
        "start a at 0",
        "start b at 0",
        "start c at 0",
        "stop a at 1",
        "stop b at 3",
        "stop c at 3",
    ]


def test_parallel_any_fails_only_when_every_child_failed_naming_the_first() -> None:
    log = Log()
    race = Parallel(
        [
            Scripted(1, Result.failed("lost line"), log, "a"),
            Scripted(2, Result.failed("x"), log, "b"),
        ],
        mode="any",
    )
    assert run(race) == (Result.failed("every action failed (first: lost line)"), 2)


def test_parallel_shows_the_running_childrens_progress() -> None:
    log = Log()
    both = Parallel([Scripted(None, DONE, log, "a"), Scripted(None, DONE, log, "b")])
    ctx = ActionContext({})
    both.start(ctx)
    both.update(ctx)
    both.update(ctx)
    assert both.feedback == "a 2 | b 2"
    both.stop(ctx)
    assert log[-2:] == ["stop a at 0", "stop b at 0"]


def test_parallel_starts_fresh_copies_each_time_its_state_is_entered() -> None:
    log = Log()
    template = Scripted(2, DONE, log, "a")
    both = Parallel([template])
    assert run(both) == (DONE, 2)
    assert run(both) == (DONE, 2)  # not ended at once by the first run's count
    assert (template.updates, template.history) == (0, [])  # the template is never run


def test_parallel_needs_the_capabilities_of_its_children() -> None:
    log = Log()
    both = Parallel(
        [
            Scripted(1, DONE, log, "a"),
            Driving(1, DONE, log, "b"),
            lambda: Driving(1, DONE, log, "c"),
        ]
    )
    assert both.child_requires == frozenset({cap.SPEAKER, cap.DRIVE_BASE})
    nested = Parallel([Repeat(Driving(1, DONE, log, "d"), times=2)])
    assert nested.child_requires == frozenset({cap.DRIVE_BASE})


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (
            ([], "all"),
            (
                "parallel needs at least one action"
                " (write Parallel([Drive(distance_mm=500), PlayTone(frequency_hz=880)]))"
            ),
        ),
        (
            ([Stop()], "first"),
            (
                "parallel runs 'all' or 'any' (write Parallel([Drive(distance_mm=500),"
                ' PlayTone(frequency_hz=880)], mode="any"))'
            ),
        ),
    ],
)
def test_parallel_refuses_an_empty_list_or_an_unknown_mode(
    args: tuple[list[Action], str], message: str
) -> None:
    with pytest.raises(ValueError) as refused:
        Parallel(*args)
    assert str(refused.value) == message


def test_repeat_runs_its_action_the_given_number_of_times_afresh() -> None:
    log = Log()
    square = Repeat(Scripted(2, DONE, log, "side"), times=3)
    assert run(square) == (DONE, 6)
    assert log == [
        "start side at 0",
        "stop side at 2",
        "start side at 2",
        "stop side at 4",
        "start side at 4",
        "stop side at 6",
    ]
    assert square.count == 3


def test_repeat_shows_which_run_it_is_on() -> None:
    log = Log()
    square = Repeat(Scripted(2, DONE, log, "side"), times=4)
    ctx = ActionContext({})
    square.start(ctx)
    square.update(ctx)
    assert square.feedback == "1/4: side 1"
    square.update(ctx)
    square.update(ctx)
    assert square.feedback == "2/4: side 1"
    square.stop(ctx)
    assert log[-1] == "stop side at 0"
    square.stop(ctx)  # leaving twice stops the child once
    assert log.count("stop side at 0") == 2


def test_repeat_ends_with_the_first_run_that_is_not_done() -> None:
    log = Log()
    runs = iter([DONE, Result.failed("stalled")])
    square = Repeat(lambda: Scripted(2, next(runs), log, "side"), times=4)
    assert run(square) == (Result.failed("stalled"), 4)
    assert log == ["start side at 0", "stop side at 2", "start side at 2", "stop side at 4"]


def test_repeat_starts_from_the_first_run_when_its_state_is_entered_again() -> None:
    log = Log()
    square = Repeat(Scripted(1, DONE, log, "side"), times=2)
    assert run(square) == (DONE, 2)
    assert run(square) == (DONE, 2)


def test_repeat_needs_at_least_one_run_and_its_actions_capabilities() -> None:
    log = Log()
    with pytest.raises(ValueError) as refused:
        Repeat(Scripted(1, DONE, log, "a"), times=0)
    assert str(refused.value) == (
        "repeat times: 0 would not run the action at all (at least 1)"
        " (write Repeat(Scripted(...), times=4))"
    )
    assert Repeat(Driving(1, DONE, log, "a"), times=1).child_requires == {cap.DRIVE_BASE}


def test_leaving_a_finished_parallel_does_not_stop_its_children_again() -> None:
    log = Log()
    both = Parallel([Scripted(1, Result.failed("x"), log, "a"), Scripted(None, DONE, log, "b")])
    assert run(both) == (Result.failed("scripted: x"), 1)
    both.stop(ActionContext({}))
    assert log == ["start a at 0", "start b at 0", "stop a at 1", "stop b at 1"]


def test_leaving_a_finished_repeat_stops_nothing_more() -> None:
    log = Log()
    twice = Repeat(Scripted(1, DONE, log, "a"), times=2)
    assert run(twice) == (DONE, 2)
    twice.stop(ActionContext({}))
    assert log.count("stop a at 2") == 1


def test_leaving_a_repeat_whose_run_failed_stops_that_run_once() -> None:
    log = Log()
    square = Repeat(Scripted(2, Result.failed("stalled"), log, "side"), times=4)
    assert run(square) == (Result.failed("stalled"), 2)
    square.stop(ActionContext({}))
    assert log == ["start side at 0", "stop side at 2"]


def test_parallel_of_actions_without_brackets_names_them_in_the_fix() -> None:
    with pytest.raises(UnderSpecifiedError) as refused:
        Parallel(Drive(distance_mm=500), Rotate(angle_deg=90), PlayTone(frequency_hz=880))  # type: ignore[call-arg]
    assert str(refused.value) == (
        "parallel takes a list of actions, in [ ] (write Parallel([Drive(distance_mm=500),"
        " Rotate(angle_deg=90), PlayTone(frequency_hz=880)]))"
    )


def test_repeat_of_two_actions_says_a_repeat_runs_one() -> None:
    with pytest.raises(UnderSpecifiedError, match=r"^repeat runs one action"):
        Repeat(Rotate(angle_deg=90), Drive(distance_mm=100))  # type: ignore[arg-type]
    with pytest.raises(UnderSpecifiedError, match=r"^repeat runs one action"):
        Repeat(Rotate(angle_deg=90), Drive(distance_mm=100), 4)  # type: ignore[call-arg]


@pytest.mark.parametrize(
    ("times", "refused"),
    [
        (Repeat.most_times + 1, "runs cannot finish within a mission's longest run"),
        (10**40, "repeat times: so many runs cannot finish"),
        (-2, "repeat times: -2 is not a number of runs"),
        (2.5, "and 2.5 is not one"),
        (4.0, "a whole number has no decimal point"),
        (float("nan"), "and nan is not one"),
        (True, "and True is not a number"),
        ("4", "written without quotes"),
    ],
)
def test_repeat_refuses_times_that_are_not_a_whole_number_of_runs_within_an_hour(
    times: object, refused: str
) -> None:
    with pytest.raises(ValueError, match=re.escape(refused)):
        Repeat(Scripted(1, DONE, Log(), "a"), times=times)  # type: ignore[arg-type]


def test_repeat_allows_as_many_runs_as_an_hour_of_ticks_holds() -> None:
    assert Repeat.most_times == int(MAX_TIME_S / DEFAULT_PERIOD_S)
    assert Repeat(Scripted(1, DONE, Log(), "a"), times=Repeat.most_times).times == 180_000
