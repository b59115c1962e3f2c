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


# What a graded recording has that run --record's has not, and the reverse: each on purpose.
GRADED_ONLY = {
    # a graded run keeps at most 10 frames a second, and names the mission's own account
    "header": {"frame_rate_hz", "claimed"},
    "frame": set(),
    "why": {"claimed"},  # the cause is the mission's own account, and the page says so
}
RUN_ONLY = {
    "header": set(),
    "mission": {"path"},  # the student's file stays the grader's business
    # the action's outcome is known only in the mission's process (``why.kind`` says it at
    # each transition); log/print too, and they are absent here as this mission has none
    "frame": {"outcome"},
    "why": set(),
}


def _keys(items: list[dict[str, Any]], part: str | None = None) -> set[str]:
    found: set[str] = set()
    for item in items:
        found |= set(item if part is None else item.get(part) or {})
    return found


def _transitions(frames: list[dict[str, Any]]) -> list[tuple[float, str, str]]:
    """(t, state, why's text) at each transition."""
    seen: list[tuple[float, str, str]] = []
    last = None
    for frame in frames:
        if frame.get("why") is not last:
            last = frame["why"]
            seen.append((frame["t"], frame["state"], last["text"]))
    return seen


def _run_and_grade(
    tmp_path: Path, mission_text: str, world: str, name: str = "m.yaml"
) -> tuple[Any, dict[str, Any]]:
    """``mission_text`` (a file called ``name``) run with ``run --record`` and graded with
    ``grade --html`` (seed 3): the run's recording, and the graded run's replay as its page
    embeds it (the page is ``tmp_path/html/runs/m--same--1.html``)."""
    from helpers import run_cli

    from roboscript.replay.recording import load_recording

    mission = tmp_path / name
    mission.write_text(mission_text, encoding="utf-8")
    spec = tmp_path / "test.yaml"
    spec.write_text(
        f"test: same\nworld: {world}\nrobot: mirto\nruns:\n  - {{seed: 3}}\nmax_time: 40 s\n"
        "expect:\n  - outcome: success\n",
        encoding="utf-8",
    )
    run = tmp_path / "run.jsonl"
    done = run_cli(
        "run", str(mission), "--world", world, "--seed", "3", "--max-time", "40",
        "--record", str(run), "--quiet",
    )  # fmt: skip
    assert done.returncode == 0, done.stderr
    done = run_cli(
        "grade", str(spec), "--mission", str(mission), "--html", str(tmp_path / "html"),
        "--quiet",
    )  # fmt: skip
    assert done.returncode == 0, done.stderr
    page = tmp_path / "html" / "runs" / "m--same--1.html"
    return load_recording(run), _embedded(page.read_text("utf-8"))


def test_run_and_grade_record_the_same_fields_in_the_same_units(tmp_path: Path) -> None:
    bump = (MISSIONS / "bump_and_turn.yaml").read_text(encoding="utf-8")
    ran, graded = _run_and_grade(tmp_path, bump, "square-room")
    header, frames = graded["header"], fill_frames(graded["frames"])

    assert set(header) - set(ran.header) == GRADED_ONLY["header"]
    assert set(ran.header) - set(header) == RUN_ONLY["header"]
    assert set(ran.header["mission"]) - set(header["mission"]) == RUN_ONLY["mission"]
    assert (header["robot"], header["world"], header["seed"], header["tick_s"]) == (
        ran.header["robot"],
        ran.header["world"],
        ran.header["seed"],
        ran.header["tick_s"],
    )
    # the states it entered, with their actions (whether a state is final is not told)
    actions = {s["name"]: s["action"] for s in ran.header["mission"]["states"]}
    assert [(s["name"], s["action"]) for s in header["mission"]["states"]] == [
        (name, actions[name]) for name in dict.fromkeys(n for _, n in ran.result["states"])
    ]
    assert _keys(frames) - _keys(ran.frames) == GRADED_ONLY["frame"]
    assert _keys(ran.frames) - _keys(frames) == RUN_ONLY["frame"]
    for part in ("sensors", "motors"):
        assert _keys(frames, part) == _keys(ran.frames, part)
    assert _keys(frames, "why") - _keys(ran.frames, "why") == GRADED_ONLY["why"]
    assert _keys(ran.frames, "why") - _keys(frames, "why") == RUN_ONLY["why"]
    # the same units: every transition at the same time, in the same words, and the pose
    # (mm, degrees) where the run ended
    assert _transitions(frames) == _transitions(ran.frames)
    assert frames[-1]["pose"] == ran.frames[-1]["pose"]
    assert frames[-1]["t"] == ran.frames[-1]["t"]
    for key in ("range_mm", "bumper"):
        graded_types = {type(f["sensors"][key]).__name__ for f in frames}
        assert graded_types <= {type(f["sensors"][key]).__name__ for f in ran.frames}
    assert {type(f["action"]) for f in frames} == {type(f["action"]) for f in ran.frames}


