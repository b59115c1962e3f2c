"""The replay page in a real headless Chromium: play, step, scrub, jump to a state, go live.

Each test reads what the page shows as text (time, state, pose, sensor values) and compares it
with the recording the page was made from.
"""

from __future__ import annotations

import json
import threading
from collections.abc import Iterator
from http.server import BaseHTTPRequestHandler, ThreadingHTTPServer
from pathlib import Path
from typing import Any

import pytest
from browser import Browser, open_browser
from helpers import LOGGING_MISSION, MISSIONS

from roboscript.mission import mission_for_robot
from roboscript.replay import Recording
from roboscript.replay.session_tap import RunRecording
from roboscript.replay.viewer import live_viewer, viewer_block, viewer_page
from roboscript.session import run_session


@pytest.fixture(scope="module")
def recorded() -> tuple[Recording, RunRecording]:
    spec, profile, _ = mission_for_robot(MISSIONS / "bump_and_turn.yaml")
    recording = RunRecording()
    run_session(spec, profile, world="square-room", recording=recording)
    assert recording.recorder is not None
    return recording.recorder.recording(), recording


@pytest.fixture(scope="module")
def page(
    recorded: tuple[Recording, RunRecording], tmp_path_factory: pytest.TempPathFactory
) -> Path:
    path = tmp_path_factory.mktemp("view") / "run.html"
    path.write_text(viewer_page(viewer_block(recorded[0]), "bump and turn"), encoding="utf-8")
    return path


@pytest.fixture
def browser(page: Path, tmp_path: Path) -> Iterator[Browser]:
    with open_browser(tmp_path) as opened:
        opened.open(page.as_uri())
        opened.wait_for("document.querySelector('.rs-viewer').dataset.ready === '1'")
        yield opened
        assert opened.errors == []  # the page's script never threw


def _text(browser: Browser, role: str) -> str:
    return str(browser.evaluate(f"document.querySelector('[data-role={role}]').textContent"))


def _sensor(browser: Browser, name: str) -> str:
    return str(browser.evaluate(f"document.querySelector('[data-sensor={name}] td').textContent"))


def _index(browser: Browser) -> int:
    return int(browser.evaluate("document.querySelector('.rs-viewer').dataset.index"))


def _shows(browser: Browser, frame: dict[str, Any], total: int, index: int) -> None:
    """The page's text is exactly this frame's."""
    assert _text(browser, "time") == f"{frame['t']:.2f} s"
    assert _text(browser, "state") == frame["state"]
    assert _text(browser, "frame") == f"{index + 1} / {total}"
    x, y, heading = frame["pose"]
    assert _text(browser, "pose") == f"x {x:.1f} mm, y {y:.1f} mm, heading {heading:.1f}°"
    reading = frame["sensors"]["range_mm"]
    assert _sensor(browser, "range_mm") == ("—" if reading is None else f"{reading:.1f}")


def test_the_page_opens_on_the_first_tick(
    browser: Browser, recorded: tuple[Recording, RunRecording]
) -> None:
    frames = recorded[0].frames
    _shows(browser, frames[0], len(frames), 0)
    assert _text(browser, "result").startswith("success in 'home' after")
    names = browser.evaluate(
        "[...document.querySelectorAll('[data-role=timeline] [data-state]')]"
        ".map(e => e.dataset.state)"
    )
    assert names == [name for _, name in recorded[0].result["states"]]  # type: ignore[index]


def test_step_moves_one_tick_at_a_time(
    browser: Browser, recorded: tuple[Recording, RunRecording]
) -> None:
    frames = recorded[0].frames
    for _ in range(3):
        browser.click("[data-action=step]")
    _shows(browser, frames[3], len(frames), 3)
    browser.click("[data-action=step-back]")
    _shows(browser, frames[2], len(frames), 2)


def test_play_runs_the_replay_and_pause_holds_it(
    browser: Browser, recorded: tuple[Recording, RunRecording]
) -> None:
    frames = recorded[0].frames
    browser.click("[data-action=play]")
    browser.wait_for("+document.querySelector('.rs-viewer').dataset.index > 10")
    browser.click("[data-action=play]")  # the same button pauses
    held = _index(browser)
    assert browser.evaluate("document.querySelector('.rs-viewer').dataset.playing") == "0"
    _shows(browser, frames[held], len(frames), held)
    browser.evaluate("new Promise(r => setTimeout(r, 200))")
    assert _index(browser) == held


