"""``roboscript grade --json``: the whole class report as one JSON-ready object.

It is the teacher's record of everything: hidden variants in full, tracebacks in ``debug``.
Text is capped (:mod:`roboscript.grading.text`).
"""

from __future__ import annotations

from typing import Any

from roboscript import __version__
from roboscript.grading.batch import Cell, ClassReport

__all__ = ["report_dict"]


def report_dict(report: ClassReport) -> dict[str, Any]:
    """The report: specs, students, one summary per student and test, and every run.

    Every field but ``wall_time_s`` is the same for the same specs and missions, whatever
    ``--jobs`` is. Points: ``max_points`` is what a test (or a run, its equal share) is worth,
    ``points`` what was earned.
    """
    report = report.capped()
    runs = []
    cells: dict[tuple[str, str], Cell] = {}
    for result in report.results:
        key = (result.student, result.test)
        cell = cells.get(key) or cells.setdefault(key, report.cell(*key))
        runs.append(
            {
                **result.to_dict(),
                "hidden": report.is_hidden(result),
                "points": cell.run_points(result),
                "max_points": cell.run_max_points,
            }
        )
    return {
        "roboscript": __version__,
        "isolation": report.isolation,
        "passed": report.passed,
        "specs": [spec.to_dict() for spec in report.specs],
        "students": [
            {
                "name": s.student,
                "missions": list(s.missions),
                "score": report.student_score(s.student),
                "points": report.student_points(s.student),
                "max_points": report.max_points,
            }
            for s in report.submissions
        ],
        "results": [
            {
                "student": s.student,
                "test": spec.name,
                "passed": cell.passed,
                "passed_runs": cell.passed_runs,
                "total_runs": cell.total_runs,
                "score": cell.score,
                "points": cell.points,
                "max_points": cell.max_points,
                "summary": cell.summary(),
            }
            for s in report.submissions
            for spec in report.specs
            for cell in [report.cell(s.student, spec.name)]
        ],
        "runs": runs,
    }
