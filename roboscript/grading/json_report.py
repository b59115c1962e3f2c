"""``roboscript grade --json``: the whole class report as one JSON-ready object."""

from __future__ import annotations

from typing import Any

from roboscript import __version__
from roboscript.grading.batch import ClassReport

__all__ = ["report_dict"]


def report_dict(report: ClassReport) -> dict[str, Any]:
    """The report: specs, students, one summary per student and test, and every run.

    Every field but ``wall_time_s`` is the same for the same specs and missions, whatever
    ``--jobs`` is.
    """
    return {
        "roboscript": __version__,
        "passed": report.passed,
        "specs": [spec.to_dict() for spec in report.specs],
        "students": [
            {
                "name": s.student,
                "missions": list(s.missions),
                "score": report.student_score(s.student),
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
                "summary": cell.summary(),
            }
            for s in report.submissions
            for spec in report.specs
            for cell in [report.cell(s.student, spec.name)]
        ],
        "runs": [result.to_dict() for result in report.results],
    }
