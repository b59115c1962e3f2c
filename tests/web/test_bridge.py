"""The functions the browser app calls, run here in CPython: the same package, the same JSON."""

from __future__ import annotations

import json

from helpers import MISSIONS, run_cli

from roboscript.web.bridge import check_text, diagram_text, run_text


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


def test_the_diagram_is_svg_and_nothing_for_a_broken_mission() -> None:
    text = (MISSIONS / "square.yaml").read_text(encoding="utf-8")
    assert diagram_text("square.yaml", text).startswith("<?xml")
    assert diagram_text("square.yaml", "states: [") == ""


def test_a_file_name_cannot_leave_the_scratch_folder() -> None:
    text = (MISSIONS / "square.yaml").read_text(encoding="utf-8").replace("drive:", "drvie:")
    problems = json.loads(check_text("../../etc/x.yaml", text))["problems"]
    assert problems[0]["text"].startswith("x.yaml:6:10: error:")
