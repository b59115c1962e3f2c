"""Recording a mission run as it goes: what each frame holds, on the simulator and a port."""

from __future__ import annotations

import math
import re
from collections.abc import Callable
from pathlib import Path
from typing import Any

import pytest
from helpers import MISSIONS, ROOT

from roboscript.mission import mission_for_robot
from roboscript.replay import Recording, load_recording
from roboscript.replay.session_tap import OdometryPose, RunRecording, save_recording
from roboscript.session import Session, run_session

DOC = (ROOT / "docs" / "reference" / "recording.md").read_text(encoding="utf-8")


def _record(mission: Path, **options: Any) -> tuple[Session, Recording, RunRecording]:
    spec, profile, _ = mission_for_robot(mission)
    recording = RunRecording()
    session = run_session(
        spec,
        profile,
        world=options.pop("world", spec.world or "empty"),
        recording=recording,
        **options,
    )
    assert recording.recorder is not None
    return session, recording.recorder.recording(), recording


@pytest.fixture(scope="module")
def bump_run() -> tuple[Session, Recording, RunRecording]:
    return _record(MISSIONS / "bump_and_turn.yaml")


def test_frames_follow_the_simulated_body(
    bump_run: tuple[Session, Recording, RunRecording],
) -> None:
    session, recording, _ = bump_run
    frames = {frame["t"]: frame for frame in recording.frames}
    compared = 0
    for t, x, y, heading in session.mission_path():
        frame = frames.get(round(t, 3))
        if frame is None:
            continue
        assert frame["pose"][0] == pytest.approx(x, abs=0.11)
        assert frame["pose"][1] == pytest.approx(y, abs=0.11)
        assert frame["pose"][2] == pytest.approx(heading, abs=0.11)
        compared += 1
    assert compared > 50
    assert recording.header["pose_source"] == "simulator"
    assert recording.header["world"]["name"] == "square-room"
    assert len(recording.header["world"]["walls"]) >= 4


def test_the_state_timeline_is_the_missions(
    bump_run: tuple[Session, Recording, RunRecording],
) -> None:
    session, recording, _ = bump_run
    entered: list[tuple[float, str]] = []
    for frame in recording.frames:
        if not entered or entered[-1][1] != frame["state"]:
            entered.append((frame["t"], frame["state"]))
    assert entered == [(round(t, 3), name) for t, name in session.result.states]
    assert recording.result is not None
    assert recording.result["outcome"] == session.result.outcome == "success"
    assert recording.result["frames"] == len(recording.frames)


def test_a_turn_starts_on_the_tick_the_range_reads_under_25_cm(
    bump_run: tuple[Session, Recording, RunRecording],
) -> None:
    frames = bump_run[1].frames
    turns = [
        index
        for index in range(1, len(frames))
        if frames[index]["state"] == "turn" and frames[index - 1]["state"] == "forward"
    ]
    assert turns
    for index in turns:
        # the guard read the value the frame before shows... or this tick's own reading
        readings = [frames[i]["sensors"]["range_mm"] for i in (index - 1, index)]
        assert any(r is not None and r < 250 for r in readings), readings
        assert frames[index]["action"] == "rotate"