def test_the_speed_setting_scales_playback(
    browser: Browser, recorded: tuple[Recording, RunRecording]
) -> None:
    browser.evaluate(
        "(() => { const s = document.querySelector('[data-role=speed]');"
        " s.value = '16'; s.dispatchEvent(new Event('change')); })()"
    )
    browser.click("[data-action=play]")
    # the page's own clocks: run seconds shown per wall second, measured over half a second
    ratio = browser.evaluate(
        "new Promise(resolve => { const v = document.querySelector('.rs-viewer');"
        " const t0 = +v.dataset.t, w0 = performance.now();"
        " setTimeout(() => resolve((+v.dataset.t - t0) / ((performance.now() - w0) / 1000)),"
        " 500); })"
    )
    assert 8.0 < ratio < 20.0


def test_scrubbing_shows_the_sensor_reading_at_that_time(
    browser: Browser, recorded: tuple[Recording, RunRecording]
) -> None:
    recording = recorded[0]
    browser.click("[data-role=scrubber]", x_fraction=0.5)
    index = _index(browser)
    assert 0.3 * len(recording.frames) < index < 0.7 * len(recording.frames)
    _shows(browser, recording.frames[index], len(recording.frames), index)
    # drag the scrubber to the tick at 5 s: the range reading is the recording's at 5 s
    at_5s = recording.frame_at(5.0)
    assert at_5s is not None
    target = recording.frames.index(at_5s)
    browser.evaluate(
        "(() => { const s = document.querySelector('[data-role=scrubber]');"
        f" s.value = '{target}'; s.dispatchEvent(new Event('input')); }})()"
    )
    assert _text(browser, "time") == "5.00 s"
    assert _sensor(browser, "range_mm") == f"{at_5s['sensors']['range_mm']:.1f}"


def test_clicking_a_state_jumps_to_where_it_began(
    browser: Browser, recorded: tuple[Recording, RunRecording]
) -> None:
    recording = recorded[0]
    assert recording.result is not None
    states = recording.result["states"]
    second_turn = [i for i, (_, name) in enumerate(states) if name == "turn"][1]
    browser.click(f"[data-role=timeline] [data-state=turn]:nth-child({second_turn + 1})")
    index = _index(browser)
    frame = recording.frames[index]
    assert frame["t"] == pytest.approx(states[second_turn][0])
    _shows(browser, frame, len(recording.frames), index)
    assert _text(browser, "action") == "rotate"


def test_clicking_a_transition_shows_why_the_robot_turned_there(
    browser: Browser, recorded: tuple[Recording, RunRecording]
) -> None:
    # bump_and_turn turns when the ranger sees a wall closer than 25 cm: the page alone says so
    browser.click("[data-role=timeline] [data-state=turn]:nth-child(2)")
    frame = recorded[0].frames[_index(browser)]
    assert frame["state"] == "turn"
    why = _text(browser, "why")
    assert why == frame["why"]["text"]
    assert why.startswith("'range.distance_cm < 25' held (range.distance_cm = ")
    assert float(why.rsplit("= ", 1)[1].rstrip(")")) < 25


def test_each_timeline_segment_names_its_cause(
    browser: Browser, recorded: tuple[Recording, RunRecording]
) -> None:
    causes = browser.evaluate(
        "Array.from(document.querySelectorAll('[data-role=timeline] [data-state]'))"
        ".map(function (b) { return b.dataset.why; })"
    )
    recording = recorded[0]
    assert recording.result is not None
    assert len(causes) == len(recording.result["states"])
    assert causes[0] == "the mission started"
    assert "'bumper.any' held (bumper.any = true)" in causes


