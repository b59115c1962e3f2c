"""Reports of a large class: the work grows with the runs (never their square), and every
report stays bounded and valid for thousands of runs. Built by hand (no simulation)."""

from __future__ import annotations

from dataclasses import fields
from pathlib import Path
from typing import Any

from hand_graded import hand_spec, student_runs

from roboscript.grading.batch import ClassReport, Submission
from roboscript.grading.gradebook import gradebook_csv
from roboscript.grading.html_report import write_html
from roboscript.grading.json_report import write_report_json
from roboscript.grading.junit import junit_xml
from roboscript.grading.record import RunResult
from roboscript.grading.table import format_table

READS = [0]
"""How many times a run's ``student`` was read: the work of finding a student's runs."""


class _Counted(RunResult):
    """A run that counts the reads of its ``student`` (a search of the runs reads it once
    per run looked at)."""

    def __getattribute__(self, name: str) -> Any:
        if name == "student":
            READS[0] += 1
        return super().__getattribute__(name)


def _counted(result: RunResult) -> RunResult:
    return _Counted(**{f.name: getattr(result, f.name) for f in fields(result)})


def synthetic_class(tmp_path: Path, students: int, counted: bool = False) -> ClassReport:
    """A class of ``students`` (three runs each, every third one's run 2 crashed and run 3
    failed), as :mod:`hand_graded` makes one student's runs."""
    spec = hand_spec(tmp_path)
    names = [f"student-{i:05d}" for i in range(students)]
    results = [r for i, name in enumerate(names) for r in student_runs(spec, name, i % 3 > 0)]
    if counted:
        results = [_counted(r) for r in results]
    submissions = [Submission(name, (f"class/{name}.yaml",)) for name in names]
    return ClassReport([spec], submissions, results, dict(spec.worlds))


def _reads_reporting(tmp_path: Path, students: int) -> int:
    """The ``student`` reads of writing the table, the gradebook, JUnit and --json."""
    report = synthetic_class(tmp_path, students, counted=True)
    READS[0] = 0
    format_table(report)
    gradebook_csv(report)
    junit_xml(report)
    with (tmp_path / "report.json").open("w", encoding="utf-8") as stream:
        write_report_json(report, stream)
    write_html(report, tmp_path / f"html-{students}")
    return READS[0]


def test_reporting_a_class_looks_each_run_up_a_fixed_number_of_times(tmp_path: Path) -> None:
    # Counted, not timed: four times the class is four times the work. Searching every run
    # for each student's cell made it sixteen times (a class of thousands took hours).
    small = _reads_reporting(tmp_path, 30)
    large = _reads_reporting(tmp_path, 120)
    assert large <= 4.5 * small, (small, large)
