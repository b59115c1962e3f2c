"""``roboscript grade --csv FILE``: a gradebook, one row per student, one column per test.

Columns, in order:

* ``student``;
* one per test, the student's score for it in percent (the mean over the runs of the weighted
  share of expectations that held);
* ``total``: the mean of those percentages; ``passed``: whether every run of every test
  passed (``yes``/``no``);
* one per test, ``TEST points (of N)``: the points earned out of the N the test is worth
  (``points:`` in the spec, default one per run);
* ``points`` and ``max points``: the sum over the tests.

Spreadsheets and learning platforms import it as it is. A spreadsheet may split a cell again
at any separator it guesses (``,``, ``;``, a tab, ``|``), so each part of a name or test
name that it would read as a formula (starting ``=``, ``+``, ``-`` or ``@``, after any
spaces) gets a ``'`` before it: ``x;=2+5`` is written ``x;'=2+5``.
"""

from __future__ import annotations

import csv
import io
import re
from pathlib import Path

from roboscript.grading.batch import ClassReport
from roboscript.grading.text import format_points

__all__ = ["gradebook_csv", "write_gradebook"]


# Any blank but a line break may stand between a separator and the formula (a no-break
# space too: not every spreadsheet counts it as text).
_FORMULA = re.compile(r"(^|[,;\t|])([^\S\r\n]*)(?=[=+\-@])")


def _safe_cell(text: str) -> str:
    """Text a spreadsheet shows as text, never runs as a formula, however it splits it."""
    return _FORMULA.sub(r"\1\2'", text)


def gradebook_csv(report: ClassReport) -> str:
    """The gradebook as CSV text."""
    report = report.capped()
    out = io.StringIO()
    writer = csv.writer(out, lineterminator="\n")
    writer.writerow(
        [
            "student",
            *(_safe_cell(spec.name) for spec in report.specs),
            "total",
            "passed",
            *(
                _safe_cell(f"{spec.name} points (of {format_points(spec.max_points)})")
                for spec in report.specs
            ),
            "points",
            "max points",
        ]
    )
    for submission in report.submissions:
        cells = [report.cell(submission.student, spec.name) for spec in report.specs]
        writer.writerow(
            [
                _safe_cell(submission.student),
                *(f"{cell.score * 100:.1f}" for cell in cells),
                f"{report.student_score(submission.student) * 100:.1f}",
                "yes" if all(cell.passed for cell in cells) else "no",
                *(format_points(cell.points) for cell in cells),
                format_points(report.student_points(submission.student)),
                format_points(report.max_points),
            ]
        )
    return out.getvalue()


def write_gradebook(report: ClassReport, path: str | Path) -> None:
    """Write :func:`gradebook_csv` to ``path`` (UTF-8 with a byte-order mark, for Excel)."""
    Path(path).parent.mkdir(parents=True, exist_ok=True)
    Path(path).write_text(gradebook_csv(report), encoding="utf-8-sig")
