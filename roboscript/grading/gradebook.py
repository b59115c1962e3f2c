"""``roboscript grade --csv FILE``: a gradebook, one row per student, one column per test.

Each test column holds the student's score for it in percent (the mean over the runs of the
weighted share of expectations that held); ``total`` is the mean over the tests, and
``passed`` says whether every run of every test passed. Spreadsheets and learning platforms
import it as it is.
"""

from __future__ import annotations

import csv
import io
from pathlib import Path

from roboscript.grading.batch import ClassReport

__all__ = ["gradebook_csv", "write_gradebook"]


def gradebook_csv(report: ClassReport) -> str:
    """The gradebook as CSV text."""
    out = io.StringIO()
    writer = csv.writer(out, lineterminator="\n")
    writer.writerow(["student", *(spec.name for spec in report.specs), "total", "passed"])
    for submission in report.submissions:
        cells = [report.cell(submission.student, spec.name) for spec in report.specs]
        writer.writerow(
            [
                submission.student,
                *(f"{cell.score * 100:.1f}" for cell in cells),
                f"{report.student_score(submission.student) * 100:.1f}",
                "yes" if all(cell.passed for cell in cells) else "no",
            ]
        )
    return out.getvalue()


def write_gradebook(report: ClassReport, path: str | Path) -> None:
    """Write :func:`gradebook_csv` to ``path`` (UTF-8 with a byte-order mark, for Excel)."""
    Path(path).write_text(gradebook_csv(report), encoding="utf-8-sig")
