"""The practice grade in a real headless Chromium, from file:// with the network off.

The teacher ships test specs in the page (``web build --spec``) or the student opens one; the
page grades the mission in the editor against it with roboscript's grading code, and shows
each expectation, the score and points, and the run's replay. The points equal what
``roboscript grade`` gives the same mission. Waits are long enough for a saturated machine;
nothing here is timed.
"""

from __future__ import annotations

import json
import shutil
from collections.abc import Iterator
from pathlib import Path

import pytest
from browser import Browser
from helpers import MISSIONS, run_cli
from web_app import LONG_S, build_or_skip, open_offline

pytestmark = pytest.mark.timeout(1800)

TEACHER = MISSIONS / "teacher"


@pytest.fixture(scope="module")
def page(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Browser]:
    specs = [TEACHER / t / "test.yaml" for t in ("square", "line-track")]
    built = build_or_skip(tmp_path_factory.mktemp("web") / "app", specs)
    # with node at hand, the page's Python was compiled at build time (it starts faster)
    assert built.compiled or shutil.which("node") is None
    browser = open_offline(built.page, tmp_path_factory.mktemp("profile"))
    try:
        browser.wait_for("document.body.dataset.ready !== undefined", LONG_S)
        yield browser
    finally:
        browser.close()


def _grade(page: Browser, name: str, text: str, test: str) -> dict[str, object]:
    """Put the mission in the editor, pick the test, grade; the shown grade's data."""
    page.evaluate(
        f"document.querySelector('[data-role=name]').value = {json.dumps(name)};"
        f"document.querySelector('.CodeMirror').CodeMirror.setValue({json.dumps(text)});"
        "document.body.removeAttribute('data-graded');"
    )
    options = page.evaluate(
        "Array.from(document.querySelectorAll('[data-role=spec] option'))"
        ".map(function (o) { return [o.textContent, o.value]; })"
    )
    path = dict(options)[test]
    page.evaluate(
        f"var s = document.querySelector('[data-role=spec]'); s.value = {json.dumps(path)};"
        "s.dispatchEvent(new Event('change'));"
    )
    page.wait_for("!document.querySelector('[data-action=grade]').disabled", LONG_S)
    page.evaluate("document.querySelector('[data-action=grade]').click()")
    page.wait_for("document.body.dataset.graded", LONG_S)
    shown: dict[str, object] = page.evaluate(
        """(function () {
          var total = document.querySelector('[data-role=grade-total]');
          return {
            points: total && parseFloat(total.dataset.points),
            max_points: total && parseFloat(total.dataset.maxPoints),
            total: total && total.textContent,
            runs: Array.from(document.querySelectorAll('[data-role=grade] [data-run]'))
              .map(function (r) { return {
                status: r.dataset.status, score: parseFloat(r.dataset.score),
                points: parseFloat(r.dataset.points), text: r.textContent,
                failed: Array.from(r.querySelectorAll('[data-passed="0"]'))
                  .map(function (v) { return v.dataset.name; }) }; })
          };
        })()"""
    )
    return shown


def _command_line(test: str, mission: Path, tmp_path: Path) -> dict[str, object]:
    answer = json.loads(
        run_cli(
            "grade", str(TEACHER / test / "test.yaml"), "--mission", str(mission), "--json"
        ).stdout
    )
    return answer  # type: ignore[no-any-return]


def test_the_shipped_tests_are_offered_once_python_is_ready(page: Browser) -> None:
    assert page.evaluate("document.body.dataset.ready") == "1"
    offered = page.evaluate(
        "Array.from(document.querySelectorAll('[data-role=spec] option'))"
        ".map(function (o) { return o.textContent; })"
    )
    assert sorted(offered) == ["line-track-lap", "square-50cm"]
    assert page.errors == []


def test_a_correct_mission_scores_full_points(page: Browser) -> None:
    good = (TEACHER / "square" / "good.yaml").read_text(encoding="utf-8")
    shown = _grade(page, "square.yaml", good, "square-50cm")
    assert (shown["points"], shown["max_points"]) == (3.0, 3.0)
    runs = shown["runs"]
    assert isinstance(runs, list) and [r["status"] for r in runs] == ["passed"] * 3
    assert str(shown["total"]).startswith("✓ square-50cm: 3 of 3 points, 3 of 3 runs passed")


