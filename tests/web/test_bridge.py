"""The functions the browser app calls, run here in CPython: the same package, the same JSON."""

from __future__ import annotations

import json
import re
import subprocess
import sys
from pathlib import Path

import pytest
from helpers import HANG_BOUND_S, MISSIONS, run_cli
from test_watchdog import LOOPING_BEHAVIOUR_FILE, SPIN, no_timer_signal
from web_app import FLOOD

from roboscript.web.bridge import _folder as scratch_folder
from roboscript.web.bridge import check_text, diagram_text, grade_text, load_specs, run_text

RING = (
    "world: ring\nstart: {x: 300, y: 500, heading: 0}\n"
    "walls:\n  - box: {x: 0, y: 0, width: 2000, height: 1000}\n"
)


def test_a_world_file_opened_as_the_mission_says_how_the_page_runs_a_mission_in_it() -> None:
    problems = json.loads(check_text("ring arena.yaml", RING))["problems"]
    assert [p["message"] for p in problems] == ["this is a world file, not a mission"]
    assert problems[0]["line"] == 1
    # the file as the page keeps it, and the page's own controls: a page has no --world
    assert problems[0]["hint"] == (
        'it is a simulator world: to run your mission in it, set World to "the mission\'s own"'
        " and name it in your mission: 'world: ring_arena.yaml' in YAML,"
        ' world = "ring_arena.yaml" in a Python mission\'s class'
    )
    assert "roboscript run" not in problems[0]["text"]


@pytest.mark.parametrize("mission", ["square.yaml", "square.py"])
def test_a_mission_that_names_the_world_as_the_page_advised_runs_in_it(mission: str) -> None:
    check_text("ring arena.yaml", RING)  # what the page does with a file opened in it
    text = (MISSIONS / mission).read_text(encoding="utf-8")
    if mission.endswith(".py"):
        text = text.replace("    side = state(", '    world = "ring_arena.yaml"\n    side = state(')
    else:
        text = text.replace("initial:", "world: ring_arena.yaml\ninitial:")
    answer = json.loads(run_text(mission, text))
    assert answer["problems"] == []
    assert answer["summary"]["sim"]["world"] == "ring"


def test_a_profile_opened_as_the_mission_says_how_the_page_runs_a_mission_on_it() -> None:
    profile = "extends: mirto\nname: fast\nmax_speed_mm_s: 300\n"
    [problem] = json.loads(check_text("fast.yaml", profile))["problems"]
    assert problem["message"] == "this is a profile file, not a mission"
    assert 'set Robot to "the mission\'s own"' in problem["hint"]
    assert "'robot: fast.yaml' in YAML" in problem["hint"]
    text = (MISSIONS / "square.yaml").read_text(encoding="utf-8")
    answer = json.loads(
        run_text("square.yaml", text.replace("initial:", "robot: fast.yaml\ninitial:"))
    )
    assert answer["summary"]["robot"] == "fast"


def test_a_test_spec_opened_as_the_mission_points_to_the_practice_grade() -> None:
    spec = (MISSIONS / "teacher" / "square" / "test.yaml").read_text(encoding="utf-8")
    [problem] = json.loads(check_text("test.yaml", spec))["problems"]
    assert problem["message"] == "this is a test spec file, not a mission"
    assert problem["hint"] == (
        'it is a teacher\'s test spec: open it with "Open a test spec…" under Practice grade,'
        ' then press "✓ Grade my mission"'
    )


def test_check_finds_a_mistake_at_its_line_and_column() -> None:
    text = (MISSIONS / "square.yaml").read_text(encoding="utf-8").replace("drive:", "drvie:")
    problems = json.loads(check_text("square.yaml", text))["problems"]
    assert problems == [
        {
            "line": 6,
            "col": 10,
            "severity": "error",
            "message": "unknown action 'drvie'",
            "hint": "did you mean 'drive'?",
            "text": "square.yaml:6:10: error: unknown action 'drvie' (did you mean 'drive'?)",
        }
    ]


def test_a_run_in_the_page_gives_the_json_of_run_json() -> None:
    text = (MISSIONS / "square.yaml").read_text(encoding="utf-8")
    answer = json.loads(run_text("square.yaml", text, seed=3))
    command_line = json.loads(
        run_cli("run", "missions/square.yaml", "--json", "--seed", "3").stdout
    )
    assert answer["summary"] == command_line
    assert answer["viewer"].startswith('<div class="rs-viewer"')


