"""Why a mission entered each state: the cause the runner records for every transition."""

from __future__ import annotations

import json
import math
from pathlib import Path

from helpers import run_cli

from roboscript.mission.cause import TransitionCause


def test_each_kind_of_cause_reads_as_a_student_would_say_it() -> None:
    assert TransitionCause("start").text() == "the mission started"
    assert TransitionCause("done", "side", action="drive").text() == "drive done"
    assert (
        TransitionCause("failed", "side", action="drive", reason="stalled").text()
        == "drive failed: stalled"
    )
    assert (
        TransitionCause("timeout", "wait", timeout_s=2.5).text()
        == "the state timed out after 2.5 s"
    )
    held = TransitionCause(
        "when",
        "go",
        condition="range.distance_cm < 20 or bumper.any",
        values={"range.distance_cm": 18.25, "bumper.any": False},
    )
    assert held.text() == (
        "'range.distance_cm < 20 or bumper.any' held (range.distance_cm = 18.2, bumper.any = false)"
    )


def test_a_route_taken_on_a_condition_names_it_with_its_values() -> None:
    cause = TransitionCause(
        "done", "beep", action="play_tone", condition="visits.side >= 4", values={"visits.side": 4}
    )
    assert cause.text() == "play_tone done, and 'visits.side >= 4' held (visits.side = 4)"


def test_a_failure_reason_in_a_state_is_the_sentence_failure_reasons_use() -> None:
    assert (
        TransitionCause("failed", "side", action="drive", reason="stalled").in_state()
        == "drive failed in state 'side': stalled"
    )
    assert TransitionCause("timeout", "w", timeout_s=5).in_state() == (
        "state 'w' timed out after 5 s"
    )


def test_a_range_sensor_that_saw_nothing_is_written_as_null_and_said_in_words() -> None:
    cause = TransitionCause(
        "when", "go", condition="range.distance_cm > 50", values={"range.distance_cm": math.inf}
    )
    assert cause.to_json()["values"] == {"range.distance_cm": None}
    assert cause.text().endswith("(range.distance_cm = nothing seen)")
    json.dumps(cause.to_json(), allow_nan=False)  # a record never holds Infinity


def test_run_json_says_why_each_state_was_entered(tmp_path: Path) -> None:
    (tmp_path / "m.yaml").write_text(
        "mission: m\nstates:\n"
        "  go:\n    do: {drive: {distance: 20 cm}}\n    on: {done: again, failed: end}\n"
        "  again:\n    do: {wait: {duration: 200 ms}}\n    on:\n      done:\n"
        '        - {if: "visits.again >= 2", goto: pause}\n        - {goto: again}\n'
        "  pause:\n    timeout: 300 ms\n    on: {timeout: end}\n"
        "  end: {final: success}\n",
        encoding="utf-8",
    )
    result = run_cli("run", "m.yaml", "--json", cwd=tmp_path)
    assert result.returncode == 0, result.stderr
    summary = json.loads(result.stdout)
    said = [(t["state"], t["cause"]["text"]) for t in summary["transitions"]]
    assert said == [
        ("go", "the mission started"),
        ("again", "drive done"),
        ("again", "wait done"),  # back into the same state: a transition of its own
        ("pause", "wait done, and 'visits.again >= 2' held (visits.again = 2)"),
        ("end", "the state timed out after 0.3 s"),
    ]
    assert [t["t_s"] for t in summary["transitions"]] == [t for t, _ in summary["states"]]
    # the terminal timeline says the same
    shown = run_cli("run", "m.yaml", cwd=tmp_path).stderr
    assert "  end  [the state timed out after 0.3 s]" in shown
