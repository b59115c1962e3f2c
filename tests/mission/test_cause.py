"""Why a mission entered each state: the cause the runner records for every transition."""

from __future__ import annotations

import json
import math
from pathlib import Path

from helpers import run_cli

from roboscript.mission.cause import CLAIM_TEXT_CHARS, TransitionCause


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


def test_a_cause_read_back_from_its_json_says_the_same() -> None:
    cause = TransitionCause(
        "done", "turn", action="rotate", condition="visits.turn >= 3", values={"visits.turn": 3}
    )
    back = TransitionCause.from_claim(json.loads(json.dumps(cause.to_json())), source="turn")
    assert back == cause
    assert back.text() == "rotate done, and 'visits.turn >= 3' held (visits.turn = 3)"
    seen = TransitionCause("when", "go", condition="r", values={"r": math.inf, "b": True})
    assert TransitionCause.from_claim(seen.to_json(), source="go") == seen


def test_a_claimed_cause_takes_its_state_and_text_from_the_caller_never_the_claim() -> None:
    claim = {"kind": "failed", "from": "forged", "reason": "stalled", "text": "full marks"}
    cause = TransitionCause.from_claim(claim, source="drive")
    assert cause is not None
    assert cause.source == "drive"
    assert cause.text() == "the action failed: stalled"
    start = TransitionCause.from_claim({"kind": "start", "from": "x"}, source="drive")
    assert start is not None and start.source is None


def test_a_hostile_claimed_cause_is_cut_to_printable_text_and_finite_numbers() -> None:
    claim = {
        "kind": "when",
        "condition": "\x1b[2J</script>\x00\u2028" + "x" * 100_000,
        "values": {
            "<b>\n": 1,
            "huge": 10**400,
            "list": [1, 2],
            "nan": float("nan"),
            **{f"v{i}": i for i in range(50)},
        },
        "timeout_s": -5,
        "action": {"not": "text"},
    }
    cause = TransitionCause.from_claim(claim, source="s")
    assert cause is not None
    assert cause.condition is not None
    assert len(cause.condition) == CLAIM_TEXT_CHARS + 1  # and an ellipsis
    assert cause.condition.isprintable() and cause.condition.startswith(" [2J</script>  x")
    assert dict(cause.values) == {"<b> ": 1} | {f"v{i}": i for i in range(4)}
    assert (cause.action, cause.timeout_s) == (None, None)
    assert json.dumps(cause.to_json(), allow_nan=False)  # JSON a page can hold


def test_a_claim_of_an_unknown_kind_or_shape_is_no_cause() -> None:
    for claim in (None, "done", [], {"kind": "passed"}, {"kind": ["done"]}, {}):
        assert TransitionCause.from_claim(claim, source="s") is None
