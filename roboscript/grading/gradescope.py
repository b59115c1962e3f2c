"""``roboscript grade --gradescope FILE``: Gradescope's autograder ``results.json``.

Gradescope grades each submission in a container of its own: ``run_autograder`` runs
``roboscript grade /autograder/source/tests --mission /autograder/submission --gradescope
/autograder/results/results.json`` and Gradescope reads that file. Everything under
``--mission`` is then one student's submission (:func:`one_submission`).

The fields written, as Gradescope's "Autograder Specifications" document them:

* top level: ``score`` (the points earned, the sum of the tests' scores), ``execution_time``
  (seconds), ``output`` (a summary for the student), ``output_format`` and
  ``test_output_format`` (``text``: student text is shown as it is, never read as Markdown or
  HTML), ``visibility`` (``visible``), ``stdout_visibility`` (``hidden``: what ``grade``
  prints is the teacher's), ``tests``;
* one test per test spec and run variant: ``name`` (``square-50cm: seed 2``), ``number``
  (``1.2``: spec 1, run 2), ``score`` (the run's points) and ``max_score`` (its equal share of
  the spec's ``points:``), ``status`` (``passed``/``failed``), ``output`` (how it ended,
  why, every expectation) and ``visibility``: ``visible``, or ``after_published`` for a
  variant marked ``hidden: true``, which is named ``hidden run N`` and whose output is only
  pass or fail and the reason (:func:`~roboscript.grading.text.public_reason`): never its
  seed, start, world or the spec's path. Gradescope hides a student's total until grades are
  published when a test is not visible yet.

Text is capped (:mod:`roboscript.grading.text`); tracebacks are never written here.
"""

from __future__ import annotations

import json
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from roboscript.grading.batch import Cell, ClassReport, Submission, mission_for_test
from roboscript.grading.record import RunResult
from roboscript.grading.spec import TestSpec
from roboscript.grading.text import advice, format_points, public_reason, student_text

__all__ = [
    "HIDDEN_VISIBILITY",
    "gradescope_results",
    "no_submission_results",
    "one_submission",
    "several_students",
    "write_gradescope",
]

HIDDEN_VISIBILITY = "after_published"
"""Gradescope visibility of a hidden variant's test: shown once the teacher publishes grades."""


def one_submission(
    submissions: Sequence[Submission], name: str = "submission", folder: str | None = None
) -> Submission:
    """Every mission found, as one student's submission (Gradescope grades one at a time).

    With several tests, the mission named after each test runs in it, as for any student.
    ``folder`` is the submission's folder, if it is one: its runs may read everything in it.
    """
    missions = tuple(dict.fromkeys(m for s in submissions for m in s.missions))
    problem = next((s.problem for s in submissions if s.problem), "")
    if folder is not None:
        return Submission(name, missions, folder, problem, folder)
    root = next((s.root for s in submissions), None)
    own = tuple(dict.fromkeys(f for s in submissions for f in s.own))
    return Submission(name, missions, None, problem, root, own)


def several_students(submissions: Sequence[Submission], specs: Sequence[TestSpec]) -> str | None:
    """Why what was found is not one student's submission, or ``None`` when it is.

    One submission holds one mission, or one per test named after it. Anything else (a class
    folder, two versions of a mission) would grade several students as one and keep one
    mission per test at random: it is refused, in one sentence naming the missions.
    """
    if len(submissions) < 2:
        return None
    whole = one_submission(submissions)
    used = {mission_for_test(whole, spec) for spec in specs}
    if not set(whole.missions) - used:
        return None
    names = ", ".join(s.student for s in submissions[:5])
    if len(submissions) > 5:
        names += ", ..."
    return (
        f"a Gradescope submission is one student's, with one mission per test named after it,"
        f" but this one holds {len(submissions)} ({names}): grade a class without"
        f" --gradescope, or submit one mission per test"
    )