def test_the_last_frame_shows_how_the_mission_ended(
    browser: Browser, recorded: tuple[Recording, RunRecording]
) -> None:
    browser.evaluate("document.querySelector('[data-role=scrubber]').value = '999999'")
    browser.evaluate(
        "document.querySelector('[data-role=scrubber]').dispatchEvent(new Event('input'))"
    )
    recording = recorded[0]
    assert recording.result is not None
    last = recording.frames[-1]
    assert _index(browser) == len(recording.frames) - 1
    # the final state's own action ended 'done' (a final state without one: the result's)
    assert _text(browser, "outcome") == (last.get("outcome") or recording.result["outcome"])
    assert _text(browser, "outcome") != "running"


def test_pause_at_a_state_stops_playing_where_it_is_entered(
    browser: Browser, recorded: tuple[Recording, RunRecording]
) -> None:
    browser.evaluate(
        "var s = document.querySelector('[data-role=pause-at]');"
        "s.value = 'state:back_off'; s.dispatchEvent(new Event('change'));"
        "var v = document.querySelector('[data-role=speed]');"
        "v.value = '8'; v.dispatchEvent(new Event('change'));"
    )
    browser.click("button[data-action=play]")
    browser.wait_for("document.querySelector('.rs-viewer').dataset.playing === '0'", 60)
    frames = recorded[0].frames
    index = _index(browser)
    assert frames[index]["state"] == "back_off"
    assert frames[index - 1]["state"] != "back_off"  # the very tick it was entered
    assert _text(browser, "why") == "'bumper.any' held (bumper.any = true)"


def test_a_tone_shows_for_its_whole_duration(
    browser: Browser, recorded: tuple[Recording, RunRecording]
) -> None:
    start = next(f for f in recorded[0].frames if "tone" in f)
    frequency_hz, duration_s = start["tone"]
    browser.evaluate(f"window.roboscriptViewer.viewers[0].seekTime({start['t'] + duration_s / 2})")
    assert _text(browser, "tone").startswith(f"{frequency_hz:.0f} Hz for {duration_s:.2f} s")
    browser.evaluate(
        f"window.roboscriptViewer.viewers[0].seekTime({start['t'] + duration_s + 0.05})"
    )
    assert _text(browser, "tone") == "—"


def test_the_map_has_a_scale_bar_and_sound_can_be_muted(browser: Browser) -> None:
    assert int(browser.evaluate("document.querySelector('.rs-viewer').dataset.scaleMm")) > 0
    browser.click("button[data-action=mute]")
    assert (
        browser.evaluate(
            "document.querySelector('[data-action=mute]').getAttribute('aria-pressed')"
        )
        == "true"
    )


def test_the_students_values_and_prints_show_beside_the_sensors(tmp_path: Path) -> None:
    mission = tmp_path / "logged.py"
    mission.write_text(LOGGING_MISSION, encoding="utf-8")
    spec, profile, _ = mission_for_robot(mission)
    recording = RunRecording()
    run_session(spec, profile, recording=recording)
    assert recording.recorder is not None
    page = tmp_path / "run.html"
    page.write_text(
        viewer_page(viewer_block(recording.recorder.recording()), "logged"), encoding="utf-8"
    )
    with open_browser(tmp_path) as browser:
        browser.open(page.as_uri())
        browser.wait_for("document.querySelector('.rs-viewer').dataset.ready === '1'")
        browser.evaluate("window.roboscriptViewer.viewers[0].seekTime(1.5)")
        assert _text(browser, "log").startswith("driven_cm")
        assert "halfway" in _text(browser, "log")
        assert _text(browser, "prints") == "1.02 s  one second in"
        options = browser.evaluate(
            "Array.from(document.querySelector('[data-role=pause-at]').options)"
            ".map(function (o) { return o.value; })"
        )
        assert "true:halfway" in options and "state:end" in options
        assert browser.errors == []


class _Events(BaseHTTPRequestHandler):
    recording: RunRecording
    page: str

    def do_GET(self) -> None:
        if self.path != "/events":
            body = self.page.encode()
            self.send_response(200)
            self.send_header("Content-Type", "text/html; charset=utf-8")
            self.send_header("Content-Length", str(len(body)))
            self.end_headers()
            self.wfile.write(body)
            return
        self.send_response(200)
        self.send_header("Content-Type", "text/event-stream")
        self.end_headers()
        recorder = self.recording.recorder
        assert recorder is not None and recorder.result is not None
        events = [("header", recorder.header())]
        events += [("frame", frame) for frame in recorder.frames]
        events.append(("end", recorder.result))
        for event, data in events:
            self.wfile.write(f"event: {event}\ndata: {json.dumps(data)}\n\n".encode())
        self.wfile.flush()

    def log_message(self, format: str, *args: Any) -> None:
        pass


