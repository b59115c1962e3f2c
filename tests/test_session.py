"""A session: one mission run on one robot, from the first tick to the stopped robot."""

from __future__ import annotations

import dataclasses
import signal
from pathlib import Path

import pytest
from helpers import LOGGING_MISSION, MISSIONS

from roboscript.clock import SimClock
from roboscript.interrupts import Interrupted
from roboscript.mission import mission_for_robot
from roboscript.replay.session_tap import RunRecording
from roboscript.session import run_session

LATE_S = 0.03
"""How late a busy machine wakes the loop for each tick (less than a tick's 20 ms apart)."""


@pytest.mark.parametrize("max_time_s", [0.5, 2.0])
def test_a_mission_out_of_time_ran_its_whole_limit_on_a_busy_machine(
    monkeypatch: pytest.MonkeyPatch, max_time_s: float
) -> None:
    # Every wake-up comes late, the first one too: the limit is counted on the mission's own
    # clock, from its first tick, so the run it reports is never shorter than its limit.
    def late(clock: SimClock, deadline_s: float) -> None:
        clock._now = max(clock._now, deadline_s + LATE_S)

    monkeypatch.setattr(SimClock, "sleep_until", late)
    spec, profile, _ = mission_for_robot(MISSIONS / "square.yaml")
    result = run_session(spec, profile, max_time_s=max_time_s).result
    assert result.reason == f"the mission did not finish within {max_time_s:g} s"
    assert max_time_s <= result.duration_s < max_time_s + 0.1


def test_what_the_mission_prints_reaches_the_recording_and_the_print_hook_alike(
    tmp_path: Path,
) -> None:
    mission = tmp_path / "logged.py"
    mission.write_text(LOGGING_MISSION, encoding="utf-8")
    spec, profile, _ = mission_for_robot(mission)
    told: list[str] = []
    recording = RunRecording()
    run_session(spec, profile, recording=recording, on_print=told.append)
    assert recording.recorder is not None
    recorded = [line for f in recording.recorder.frames for line in f.get("print", [])]
    assert told == recorded == ["one second in"]


def test_a_run_out_of_time_round_a_loop_names_the_states_it_kept_entering(
    tmp_path: Path,
) -> None:
    path = tmp_path / "loop.yaml"
    path.write_text(
        "mission: loop\nstates:\n  go:\n    do: {drive: {distance: 10 cm}}\n"
        "    on: {done: turn, failed: end}\n  turn:\n    do: {rotate: {angle: 90 deg}}\n"
        "    on: {done: go, failed: end}\n  end: {final: success}\n",
        encoding="utf-8",
    )
    spec, profile, _ = mission_for_robot(path)
    result = run_session(spec, profile, max_time_s=20.0).result
    assert result.outcome == "failure"
    assert (result.reason or "").startswith(
        "the mission did not finish within 20 s: it kept going round, 'go' entered"
    )
    assert (result.reason or "").endswith(
        "(a loop needs a way out to a final state, e.g. a when condition on visits.go)"
    )


def test_a_runs_interruption_and_its_exit_status_are_read_from_the_one_signal_that_ended_it(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    # the status is no second fact kept beside the signal's exception: it cannot disagree
    def terminated(clock: SimClock, deadline_s: float) -> None:
        if deadline_s > 0.5:
            raise Interrupted(signal.SIGTERM)
        clock._now = max(clock._now, deadline_s)

    monkeypatch.setattr(SimClock, "sleep_until", terminated)
    spec, profile, _ = mission_for_robot(MISSIONS / "square.yaml")
    session = run_session(spec, profile, max_time_s=2.0)
    assert isinstance(session.interrupted_by, Interrupted)
    assert session.interruption is not None
    assert (session.interrupted, session.interruption.signum) == (143, signal.SIGTERM)
    assert dataclasses.replace(session, interrupted_by=None).interrupted == 0