def test_a_broken_mission_shows_the_failed_expectation_and_the_command_lines_points(
    page: Browser, tmp_path: Path
) -> None:
    bad = TEACHER / "line-track" / "bad.yaml"
    shown = _grade(page, "bad.yaml", bad.read_text(encoding="utf-8"), "line-track-lap")
    graded = _command_line("line-track", bad, tmp_path)
    runs = shown["runs"]
    assert isinstance(runs, list)
    cli_runs = graded["runs"]
    assert isinstance(cli_runs, list)
    assert [(r["status"], r["score"], r["points"]) for r in runs] == [
        (r["status"], r["score"], r["points"]) for r in cli_runs
    ]
    students = graded["students"]
    assert isinstance(students, list)
    assert shown["points"] == students[0]["points"] and shown["max_points"] == 3.0
    assert runs[0]["failed"] == ["check: stays_on_line"]
    assert "check: stays_on_line failed by" in runs[0]["text"]
    assert "regions_in_order" in runs[2]["failed"]


def test_the_graded_run_replays_where_it_first_failed(page: Browser) -> None:
    page.wait_for("document.querySelector('[data-role=viewer] .rs-viewer') !== null", LONG_S)
    page.wait_for(
        "document.querySelector('[data-role=viewer] .rs-viewer').dataset.ready === '1'", LONG_S
    )
    assert page.evaluate("document.querySelector('[data-role=viewer]').dataset.showing") == (
        "grade run 1"
    )
    page.click("[data-run='1'] [data-action=grade-replay]")
    assert page.evaluate("document.querySelector('[data-role=viewer]').dataset.showing") == (
        "grade run 2"
    )
    assert page.errors == []


def test_a_mission_with_a_mistake_is_invalid_on_every_run_at_its_line(page: Browser) -> None:
    good = (TEACHER / "square" / "good.yaml").read_text(encoding="utf-8")
    shown = _grade(page, "square.yaml", good.replace("rotate:", "rotat:"), "square-50cm")
    runs = shown["runs"]
    assert isinstance(runs, list) and [r["status"] for r in runs] == ["invalid"] * 3
    assert "square.yaml:12:10: error: unknown action 'rotat'" in runs[0]["text"]
    assert shown["points"] == 0.0


def test_a_spec_the_student_opens_is_offered_and_graded(page: Browser) -> None:
    chooser = page._call(
        "Runtime.evaluate", {"expression": "document.querySelector('[data-role=spec-file]')"}
    )
    spec = TEACHER / "corridor" / "test.yaml"
    page._call(
        "DOM.setFileInputFiles",
        {"files": [str(spec)], "objectId": chooser["result"]["objectId"]},
    )
    page.wait_for(
        "Array.from(document.querySelectorAll('[data-role=spec] option'))"
        ".some(function (o) { return o.textContent === 'corridor-wall-follow'; })",
        LONG_S,
    )
    good = (TEACHER / "corridor" / "good.yaml").read_text(encoding="utf-8")
    shown = _grade(page, "corridor.yaml", good, "corridor-wall-follow")
    assert (shown["points"], shown["max_points"]) == (3.0, 3.0)


def test_a_spec_with_a_mistake_is_shown_at_its_line(page: Browser, tmp_path: Path) -> None:
    spec = tmp_path / "test.yaml"
    text = (TEACHER / "square" / "test.yaml").read_text(encoding="utf-8")
    spec.write_text(text.replace("final_pose_within:", "final_pose_witin:"), encoding="utf-8")
    chooser = page._call(
        "Runtime.evaluate", {"expression": "document.querySelector('[data-role=spec-file]')"}
    )
    page._call(
        "DOM.setFileInputFiles", {"files": [str(spec)], "objectId": chooser["result"]["objectId"]}
    )
    shown = page.wait_for(
        "document.querySelector('[data-role=spec-problems] li') &&"
        " document.querySelector('[data-role=spec-problems] li').textContent",
        LONG_S,
    )
    assert shown.startswith("test.yaml:")
    assert "final_pose_witin" in shown and "final_pose_within" in shown
