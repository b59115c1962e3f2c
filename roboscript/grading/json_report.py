"""``roboscript grade --json``: the whole class report as one JSON-ready object.

It is the teacher's record of everything: hidden variants in full, tracebacks in ``debug``.
Text is capped (:mod:`roboscript.grading.text`).
"""

from __future__ import annotations

import json
from collections.abc import Callable, Iterator
from typing import Any, TextIO

from roboscript import __version__
from roboscript.grading.batch import Cell, ClassReport

__all__ = ["report_dict", "write_report_json"]


def report_dict(report: ClassReport) -> dict[str, Any]:
    """The report: specs, students, one summary per student and test, and every run.

    Every field but ``wall_time_s`` is the same for the same specs and missions, whatever
    ``--jobs`` is. Points: ``max_points`` is what a test (or a run, its equal share) is worth,
    ``points`` what was earned.
    """
    report = report.capped()
    return _report(report, list(_runs(report)))


def write_report_json(report: ClassReport, stream: TextIO) -> None:
    """Write :func:`report_dict` to ``stream`` as indented JSON, one run at a time: no more
    than one run's record is held, however large the class."""
    report = report.capped()
    runs = _Streamed(len(report.results), lambda: _runs(report))
    encoder = json.JSONEncoder(indent=2, ensure_ascii=False)
    stream.writelines(encoder.iterencode(_report(report, runs)))
    stream.write("\n")


class _Streamed(list[dict[str, Any]]):
    """A list JSON's encoder writes item by item as ``make`` yields them (it takes lists
    only), never holding them all."""

    def __init__(self, length: int, make: Callable[[], Iterator[dict[str, Any]]]) -> None:
        super().__init__()
        self._length = length
        self._make = make

    def __len__(self) -> int:
        return self._length

    def __iter__(self) -> Iterator[dict[str, Any]]:
        return self._make()


def _runs(report: ClassReport) -> Iterator[dict[str, Any]]:
    cells: dict[tuple[str, str], Cell] = {}
    for result in report.results:
        key = (result.student, result.test)
        cell = cells.get(key) or cells.setdefault(key, report.cell(*key))
        yield {
            **report.in_full(result).to_dict(),
            "hidden": report.is_hidden(result),
            "points": cell.run_points(result),
            "max_points": cell.run_max_points,
        }


def _report(report: ClassReport, runs: list[dict[str, Any]]) -> dict[str, Any]:
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