def test_a_live_source_appends_frames_as_they_come(
    recorded: tuple[Recording, RunRecording], tmp_path: Path
) -> None:
    recording, run = recorded
    handler = type(
        "Handler",
        (_Events,),
        {"recording": run, "page": viewer_page(live_viewer("/events"), "live")},
    )
    server = ThreadingHTTPServer(("127.0.0.1", 0), handler)
    thread = threading.Thread(target=server.serve_forever, daemon=True)
    thread.start()
    try:
        with open_browser(tmp_path) as browser:
            browser.open(f"http://127.0.0.1:{server.server_address[1]}/")
            browser.wait_for("document.querySelector('.rs-viewer').dataset.ended === '1'")
            browser.wait_for("document.querySelector('.rs-viewer').dataset.ready === '1'")
            last = len(recording.frames) - 1
            assert _index(browser) == last  # a live view follows the newest tick
            _shows(browser, recording.frames[last], len(recording.frames), last)
            assert _text(browser, "result").startswith("success in 'home'")
            assert browser.errors == []
    finally:
        server.shutdown()
        server.server_close()


def test_a_run_without_a_world_or_a_pose_still_replays(tmp_path: Path) -> None:
    from roboscript.replay import Recorder

    recorder = Recorder({"mission": {"name": "walk", "states": []}, "world": None, "robot": {}})
    for i in range(50):
        state = "walk" if i < 25 else "rest"
        recorder.add({"t": i * 0.02, "pose": None, "state": state, "sensors": {"range_mm": i}})
    recorder.finish({"outcome": "success", "final_state": "rest", "duration_s": 0.98})
    page = tmp_path / "walk.html"
    page.write_text(viewer_page(viewer_block(recorder.recording()), "walk"), encoding="utf-8")
    with open_browser(tmp_path) as browser:
        browser.open(page.as_uri())
        browser.wait_for("document.querySelector('.rs-viewer').dataset.ready === '1'")
        browser.click("[data-role=timeline] [data-state=rest]")
        assert _text(browser, "state") == "rest"
        assert _text(browser, "time") == "0.50 s"
        assert _sensor(browser, "range_mm") == "25.0"
        assert _text(browser, "pose") == "—"
        assert browser.errors == []


HOSTILE_NAMES = ["a'b", 'say "hi"', "</script><script>window.owned=1</script>", "x]y\\z"]


def test_names_of_any_text_show_as_text_and_run_nothing(tmp_path: Path) -> None:
    from helpers import run_cli

    from roboscript.replay import Recorder

    names = HOSTILE_NAMES
    recorder = Recorder(
        {"mission": {"name": names[2], "states": [{"name": n} for n in names]}, "robot": {}}
    )
    for i, name in enumerate(names):
        recorder.add({"t": i * 0.1, "state": name, "sensors": dict.fromkeys(names, i)})
    recorder.finish({"outcome": "success", "final_state": names[-1], "reason": names[2]})
    run = tmp_path / "names.jsonl"
    recorder.write(run)
    done = run_cli("view", str(run))  # the page as `roboscript view` writes it
    assert done.returncode == 0, done.stderr
    with open_browser(tmp_path) as browser:
        browser.open((tmp_path / "names.html").as_uri())
        browser.wait_for("document.querySelector('.rs-viewer').dataset.ready === '1'")
        cells = "[...document.querySelectorAll('[data-role=sensors] tr')]"
        assert browser.evaluate(f"{cells}.map(r => r.firstChild.textContent)") == names
        assert browser.evaluate(f"{cells}.map(r => r.lastChild.textContent)") == ["0.0"] * 4
        browser.click("[data-action=step]")
        assert _text(browser, "state") == names[1]
        assert browser.evaluate(f"{cells}.map(r => r.lastChild.textContent)") == ["1.0"] * 4
        assert browser.evaluate("window.owned === undefined")
        assert browser.errors == []