def test_a_mission_with_errors_is_not_run() -> None:
    answer = json.loads(run_text("m.yaml", "mission: m\nstates: []\n"))
    assert answer["summary"] is None and answer["viewer"] is None
    assert answer["problems"][0]["text"].startswith("m.yaml:2:1: error:")


def test_a_python_mission_is_checked_and_run_too() -> None:
    text = (MISSIONS / "square.py").read_text(encoding="utf-8")
    assert json.loads(check_text("square.py", text))["problems"] == []
    assert json.loads(run_text("square.py", text))["summary"]["outcome"] == "success"


def test_a_condition_that_loops_forever_ends_the_run_at_its_line_not_the_tab() -> None:
    with no_timer_signal():  # a browser tab has no timer signal
        summary = json.loads(run_text("spin.py", SPIN))["summary"]
    assert summary["outcome"] == "error"
    assert summary["reason"].startswith(
        "the mission's code did not return for 5 s and was stopped at spin.py:2"
    )
    assert " in far: is there a loop that never ends?" in summary["reason"]


def test_a_file_that_loops_forever_when_loaded_is_a_problem_at_its_line(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    # the page works in the folder above its scratch folder (/home/pyodide), so the stuck
    # place's file is written relative to it there: the student still sees only the name
    monkeypatch.chdir(scratch_folder().parent)
    with no_timer_signal():
        problems = json.loads(check_text("hang.py", LOOPING_BEHAVIOUR_FILE))["problems"]
    assert len(problems) == 1
    line = problems[0]["line"]
    assert line in (3, 4)  # a line of the endless loop
    assert problems[0]["text"].startswith(f"hang.py:{line}:1: error: the mission")
    assert "did not return for 5 s" in problems[0]["message"]
    assert f"stopped at hang.py:{line} in <module>:" in problems[0]["message"]


def test_a_behaviour_file_that_loops_when_loaded_is_a_problem_at_the_missions_first_line() -> None:
    # the loop is at line 3 of the behaviour file, not of the mission: the mission's problem
    # is at its first line, and the message names the file and line that loop
    (scratch_folder() / "loops.py").write_text(LOOPING_BEHAVIOUR_FILE, encoding="utf-8")
    mission = "behaviours: [loops.py]\nstates:\n  s:\n    initial: true\n    final: success\n"
    with no_timer_signal():
        problems = json.loads(check_text("uses.yaml", mission))["problems"]
    assert len(problems) == 1
    assert problems[0]["line"] == 1
    assert re.search(r"stopped at \S*loops\.py:[34] in <module>:", problems[0]["message"])


def test_the_diagram_is_svg_and_nothing_for_a_broken_mission() -> None:
    text = (MISSIONS / "square.yaml").read_text(encoding="utf-8")
    assert diagram_text("square.yaml", text).startswith("<?xml")
    assert diagram_text("square.yaml", "states: [") == ""


def test_a_file_name_cannot_leave_the_scratch_folder() -> None:
    text = (MISSIONS / "square.yaml").read_text(encoding="utf-8").replace("drive:", "drvie:")
    problems = json.loads(check_text("../../etc/x.yaml", text))["problems"]
    assert problems[0]["text"].startswith("x.yaml:6:10: error:")


def _square_spec(hidden_first: bool = False) -> dict[str, str]:
    text = (MISSIONS / "teacher" / "square" / "test.yaml").read_text(encoding="utf-8")
    if hidden_first:
        text = text.replace("- {seed: 1}", "- {seed: 1, hidden: true}")
    return {"square/test.yaml": text}


def test_a_shipped_spec_is_read_and_a_hidden_run_named_only_by_number() -> None:
    answer = json.loads(load_specs(json.dumps(_square_spec(hidden_first=True))))
    assert answer["problems"] == []
    (spec,) = answer["specs"]
    assert spec["test"] == "square-50cm" and spec["points"] == 3.0
    assert [r["label"] for r in spec["runs"]] == [
        "hidden run 1",
        "seed 2, start (300, -200) mm 0°",
        "seed 3, start (0, 0) mm 30°",
    ]


def test_a_spec_with_a_mistake_is_a_problem_at_its_line() -> None:
    files = _square_spec()
    files["square/test.yaml"] = files["square/test.yaml"].replace("tones:", "tonez:")
    answer = json.loads(load_specs(json.dumps(files), "opened"))
    assert answer["specs"] == []
    assert answer["problems"][0]["text"].startswith("square/test.yaml:")
    assert "tonez" in answer["problems"][0]["text"]


def test_a_spec_file_name_cannot_leave_the_specs_folder() -> None:
    answer = json.loads(
        load_specs(json.dumps({"../../../test.yaml": _square_spec()["square/test.yaml"]}))
    )
    assert answer["specs"][0]["path"].endswith("/specs/shipped/test.yaml")


def test_the_practice_grade_shows_each_run_but_no_detail_of_a_hidden_one() -> None:
    spec = json.loads(load_specs(json.dumps(_square_spec(hidden_first=True))))["specs"][0]
    bad = (MISSIONS / "teacher" / "square" / "bad.yaml").read_text(encoding="utf-8")
    grade = json.loads(grade_text("square.yaml", bad, spec["path"]))["grade"]
    assert (grade["points"], grade["max_points"], grade["passed_runs"]) == (0.0, 3.0, 0)
    hidden, shown = grade["runs"][0], grade["runs"][1]
    assert hidden["label"] == "hidden run 1" and hidden["viewer"] is None
    assert all(set(v) == {"name", "passed", "required", "weight"} for v in hidden["verdicts"])
    assert hidden["message"].startswith("final_pose_within failed by ")  # margin, no place
    assert shown["viewer"].startswith('<div class="rs-viewer"')
    failed = [v for v in shown["verdicts"] if not v["passed"]]
    assert [v["name"] for v in failed] == ["final_pose_within", "path_visits", "turns", "tones"]
    assert failed[1]["text"].startswith("path_visits failed by ") and failed[1]["required"]
    assert shown["message"].startswith("path_visits failed by ")  # the required one first


def test_parallel_without_its_brackets_is_answered_in_the_page_with_the_students_actions() -> None:
    text = (MISSIONS / "square.py").read_text(encoding="utf-8")
    text = text.replace(
        "    corner = state(Rotate(angle_deg=90),",
        "    corner = state(Parallel(Rotate(angle_deg=90), PlayTone(frequency_hz=880),"
        " Wait(duration_s=1)),",
    ).replace("import Drive,", "import Drive, Parallel, Wait,")
    [problem] = json.loads(check_text("square.py", text))["problems"]
    assert (problem["line"], problem["message"]) == (18, "parallel takes a list of actions, in [ ]")
    assert problem["hint"] == (
        "write Parallel([Rotate(angle_deg=90), PlayTone(frequency_hz=880), Wait(duration_s=1)])"
    )


def test_the_pages_replay_keeps_what_the_mission_printed_while_it_loaded() -> None:
    text = 'print("loading my square")\n' + (MISSIONS / "square.py").read_text(encoding="utf-8")
    viewer = json.loads(run_text("square.py", text))["viewer"]
    assert '"printed_before_start":["loading my square"]' in viewer


def test_two_programs_using_the_page_functions_at_once_never_share_a_file() -> None:
    # Each checks and grades its own mission and spec files, whatever the other writes.
    code = "from roboscript.web.bridge import _folder; print(_folder())"
    other = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, check=True,
        timeout=HANG_BOUND_S,
    ).stdout.strip()  # fmt: skip
    assert other and Path(other) != scratch_folder()
    assert Path(other).parent != scratch_folder().parent  # the specs' folder is beside it


def test_a_flood_of_print_is_counted_in_one_sentence_and_the_record_keeps_its_bound() -> None:
    answer = json.loads(run_text("flood.py", FLOOD))
    assert answer["summary"]["outcome"] == "success"
    assert answer["note"] == (
        "Your mission printed 2500 lines: the replay keeps the first 2000 and counted the other"
        " 500 (print less often, or log() a value to plot it)."
    )


def test_a_run_that_printed_what_the_record_keeps_has_no_note() -> None:
    answer = json.loads(run_text("flood.py", FLOOD.replace("2500", "2000")))
    assert answer["note"] == ""