def test_commands_are_recorded_as_the_mission_gives_them(
    bump_run: tuple[Session, Recording, RunRecording],
) -> None:
    frames = bump_run[1].frames
    forward = next(f for f in frames if f["state"] == "forward" and f["t"] > 1.0)
    assert forward["motors"]["left_mm_s"] == pytest.approx(forward["motors"]["right_mm_s"])
    assert forward["motors"]["left_mm_s"] > 50
    first_turn = [f for f in frames if f["state"] == "turn"][:20]
    turning = first_turn[len(first_turn) // 2]
    assert turning["motors"]["left_mm_s"] > turning["motors"]["right_mm_s"]  # right turn
    tones = [f["tone"] for f in frames if "tone" in f]
    assert tones == [[660.0, 0.3]]
    assert frames[-1]["motors"] == {"left_mm_s": 0.0, "right_mm_s": 0.0}


def test_every_key_a_recording_holds_is_documented(
    bump_run: tuple[Session, Recording, RunRecording],
) -> None:
    _, recording, _ = bump_run
    documented = set(re.findall(r"`([a-z_]+)`", DOC))
    keys: set[str] = set(recording.header)
    keys |= set(recording.header["robot"]) | set(recording.header["world"])
    for sensor in recording.header["robot"]["sensors"]:
        keys |= set(sensor)
        keys.add(sensor["name"])
    for state in recording.header["mission"]["states"]:
        keys |= set(state)
    for frame in recording.frames:
        keys |= set(frame) | set(frame.get("sensors", {})) | set(frame.get("motors", {}))
    assert recording.result is not None
    keys |= set(recording.result)
    assert keys - documented == set()


def test_frame_values_have_the_documented_types(
    bump_run: tuple[Session, Recording, RunRecording],
) -> None:
    _, recording, _ = bump_run
    states = {state["name"] for state in recording.header["mission"]["states"]}
    last_t = -1.0
    for frame in recording.frames:
        assert isinstance(frame["t"], float) and frame["t"] > last_t
        last_t = frame["t"]
        x, y, heading = frame["pose"]
        assert abs(x) < 1000 and abs(y) < 1000 and -180 <= heading < 180
        assert frame["state"] in states
        sensors = frame["sensors"]
        assert set(sensors) == {"range_mm", "side_range_mm", "line", "bumper"}
        for key in ("range_mm", "side_range_mm"):
            assert sensors[key] is None or 0 <= sensors[key] <= 1000
        assert set(sensors["bumper"]) <= {"left", "right"}
        assert frame["contact"] in (None, "left", "right")


def test_a_recording_of_a_60_s_run_stays_small(tmp_path: Path) -> None:
    _, _, recording = _record(ROOT / "tests" / "bench" / "patrol_60s.yaml")
    path = tmp_path / "run.jsonl"
    assert save_recording(recording, str(path)) is None
    assert path.stat().st_size < 2_000_000


def test_a_sensor_that_breaks_ends_the_recording_not_the_run(
    write_mission: Callable[..., Path], tmp_path: Path
) -> None:
    mission = write_mission(
        "mission: m\ninitial: go\nstates:\n"
        "  go:\n    do: {drive: {distance: 10 cm, speed: 10 cm/s}}\n    on: {done: end}\n"
        "  end:\n    final: success\n"
    )
    spec, profile, _ = mission_for_robot(mission)
    calls = 0

    def failing() -> float:
        nonlocal calls
        calls += 1
        if calls > 10:
            raise OSError("sensor gone")
        return 1.0

    class WithFailingSensor(RunRecording):
        def attach(self, robot: Any, spec: Any, profile: Any) -> dict[str, object]:
            capabilities = super().attach(robot, spec, profile)
            self.add_sensors([("range_mm", failing)])
            return capabilities

    recording = WithFailingSensor()
    session = run_session(spec, profile, recording=recording)
    assert session.result.outcome == "success"
    assert recording.recorder is not None
    assert len(recording.recorder.frames) == 10
    problem = save_recording(recording, str(tmp_path / "r.jsonl"))
    assert problem is not None
    assert "recording stopped at 0.20 s: sensor gone" in problem
    assert recording.recorder.result is not None
    assert recording.recorder.result["recording_error"].endswith("sensor gone")


def test_a_write_that_fails_says_so_in_one_line(
    bump_run: tuple[Session, Recording, RunRecording], tmp_path: Path
) -> None:
    problem = save_recording(bump_run[2], str(tmp_path))  # a folder: cannot be written
    assert problem is not None
    assert problem.startswith(f"error: cannot write the recording {tmp_path}: ")
    assert "\n" not in problem


@pytest.mark.parametrize(
    ("moves", "expected"),
    [
        ([(100.0, 100.0)], (0.0, 100.0, 0.0)),  # straight ahead: north
        ([(-50.0, -50.0)], (0.0, -50.0, 0.0)),
        # a quarter turn right on the spot (the left wheel forward), then 100 mm ahead: east
        ([(math.pi * 81 / 2, -math.pi * 81 / 2), (100.0, 100.0)], (100.0, 0.0, 90.0)),
    ],
)
def test_odometry_dead_reckons_clockwise_from_north(
    moves: list[tuple[float, float]], expected: tuple[float, float, float]
) -> None:
    odometry = OdometryPose(track_mm=162.0)
    odometry.update(0.0, 0.0)
    left = right = 0.0
    pose = (0.0, 0.0, 0.0)
    for dl, dr in moves:
        left, right = left + dl, right + dr
        pose = odometry.update(left, right)
    assert pose == pytest.approx(expected, abs=1e-6)


def test_a_listener_gets_the_header_each_frame_as_written_and_the_end(tmp_path: Path) -> None:
    seen: list[tuple[str, dict[str, Any]]] = []
    spec, profile, _ = mission_for_robot(MISSIONS / "square.yaml")
    recording = RunRecording(listeners=(lambda event, data: seen.append((event, data)),))
    run_session(spec, profile, recording=recording)
    assert recording.recorder is not None
    events = [event for event, _ in seen]
    assert events[0] == "header" and events[-1] == "end"
    assert events.count("header") == 1 and events.count("end") == 1
    streamed = [data for event, data in seen if event == "frame"]
    assert streamed == recording.recorder.frames  # the same dicts the file holds
    path = tmp_path / "run.jsonl"
    assert save_recording(recording, str(path)) is None
    assert load_recording(path).frames == recording.recorder.recording().frames


@pytest.mark.parametrize(
    ("url", "port"),
    [
        ("webserial://1", "the robot on the serial port you chose"),
        ("webbluetooth://2", "the Bluetooth robot you chose"),
        ("/dev/ttyUSB0", "/dev/ttyUSB0"),
    ],
)
def test_the_header_names_a_port_chosen_in_the_browser_as_the_page_does(
    url: str, port: str
) -> None:
    def reached_on(robot: Any) -> None:
        robot.url = url  # as a run from the browser app reaches its robot

    _, recording, _ = _record(MISSIONS / "square.yaml", on_connected=reached_on, max_time_s=0.1)
    assert recording.header["port"] == port


def test_the_replay_names_the_robot_and_where_it_ran(tmp_path: Path) -> None:
    from browser import open_browser

    from roboscript.replay.viewer import viewer_block, viewer_page

    def reached_on(robot: Any) -> None:
        robot.url = "webserial://1"

    _, recording, _ = _record(MISSIONS / "square.yaml", on_connected=reached_on, max_time_s=0.1)
    page = tmp_path / "run.html"
    page.write_text(viewer_page(viewer_block(recording), "square"), encoding="utf-8")
    with open_browser(tmp_path) as browser:
        browser.open(page.as_uri())
        browser.wait_for("document.querySelector('.rs-viewer').dataset.ready === '1'")
        robot = browser.evaluate("document.querySelector('[data-role=robot]').textContent")
        assert robot == "mirto, the robot on the serial port you chose"
        assert browser.errors == []
