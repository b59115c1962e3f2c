"""The class table printed on the terminal: one line per student and test.

Each line shows ✓ or ✗ with the runs that passed out of all runs, the score, the points earned
out of those the test is worth, and what to look at: the first failure's margin (or why the run
stopped), or, when every run passed, the expectation that passed with the least room to spare.

A CI job's log is read by the student it graded, so a hidden variant's details never appear
here (its margin does). Text is capped, and kept to one line.
"""

from __future__ import annotations

from roboscript.grading.batch import ClassReport
from roboscript.grading.text import cap, display_width, format_points, padded

__all__ = ["format_table", "symbols_for"]

_WHY_CHARS = 300


def symbols_for(encoding: str | None) -> tuple[str, str]:
    """``(pass, fail)`` marks the terminal can show: ✓ ✗, or PASS FAIL where it cannot."""
    try:
        "✓✗".encode(encoding or "ascii")
    except (UnicodeEncodeError, LookupError):
        return "PASS", "FAIL"
    return "✓", "✗"


def format_table(report: ClassReport, encoding: str | None = "utf-8") -> str:
    """The table as text, ending with a one-line summary."""
    ok, bad = symbols_for(encoding)
    report = report.capped()
    rows: list[tuple[str, ...]] = []
    for submission in report.submissions:
        for spec in report.specs:
            cell = report.cell(submission.student, spec.name)
            mark = ok if cell.passed else bad
            rows.append(
                (
                    submission.student,  # cleaned when it was found
                    spec.name,
                    f"{mark} {cell.passed_runs}/{cell.total_runs}",
                    f"{cell.score * 100:.0f}%",
                    f"{format_points(cell.points)}/{format_points(cell.max_points)}",
                    cap(" ".join(cell.summary().split()), _WHY_CHARS),
                )
            )
    header = ("student", "test", "runs", "score", "points", "worst margin / why")
    numeric = (3, 4)
    # in a terminal's columns: a Chinese name is two a character, an accent none
    widths = [max(display_width(r[i]) for r in [header, *rows]) for i in range(5)]
    lines = []
    for row in [header, *rows]:
        cells = [padded(row[i], widths[i], right=i in numeric) for i in range(5)]
        lines.append("  ".join([*cells, row[5]]).rstrip())
    runs = len(report.results)
    passed_runs = sum(1 for r in report.results if r.passed)
    students = len(report.submissions)
    all_passed = sum(
        1
        for s in report.submissions
        if all(report.cell(s.student, spec.name).passed for spec in report.specs)
    )
    lines.append("")
    lines.append(
        f"{passed_runs} of {runs} runs passed; {all_passed} of {students} student"
        f"{'s' if students != 1 else ''} passed every test"
    )

    return "\n".join(lines)
