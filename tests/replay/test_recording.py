"""The recorded-run format: what a recording holds, and that it reads back as it was made."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from roboscript.replay import FORMAT, VERSION, Recorder, RecordingError, load_recording
from roboscript.replay.recording import (
    MAX_FRAMES,
    MAX_LINE_CHARS,
    RecordingFile,
    fill_frames,
    parse_recording,
)

SNAPSHOTS = [
    {
        "t": 0.0,
        "pose": [0.0, 0.0, 0.0],
        "state": "go",
        "action": "drive",
        "outcome": None,
        "sensors": {"range_mm": 500.0, "bumper": []},
        "motors": {"left_mm_s": 100.0, "right_mm_s": 100.0},
    },
    {
        "t": 0.02,
        "pose": [0.0, 2.0, 0.0],
        "state": "go",
        "action": "drive",
        "outcome": None,
        "sensors": {"range_mm": 498.0, "bumper": []},
        "motors": {"left_mm_s": 100.0, "right_mm_s": 100.0},
        "tone": [440.0, 0.2],
    },
    {
        "t": 0.04,
        "pose": [0.0, 4.0, 0.0],
        "state": "beep",
        "action": "play_tone",
        "outcome": "done",
        "sensors": {"range_mm": None, "bumper": ["left"]},
        "motors": {"left_mm_s": 0.0, "right_mm_s": 100.0},
        "display": "hi",
    },
]


def _recorder() -> Recorder:
    recorder = Recorder({"mission": {"name": "m"}, "world": None})
    for snapshot in SNAPSHOTS:
        recorder.add(snapshot)
    recorder.finish({"outcome": "success", "final_state": "beep", "duration_s": 0.04})
    return recorder


def test_a_frame_keeps_only_what_changed() -> None:
    frames = _recorder().frames
    assert frames[1] == {
        "t": 0.02,
        "pose": [0.0, 2.0, 0.0],
        "sensors": {"range_mm": 498.0},
        "tone": [440.0, 0.2],
    }
    assert frames[2] == {
        "t": 0.04,
        "pose": [0.0, 4.0, 0.0],
        "state": "beep",
        "action": "play_tone",
        "outcome": "done",
        "sensors": {"range_mm": None, "bumper": ["left"]},
        "motors": {"left_mm_s": 0.0},
        "display": "hi",
    }


# A state entered again for the same cause: two transitions whose causes are equal.
AGAIN = [
    {"t": 0.0, "state": "wait", "why": {"kind": "start", "text": "the mission started"}},
    {"t": 0.3, "why": {"kind": "done", "text": "wait done"}},
    {"t": 0.32},
    {"t": 0.6, "why": {"kind": "done", "text": "wait done"}},
    {"t": 0.62},
]


def test_a_cause_equal_to_the_one_before_is_recorded_again_when_frames_are_recorded_anew() -> None:
    recorder = Recorder({"mission": {"name": "again"}, "world": None})
    for frame in fill_frames(AGAIN):  # as a saved run or a report's page re-records a run
        recorder.add(frame)
    assert [f["t"] for f in recorder.frames if "why" in f] == [0.0, 0.3, 0.6]


def test_a_recording_reads_back_as_it_was_recorded(tmp_path: Path) -> None:
    path = tmp_path / "run.jsonl"
    _recorder().write(path)
    recording = load_recording(path)
    assert recording.header["format"] == FORMAT
    assert recording.header["version"] == VERSION
    assert recording.header["mission"] == {"name": "m"}
    assert recording.frames == SNAPSHOTS
    assert recording.result == {
        "outcome": "success",
        "final_state": "beep",
        "duration_s": 0.04,
        "frames": 3,
    }
    assert recording.frame_at(0.03) == SNAPSHOTS[1]
    assert recording.frame_at(-1.0) is None


def test_a_tone_is_an_event_of_one_tick() -> None:
    frames = fill_frames(_recorder().frames)
    assert [frame.get("tone") for frame in frames] == [None, [440.0, 0.2], None]


def test_the_file_is_one_json_object_a_line(tmp_path: Path) -> None:
    path = tmp_path / "run.jsonl"
    _recorder().write(path)
    lines = path.read_text(encoding="utf-8").splitlines()
    assert len(lines) == 1 + len(SNAPSHOTS) + 1
    items = [json.loads(line) for line in lines]
    assert items[0]["format"] == "roboscript-run"
    assert all("t" in item for item in items[1:-1])
    assert set(items[-1]) == {"result"}


def test_listeners_see_each_frame_as_it_is_made_and_the_end() -> None:
    seen: list[tuple[str, dict[str, object]]] = []
    recorder = Recorder({"mission": {"name": "m"}})
    recorder.subscribe(lambda event, data: seen.append((event, data)), with_header=True)
    recorder.add(SNAPSHOTS[0])
    recorder.add(SNAPSHOTS[1])
    recorder.finish({"outcome": "failure"})
    assert [event for event, _ in seen] == ["header", "frame", "frame", "end"]
    assert seen[0][1]["format"] == FORMAT
    assert seen[2][1] == recorder.frames[1]
    assert seen[3][1]["outcome"] == "failure"


def test_a_broken_listener_is_dropped_and_recording_goes_on() -> None:
    recorder = Recorder({})

    def broken(event: str, data: dict[str, object]) -> None:
        raise RuntimeError("viewer gone")

    recorder.subscribe(broken)
    recorder.add(SNAPSHOTS[0])
    recorder.add(SNAPSHOTS[1])
    assert len(recorder.frames) == 2


def test_a_full_recording_counts_the_ticks_it_did_not_keep() -> None:
    recorder = Recorder({}, max_frames=2)
    for snapshot in SNAPSHOTS:
        recorder.add(snapshot)
    result = recorder.finish({"outcome": "success"})
    assert len(recorder.frames) == 2
    assert result["frames_not_recorded"] == 1
    assert recorder.add(SNAPSHOTS[0]) is None  # finished: nothing more is taken


@pytest.mark.parametrize(
    ("text", "problem"),
    [
        ("", "run.jsonl: error: the recording is empty"),
        ('{"format": "other", "version": 1}\n', "run.jsonl:1: error: not a roboscript recording"),
        (
            '{"format": "roboscript-run", "version": 2}\n',
            (
                "run.jsonl:1: error: this recording is version 2; this roboscript reads up to"
                " version 1"
            ),
        ),
        ('{"format": "roboscript-run", "version": 1}\n{"t": 0}\n{oops\n', "run.jsonl:3: error:"),
        (
            '{"format": "roboscript-run", "version": 1}\n{"pose": [0, 0, 0]}\n',
            "run.jsonl:2: error: a frame needs 't', its time in seconds",
        ),
        (
            '{"format": "roboscript-run", "version": 1}\n{"result": {}}\n{"t": 1}\n',
            "run.jsonl:3: error: nothing may follow the result line",
        ),
        ('{"format": "roboscript-run", "version": 1}\n[1, 2]\n', "run.jsonl:2: error:"),
    ],
)
def test_a_bad_recording_is_named_by_file_and_line(text: str, problem: str) -> None:
    with pytest.raises(RecordingError) as caught:
        parse_recording(text, "run.jsonl")
    assert str(caught.value).startswith(problem)
    assert "\n" not in str(caught.value)


def test_a_missing_file_is_one_sentence(tmp_path: Path) -> None:
    with pytest.raises(RecordingError, match=r"cannot read the recording: No such file"):
        load_recording(tmp_path / "none.jsonl")


def test_unknown_keys_are_kept_for_newer_minor_additions() -> None:
    recording = parse_recording(
        '{"format": "roboscript-run", "version": 1, "extra": 5}\n{"t": 0, "new_key": [1]}\n'
    )
    assert recording.header["extra"] == 5
    assert recording.frames == [{"t": 0, "new_key": [1]}]
    assert recording.result is None


# Text a student may type, the kinds that once broke the framing first: every character a
# reader could take for a line end, then anything Unicode holds but lone surrogates (which
# a JSON reader joins into one character when two meet).
_TEXT = st.text(
    alphabet=st.one_of(
        st.sampled_from("\n\r\x0b\x0c\x1c\x1d\x1e\x85\u2028\u2029\"\\<>'"),
        st.characters(exclude_categories=["Cs"]),
    )
)


@settings(max_examples=200, deadline=None)
@given(name=_TEXT, display=_TEXT, state=_TEXT)
def test_any_text_reads_back_as_it_was_written(name: str, display: str, state: str) -> None:
    recorder = Recorder({"mission": {"name": name, "states": [{"name": state}]}})
    recorder.add({"t": 0.0, "state": state, "display": display, "sensors": {name: 1.0}})
    recorder.finish({"outcome": "success", "final_state": state, "reason": display})
    text = "".join(line + "\n" for line in recorder.lines())
    assert len(text.split("\n")) == 4  # header, frame, result, and nothing after the last
    recording = parse_recording(text)
    assert recording.header["mission"]["name"] == name
    assert recording.frames[0]["display"] == display
    assert recording.frames[0]["sensors"] == {name: 1.0}
    assert recording.result is not None and recording.result["reason"] == display


def test_a_lone_surrogate_is_written_as_its_escape() -> None:
    recorder = Recorder({"mission": {"name": "\ud800"}})
    recorder.finish({"outcome": "success"})
    text = "\n".join(recorder.lines()).encode("utf-8").decode("utf-8")
    assert parse_recording(text).header["mission"]["name"] == "\ud800"


def test_a_recorder_with_a_file_writes_as_it_goes(tmp_path: Path) -> None:
    out = RecordingFile(tmp_path / "run.jsonl")
    recorder = Recorder({"mission": {"name": "m"}}, out=out)
    # the header is on disk before the first frame, as a run killed at once would leave it
    assert load_recording(tmp_path / "run.jsonl").header["mission"]["name"] == "m"
    for snapshot in SNAPSHOTS:
        recorder.add(snapshot)
    recorder.finish({"outcome": "success"})
    assert out.error is None
    recording = load_recording(tmp_path / "run.jsonl")
    assert recording.frames == _recorder().recording().frames
    assert recording.result is not None and recording.result["outcome"] == "success"


def test_a_line_cut_short_at_the_end_is_a_run_killed_while_writing() -> None:
    text = "\n".join(_recorder().lines())
    cut = text[: text.rindex("\n") + 12]  # the result line, cut after 11 characters
    recording = parse_recording(cut)
    assert len(recording.frames) == len(SNAPSHOTS) and recording.result is None


HEADER = '{"format": "roboscript-run", "version": 1}\n'


@pytest.mark.parametrize(
    ("text", "problem"),
    [
        (HEADER + '{"t": NaN}\n', "2: error: this line is not JSON (NaN is not a number"),
        (HEADER + '{"t": 0, "pose": [0, 0, Infinity]}\n', "2: error: this line is not JSON"),
        (HEADER + '{"t": 0, "pose": [0, 0, 1e999]}\n', "2: error: 'pose[2]' must be a finite"),
        (HEADER + "[" * 5000 + "]" * 5000 + "\n", "2: error: this line is nested too deeply"),
        (HEADER[:-2] + ', "mission": "x"}\n', "1: error: 'mission' must be an object"),
        (HEADER[:-2] + ', "robot": {"sensors": 3}}\n', "1: error: 'robot.sensors' must be a list"),
        (
            HEADER[:-2] + ', "world": {"walls": [[0, 0, 1]]}}\n',
            "1: error: 'world.walls[0]' must be a list of 4 values",
        ),
        (HEADER + '{"t": 0, "sensors": "a"}\n', "2: error: 'sensors' must be an object"),
        (HEADER + '{"t": 0, "motors": {"left": "x"}}\n', "2: error: 'motors.left' must be a"),
        (HEADER + '{"result": {"states": [[0]]}}\n', "2: error: 'result.states[0]' must be"),
        (HEADER + '{"t": 0}\n{"t": 0}\n\x85\n{"t": 0, "display": "\u2028"}\n', ""),
    ],
)
def test_a_hostile_recording_is_refused_at_its_line(text: str, problem: str) -> None:
    if not problem:  # a recording only this reader's framing reads right
        assert parse_recording(text, "r.jsonl").frames[-1]["display"] == "\u2028"
        return
    with pytest.raises(RecordingError) as caught:
        parse_recording(text, "r.jsonl")
    assert str(caught.value).startswith("r.jsonl:" + problem)


def test_a_file_of_more_frames_than_any_recorder_writes_is_refused(tmp_path: Path) -> None:
    path = tmp_path / "many.jsonl"
    path.write_text(HEADER + '{"t": 0}\n' * (MAX_FRAMES + 1), encoding="utf-8")
    with pytest.raises(RecordingError, match=f"many.jsonl:{MAX_FRAMES + 2}: error: more than"):
        load_recording(path)


def test_an_endless_line_is_refused_without_reading_it_whole(tmp_path: Path) -> None:
    path = tmp_path / "long.jsonl"
    path.write_text(HEADER + " " * (MAX_LINE_CHARS + 10), encoding="utf-8")
    with pytest.raises(RecordingError, match=r"long\.jsonl:2: error: this line is longer"):
        load_recording(path)