def _run_output(report: ClassReport, result: RunResult, cell: Cell) -> str:
    hidden = report.is_hidden(result)
    head = {"passed": "PASSED", "failed": "FAILED"}.get(result.status, f"FAILED ({result.status})")
    points = (
        f"{format_points(cell.run_points(result))} of {format_points(cell.run_max_points)} points"
    )
    lines = [f"{head}, {points}, score {result.score * 100:.0f}%"]
    reason = public_reason(result, hidden)
    if reason:
        lines.append(reason)
    if hidden:
        lines.append(
            "This run is hidden: its seed and start are not shown. Make the mission work from"
            " any start."
        )
        return "\n".join(lines)
    lines.append(f"Run: {result.label}")
    if result.verdicts:
        lines.append("")
        for verdict in result.verdicts:
            lines.append(f"{'PASS' if verdict.passed else 'FAIL'} {verdict.text}")
            if verdict.first_violation_s is not None:
                lines.append(f"     first failed at {verdict.first_violation_s:.2f} s")
    elif not result.passed:
        lines.append(advice(result.status))
    return "\n".join(lines)


def _test(number: str, name: str, score: float, max_score: float, passed: bool) -> dict[str, Any]:
    return {
        "name": name,
        "number": number,
        "score": score,
        "max_score": max_score,
        "status": "passed" if passed else "failed",
    }


def gradescope_results(report: ClassReport) -> dict[str, Any]:
    """The report of one submission as Gradescope's ``results.json``.

    Raises:
        ValueError: The report holds more than one student.
    """
    report = report.capped()
    if len(report.submissions) != 1:
        raise ValueError(
            f"a Gradescope results.json is for one submission; this report has"
            f" {len(report.submissions)}"
        )
    student = report.submissions[0].student
    tests: list[dict[str, Any]] = []
    summary: list[str] = []
    for i, spec in enumerate(report.specs, start=1):
        cell = report.cell(student, spec.name)
        for result in cell.results:
            hidden = report.is_hidden(result)
            test = _test(
                f"{i}.{result.variant + 1}",
                f"{spec.name}: {report.public_label(result)}",
                cell.run_points(result),
                cell.run_max_points,
                result.passed,
            )
            test["output"] = _run_output(report, result, cell)
            test["visibility"] = HIDDEN_VISIBILITY if hidden else "visible"
            tests.append(test)
        summary.append(
            f"{spec.name}: {cell.passed_runs} of {cell.total_runs} runs passed,"
            f" {format_points(cell.points)}/{format_points(cell.max_points)} points"
        )
    total = round(sum(t["score"] for t in tests), 4)
    summary.append(f"Total: {format_points(total)}/{format_points(report.max_points)} points.")
    if report.isolation:
        summary.append(f"Isolation: {report.isolation}.")
    if any(report.is_hidden(r) for r in report.results):
        summary.append("Hidden runs show their result once grades are published.")
    return _results(total, "\n".join(summary), tests, sum(r.wall_time_s for r in report.results))


def no_submission_results(specs: Sequence[TestSpec], reason: str) -> dict[str, Any]:
    """``results.json`` when the submission holds no mission: every run failed, ``reason`` why."""
    text = f"{student_text(reason)}. {advice('missing')}"  # no folder of the teacher's
    tests = []
    for i, spec in enumerate(specs, start=1):
        share = round(spec.max_points / len(spec.variants), 4) if spec.variants else 0.0
        for variant in spec.variants:
            test = _test(
                f"{i}.{variant.index + 1}",
                f"{spec.name}: {variant.public_label}",
                0.0,
                share,
                False,
            )
            test["output"] = text
            test["visibility"] = HIDDEN_VISIBILITY if variant.hidden else "visible"
            tests.append(test)
    return _results(0.0, text, tests, 0.0)


def _results(
    score: float, output: str, tests: list[dict[str, Any]], seconds: float
) -> dict[str, Any]:
    return {
        "score": score,
        "execution_time": round(seconds),
        "output": output,
        "output_format": "text",
        "test_output_format": "text",
        "visibility": "visible",
        "stdout_visibility": "hidden",
        "tests": tests,
    }


def write_gradescope(report: ClassReport | dict[str, Any], path: str | Path) -> None:
    """Write :func:`gradescope_results` (or ready results) to ``path`` as UTF-8 JSON."""
    data = report if isinstance(report, dict) else gradescope_results(report)
    target = Path(path)
    target.parent.mkdir(parents=True, exist_ok=True)
    target.write_text(json.dumps(data, indent=2, ensure_ascii=False) + "\n", encoding="utf-8")
