"""Graded runs recorded in the world's process, and the viewer in ``grade --html``."""

from __future__ import annotations

import itertools
import json
import re
from dataclasses import replace
from pathlib import Path
from typing import Any

import pytest
from browser import open_browser
from hand_graded import hand_report
from helpers import MISSIONS

from roboscript.grading.html_report import write_html
from roboscript.mission import mission_for_robot
from roboscript.replay.recording import fill_frames
from roboscript.replay.world_tap import WorldReplay
from roboscript.session import Session, run_session


def _graded_like(mission: Path, world: str, replay: bool) -> tuple[Session, dict[str, Any] | None]:
    """Run in-process, feeding a WorldReplay the way the world process does after each tick."""
    spec, profile, _ = mission_for_robot(mission)
    tap: WorldReplay | None = None

    def connected(robot: Any) -> None:
        nonlocal tap
        if replay:
            tap = WorldReplay(robot.simulation, profile)

    def ticked(runner: Any, robot: Any) -> None:
        if tap is not None:
            if runner.start_time_s and tap._start_s is None:
                tap.start(runner.start_time_s)
            tap.tick(robot.simulation.time_s, runner.state)

    session = run_session(spec, profile, world=world, on_connected=connected, on_tick=ticked)
    if tap is None:
        return session, None
    result = session.result
    data = tap.finish(
        mission=result.mission,
        outcome=result.outcome,
        final_state=result.final_state,
        reason=result.reason,
        duration_s=result.duration_s,
        states=tuple(result.states),
        now_s=session.start_time_s + result.duration_s,
    )
    return session, data


@pytest.fixture(scope="module")
def bump_replay() -> tuple[Session, dict[str, Any]]:
    session, data = _graded_like(MISSIONS / "bump_and_turn.yaml", "square-room", replay=True)
    assert data is not None
    return session, data


def test_recording_in_the_world_never_changes_the_run(
    bump_replay: tuple[Session, dict[str, Any]],
) -> None:
    plain, _ = _graded_like(MISSIONS / "bump_and_turn.yaml", "square-room", replay=False)
    assert bump_replay[0].final_pose() == plain.final_pose()
    assert bump_replay[0].result.states == plain.result.states


def test_a_graded_run_keeps_ten_frames_a_second_and_every_state(
    bump_replay: tuple[Session, dict[str, Any]],
) -> None:
    session, data = bump_replay
    frames = fill_frames(data["frames"])
    gaps = [b["t"] - a["t"] for a, b in itertools.pairwise(frames)]
    assert max(gaps) <= 0.1 + 1e-6
    assert len(frames) <= session.result.duration_s * 10 + len(session.result.states) + 2
    entered = []
    for frame in frames:
        if not entered or entered[-1] != frame["state"]:
            entered.append(frame["state"])
    assert entered == [name for _, name in session.result.states]
    assert frames[-1]["pose"] == list(session.final_pose())
    assert [f["tone"] for f in frames if "tone" in f] == [[660.0, 0.3]]
    assert data["header"]["mission"]["name"] == "bump-and-turn"
    assert data["result"]["outcome"] == "success"
    # the wheels' own speeds, in run --record's fields and units (mm/s), up to the top speed
    speeds = [f["motors"]["left_mm_s"] for f in frames]
    top_mm_s = data["header"]["robot"]["max_speed_mm_s"]
    assert max(speeds) > 50 and all(abs(s) <= top_mm_s + 1e-6 for s in speeds)


def test_the_range_shown_is_the_sensors_last_measurement(
    bump_replay: tuple[Session, dict[str, Any]],
) -> None:
    frames = fill_frames(bump_replay[1]["frames"])
    turns = [
        frames[i]
        for i in range(1, len(frames))
        if frames[i]["state"] == "turn" and frames[i - 1]["state"] == "forward"
    ]
    assert turns
    # the mission turned on "range.distance_cm < 25": the world saw the same echo
    assert all(
        f["sensors"]["range_mm"] is not None and f["sensors"]["range_mm"] < 260 for f in turns
    )


def _with_replays(report: Any, data: dict[str, Any]) -> Any:
    results = [replace(r, replay=data) if r.record is not None else r for r in report.results]
    return replace(report, results=results)


def _embedded(html: str) -> dict[str, Any]:
    found = re.search(r'class="rs-data">(.*?)</script>', html)
    assert found is not None, "no embedded replay"
    data: dict[str, Any] = json.loads(found.group(1))
    return data


def test_grade_html_embeds_the_viewer_opening_at_the_first_failure(
    bump_replay: tuple[Session, dict[str, Any]], tmp_path: Path
) -> None:
    report = _with_replays(hand_report(tmp_path), bump_replay[1])
    out = write_html(report, tmp_path / "html").parent
    failed_page = out / "runs" / "Quentin--square-50cm--3.html"
    html = failed_page.read_text(encoding="utf-8")
    assert html.count('class="rs-viewer"') == 1
    assert html.count("rs-viewer {") <= 1 and html.count("roboscript replay viewer") == 2  # once
    data = _embedded(html)
    assert data["open_at_s"] == 10.0  # the pose verdict's first violation
    assert data["marks"] == [{"t": 10.0, "label": "final_pose_within"}]
    passed_page = (out / "runs" / "Zelda--square-50cm--1.html").read_text(encoding="utf-8")
    assert "open_at_s" not in _embedded(passed_page)  # nothing failed: it opens at the start
    crashed = (out / "runs" / "Quentin--square-50cm--2.html").read_text(encoding="utf-8")
    assert "rs-viewer" not in crashed  # no record, no replay


def test_a_students_page_replays_visible_runs_only(
    bump_replay: tuple[Session, dict[str, Any]], tmp_path: Path
) -> None:
    report = _with_replays(hand_report(tmp_path), bump_replay[1])
    out = write_html(report, tmp_path / "html").parent
    student = (out / "students" / "Quentin.html").read_text(encoding="utf-8")
    assert student.count('class="rs-viewer"') == 1  # run 1; run 2 crashed, run 3 is hidden
    assert student.count("roboscript replay viewer") == 2  # the script and styles, once each
    index = (out / "index.html").read_text(encoding="utf-8")
    assert "rs-viewer" not in index


def test_the_report_viewer_opens_at_the_failure_in_a_browser(
    bump_replay: tuple[Session, dict[str, Any]], tmp_path: Path
) -> None:
    report = _with_replays(hand_report(tmp_path), bump_replay[1])
    out = write_html(report, tmp_path / "html").parent
    page = out / "runs" / "Quentin--square-50cm--3.html"
    frames = fill_frames(bump_replay[1]["frames"])
    at_10s = [f for f in frames if f["t"] <= 10.0][-1]
    with open_browser(tmp_path) as browser:
        browser.open(page.as_uri())
        browser.wait_for("document.querySelector('.rs-viewer').dataset.ready === '1'")
        shown = browser.evaluate("document.querySelector('[data-role=time]').textContent")
        assert shown == f"{at_10s['t']:.2f} s"
        state = browser.evaluate("document.querySelector('[data-role=state]').textContent")
        assert state == at_10s["state"]
        assert browser.errors == []


def test_a_line_follower_is_seen_over_the_tape() -> None:
    session, data = _graded_like(MISSIONS / "line_lap.yaml", "line-track", replay=True)
    assert data is not None and session.result.outcome == "success"
    frames = fill_frames(data["frames"])
    centre = [f["sensors"]["line"][1] for f in frames]
    assert sum(v > 500 for v in centre) > 0.8 * len(centre)  # following: over the tape
    assert all(90 <= v <= 850 for f in frames for v in f["sensors"]["line"])