# Enters its state again every 0.3 s for the same cause: on a tick a graded run keeps anyway.
AGAIN = """\
mission: again
world: empty
initial: wait
states:
  wait:
    do: {wait: {duration: 0.3 s}}
    on:
      done:
        - {if: "visits.wait >= 4", goto: finish}
        - {goto: wait}
  finish:
    final: success
"""


def test_a_state_entered_again_for_the_same_cause_shows_on_its_own_tick_when_graded(
    tmp_path: Path,
) -> None:
    ran, graded = _run_and_grade(tmp_path, AGAIN, "empty")
    transitions = _transitions(ran.frames)
    assert [(t, state) for t, state, _ in transitions] == [
        (0.0, "wait"),
        (0.3, "wait"),
        (0.6, "wait"),
        (0.9, "wait"),
        (1.2, "finish"),
    ]
    assert transitions[1][2] == transitions[2][2] == "wait done"  # equal causes, in a row
    assert _transitions(fill_frames(graded["frames"])) == transitions


def test_a_runs_claimed_causes_are_kept_up_to_a_bound_and_its_states_all() -> None:
    from roboscript.mission.cause import TransitionCause
    from roboscript.profiles import get_profile
    from roboscript.replay.recording import encode_line
    from roboscript.replay.world_tap import CLAIMED_CHARS
    from roboscript.sim.simulation import Simulation
    from roboscript.sim.world import load_world

    tap = WorldReplay(Simulation(load_world("empty"), get_profile("mirto")), get_profile("mirto"))
    tap.start(0.0)
    big = TransitionCause("when", "a", condition="x" * 200, values={"y" * 200: 1}).to_json()
    for tick in range(2 * CLAIMED_CHARS // len(encode_line(big))):
        tap.enter(tick * 0.02, "a" if tick % 2 else "b", "drive", big)
    frames = tap.recorder.frames
    kept = [f["why"] for f in frames if "why" in f]
    assert 0 < len(kept) < len(frames)
    assert len(kept) == -(-CLAIMED_CHARS // len(encode_line(big)))  # up to the bound, then none
    assert len({f["t"] for f in frames}) == len(frames)  # every state entered has its frame


# Prints on a few ticks (a tab and a terminal escape among its words), then on one tick a
# line of 10,000 characters and 2,500 more lines: more than a record keeps.
PRINTER = """\
from roboscript import Drive, Mission, state

_FLOODED = []


class Printer(Mission):
    go = state(Drive(distance_mm=300, speed_mm_s=150), initial=True, on_done="done",
               when=[("talk", "done")])
    done = state(final="success")

    def talk(self):
        if 0.5 < self.elapsed < 0.58:
            print(f"at {self.elapsed:.2f}\\tgap\\x1b[2J", "and more")
        if self.elapsed > 1.0 and not _FLOODED:
            _FLOODED.append(True)
            print("x" * 10_000)
            for number in range(2_500):
                print("line", number)
        return False
"""


@pytest.fixture(scope="module")
def printed(tmp_path_factory: pytest.TempPathFactory) -> tuple[Any, dict[str, Any], Path]:
    """PRINTER run with ``run --record`` and graded: the recording, the graded replay, and
    the graded run's page."""
    folder = tmp_path_factory.mktemp("printed")
    ran, graded = _run_and_grade(folder, PRINTER, "empty", name="m.py")
    return ran, graded, folder / "html" / "runs" / "m--same--1.html"


def _prints(frames: list[dict[str, Any]]) -> list[tuple[float, str]]:
    return [(frame["t"], line) for frame in frames for line in frame.get("print", [])]


def test_run_and_grade_record_what_the_mission_printed_on_the_same_ticks(
    printed: tuple[Any, dict[str, Any], Path],
) -> None:
    ran, graded, _ = printed
    graded_prints = _prints(fill_frames(graded["frames"]))
    ran_prints = _prints(ran.frames)
    # both write only printable text (a tab or a terminal's escape becomes a space), cut
    # alike: the same text on the same ticks
    assert graded_prints == ran_prints
    assert ran_prints[:4] == [
        (0.52, "at 0.52 gap [2J and more"),
        (0.54, "at 0.54 gap [2J and more"),
        (0.56, "at 0.56 gap [2J and more"),
        (ran_prints[3][0], "x" * 500 + "…"),
    ]
    # labelled as the mission's own words, like the causes it gives
    assert "print" in graded["header"]["claimed"]


def test_a_graded_replay_keeps_printed_lines_up_to_the_records_bound_and_counts_the_rest(
    printed: tuple[Any, dict[str, Any], Path],
) -> None:
    from roboscript.mission.channels import MAX_PRINTED_LINES

    ran, graded, _ = printed
    assert len(_prints(fill_frames(graded["frames"]))) == MAX_PRINTED_LINES
    assert graded["result"]["prints_not_recorded"] == 3 + 1 + 2_500 - MAX_PRINTED_LINES
    assert graded["result"]["prints_not_recorded"] == ran.result["prints_not_recorded"]


def test_a_graded_replay_keeps_printed_text_up_to_a_bound_and_counts_the_rest() -> None:
    from roboscript.profiles import get_profile
    from roboscript.replay.world_tap import PRINTED_CHARS
    from roboscript.sim.simulation import Simulation
    from roboscript.sim.world import load_world

    tap = WorldReplay(Simulation(load_world("empty"), get_profile("mirto")), get_profile("mirto"))
    tap.printed(0.0, "before the start")
    tap.start(0.0)
    tap.enter(0.0, "go", "drive", None)
    line = "y" * 499
    lines = 2 * PRINTED_CHARS // len(line)
    for tick in range(lines):
        tap.printed(tick * 0.02, line)
    data = tap.finish(
        mission="m",
        outcome="success",
        final_state="go",
        reason=None,
        duration_s=lines * 0.02,
        states=((0.0, "go"),),
        now_s=lines * 0.02,
    )
    kept = _prints(fill_frames(data["frames"]))
    assert len(kept) == PRINTED_CHARS // len(line)
    assert kept[-1] == (round((len(kept) - 1) * 0.02, 3), line)  # each at its own tick
    assert data["result"]["prints_not_recorded"] == lines - len(kept)
    assert data["header"]["printed_before_start"] == ["before the start"]


def test_the_replay_shows_what_the_mission_printed_under_its_states_in_a_browser(
    printed: tuple[Any, dict[str, Any], Path], tmp_path: Path
) -> None:
    _, _, page = printed
    with open_browser(tmp_path) as browser:
        browser.open(page.as_uri())
        browser.wait_for("document.querySelector('.rs-viewer').dataset.ready === '1'")
        label = browser.evaluate("document.querySelector('[data-role=prints-label]').textContent")
        assert label == "the mission printed (its own words)"
        marks = browser.evaluate(
            "Array.from(document.querySelectorAll('.rs-print-mark'))"
            ".map(function (m) { return m.getAttribute('data-t'); })"
        )
        assert marks[:2] == ["0.52", "0.54"]
        browser.click(".rs-print-mark[data-t='0.54']")
        shown = browser.evaluate("document.querySelector('[data-role=time]').textContent")
        assert shown == "0.54 s"
        lines = browser.evaluate("document.querySelector('[data-role=prints]').textContent")
        assert lines.endswith("0.54 s  at 0.54 gap [2J and more")
        assert browser.errors == []


HIDDEN_AND_VISIBLE = """\
test: printed
world: empty
robot: mirto
runs:
  - {seed: 2, start: {x: 313.7 mm, y: 0 mm, heading: 0 deg}, hidden: true}
  - {seed: 1}
max_time: 10 s
expect:
  - outcome: success
"""

# Prints where it started (the grader's map of the world names it): in the hidden run, that
# would give the hidden start away.
START_PRINTER = """\
import json, sys
from roboscript import Mission, Wait, state

_TOLD = []


class Teller(Mission):
    go = state(Wait(duration_s=0.2), initial=True, on_done="done", when=[("tell", "done")])
    done = state(final="success")

    def tell(self):
        if not _TOLD:
            _TOLD.append(True)
            with open(sys.argv[-1], encoding="utf-8") as handle:
                print("STARTED-AT", json.load(handle)["start"][0])
        return False
"""


def test_a_hidden_runs_prints_reach_the_teachers_replay_only(tmp_path: Path) -> None:
    from helpers import run_cli

    spec = tmp_path / "printed.yaml"
    spec.write_text(HIDDEN_AND_VISIBLE, encoding="utf-8")
    folder = tmp_path / "ana"
    folder.mkdir()
    (folder / "printed.py").write_text(START_PRINTER, encoding="utf-8")
    out = tmp_path / "out"
    out.mkdir()
    done = run_cli(
        "grade", str(spec), "--mission", str(folder), "--html", str(out / "html"),
        "--junit", str(out / "junit.xml"), "--gradescope", str(out / "gradescope.json"),
    )  # fmt: skip
    assert done.returncode == 0, done.stderr
    hidden = _embedded((out / "html" / "runs" / "ana--printed--1.html").read_text("utf-8"))
    visible = _embedded((out / "html" / "runs" / "ana--printed--2.html").read_text("utf-8"))
    assert _prints(fill_frames(hidden["frames"])) == [(0.0, "STARTED-AT 313.7")]  # for you
    assert _prints(fill_frames(visible["frames"])) == [(0.0, "STARTED-AT 0.0")]
    student = (out / "html" / "students" / "ana.html").read_text("utf-8")
    assert "STARTED-AT 0.0" in student  # a visible run's replay shows what it printed
    for text in (student, done.stdout, done.stderr, (out / "junit.xml").read_text("utf-8")):
        assert "313.7" not in text
    assert "313.7" not in (out / "gradescope.json").read_text("utf-8")


# Prints while it loads (at the top of its file and in its class body), then once as it runs.
LOAD_PRINTER = """\
from roboscript import Mission, Wait, state

print("loading the mission", 1)
_TOLD = []


class Loud(Mission):
    print("in the class body")
    go = state(Wait(duration_s=0.3), initial=True, on_done="done", when=[("talk", "done")])
    done = state(final="success")

    def talk(self):
        if self.elapsed > 0.1 and not _TOLD:
            _TOLD.append(True)
            print("running")
        return False
"""


def test_run_and_grade_record_what_the_mission_printed_while_it_loaded_before_the_start(
    tmp_path: Path,
) -> None:
    ran, graded = _run_and_grade(tmp_path, LOAD_PRINTER, "empty", name="m.py")
    loaded = ["loading the mission 1", "in the class body"]
    assert ran.header["printed_before_start"] == loaded
    assert graded["header"]["printed_before_start"] == loaded
    # and not again on a frame: the frames hold what it printed as it ran, on the same tick
    ran_prints = _prints(ran.frames)
    assert [line for _, line in ran_prints] == ["running"]
    assert _prints(fill_frames(graded["frames"])) == ran_prints
    assert "prints_not_recorded" not in graded["result"]


def test_the_replay_shows_what_the_mission_printed_before_the_start_first(
    tmp_path: Path,
) -> None:
    from helpers import run_cli

    mission = tmp_path / "m.py"
    mission.write_text(LOAD_PRINTER, encoding="utf-8")
    run = tmp_path / "run.jsonl"
    done = run_cli("run", str(mission), "--record", str(run), "--quiet")
    assert done.returncode == 0, done.stderr
    page = tmp_path / "run.html"
    assert run_cli("view", str(run), "--output", str(page)).returncode == 0
    with open_browser(tmp_path) as browser:
        browser.open(page.as_uri())
        browser.wait_for("document.querySelector('.rs-viewer').dataset.ready === '1'")
        lines = browser.evaluate(
            "Array.from(document.querySelectorAll('[data-role=prints] li'))"
            ".map(function (li) { return li.textContent; })"
        )
        assert lines == [
            "before the start  loading the mission 1",
            "before the start  in the class body",
        ]
        browser.evaluate("window.roboscriptViewer.viewers[0].seekTime(0.3)")
        lines = browser.evaluate("document.querySelector('[data-role=prints]').textContent")
        assert lines.startswith("before the start  loading the mission 1")
        assert lines.endswith(" s  running")
        marks = browser.evaluate(
            "Array.from(document.querySelectorAll('.rs-print-mark'))"
            ".map(function (m) { return m.getAttribute('data-t'); })"
        )
        assert len(marks) == 2 and marks[0] == "0"  # lines before the start: at the start
        robot = browser.evaluate("document.querySelector('[data-role=robot]').textContent")
        assert robot == "mirto, simulated"
        assert browser.errors == []
