"""One student in one test: every run's result, the points they earned, what to show first.

Shared by the class's reports (:mod:`roboscript.grading.batch`) and the browser page's
practice grade (:mod:`roboscript.grading.practice`), so a test's points add up the same way
in both.
"""

from __future__ import annotations

from dataclasses import dataclass

from roboscript.grading.record import RunResult, Verdict
from roboscript.grading.text import public_reason

__all__ = ["Cell"]


@dataclass(frozen=True)
class Cell:
    """One student in one test: every run, and what to show for it.

    Attributes:
        student: The student.
        test: The test.
        results: One per run variant, in the spec's order.
        max_points: What the test is worth (:attr:`TestSpec.max_points`); each run is worth
            an equal share of it.
        hidden: The variants (indexes) students must not see the details of.
    """

    student: str
    test: str
    results: tuple[RunResult, ...]
    max_points: float = 0.0
    hidden: frozenset[int] = frozenset()

    @property
    def passed_runs(self) -> int:
        """Runs that passed."""
        return sum(1 for r in self.results if r.passed)

    @property
    def total_runs(self) -> int:
        """Runs in all."""
        return len(self.results)

    @property
    def passed(self) -> bool:
        """True if every run passed."""
        return self.passed_runs == self.total_runs

    @property
    def score(self) -> float:
        """Mean of the runs' scores, 0 to 1 (partial credit for expectations that held)."""
        if not self.results:
            return 0.0
        return round(sum(r.score for r in self.results) / len(self.results), 4)

    @property
    def run_max_points(self) -> float:
        """What one run is worth: an equal share of :attr:`max_points`."""
        return round(self.max_points / self.total_runs, 4) if self.results else 0.0

    def run_points(self, result: RunResult) -> float:
        """The points one run earned: its share of the test's points times its score."""
        if not self.results:
            return 0.0
        return round(self.max_points / self.total_runs * result.score, 4)

    @property
    def points(self) -> float:
        """The points earned: the sum of the runs' points."""
        return round(sum(self.run_points(r) for r in self.results), 4)

    def worst(self) -> tuple[RunResult | None, Verdict | None]:
        """The run to look at first and its telling verdict.

        That is the first run that did not pass (with its first failed verdict), or, when all
        passed, the run and verdict that passed with the least room to spare.
        """
        for result in self.results:
            if not result.passed:
                return result, result.worst_verdict()
        tightest: tuple[RunResult | None, Verdict | None] = (None, None)
        least = float("inf")
        for result in self.results:
            verdict = result.worst_verdict()
            relative = verdict.relative_margin if verdict is not None else None
            if relative is not None and relative < least:
                least = relative
                tightest = (result, verdict)
        return tightest

    def summary(self) -> str:
        """What the class table shows beside the pass count: the worst margin or the reason."""
        result, verdict = self.worst()
        if result is None:
            return ""
        hidden = result.variant in self.hidden  # CI logs show the table to the student
        if verdict is None or (not result.passed and result.status != "failed"):
            return public_reason(result, hidden)
        if verdict.margin:
            return f"{verdict.name} {verdict.margin}"
        if hidden:
            return f"{verdict.name} {'passed' if verdict.passed else 'failed'}"
        return verdict.text
