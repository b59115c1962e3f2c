"""The class table printed on the terminal: one line per student and test.

Each line shows ✓ or ✗ with the runs that passed out of all runs, the score, and what to look
at: the first failure's margin (or why the run stopped), or, when every run passed, the
expectation that passed with the least room to spare.
"""

from __future__ import annotations

from roboscript.grading.batch import ClassReport

__all__ = ["format_table", "symbols_for"]


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
    rows: list[tuple[str, str, str, str, str]] = []
    for submission in report.submissions:
        for spec in report.specs:
            cell = report.cell(submission.student, spec.name)
            mark = ok if cell.passed else bad
            rows.append(
                (
                    submission.student,
                    spec.name,
                    f"{mark} {cell.passed_runs}/{cell.total_runs}",
                    f"{cell.score * 100:.0f}%",
                    cell.summary(),
                )
            )
    header = ("student", "test", "runs", "score", "worst margin / why")
    widths = [max(len(r[i]) for r in [header, *rows]) for i in range(4)]
    lines = []
    for row in [header, *rows]:
        cells = [row[i].ljust(widths[i]) for i in range(4)]
        cells[3] = row[3].rjust(widths[3])
        lines.append("  ".join([*cells, row[4]]).rstrip())
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
