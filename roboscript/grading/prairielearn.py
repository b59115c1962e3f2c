"""``roboscript grade --prairielearn FILE``: PrairieLearn's external-grader ``results.json``.

PrairieLearn runs the question's entrypoint in a container per submission, with the student's
files in ``/grade/student`` and the question's tests in ``/grade/tests``, and reads
``/grade/results/results.json``. As with Gradescope, everything under ``--mission`` is one
student's submission.

The fields written, as PrairieLearn's "External Grading" reference documents them:
``gradable`` (``true``), ``score`` (0 to 1: the points earned over the points possible),
``message`` (the summary), and ``tests``, one per test spec and run variant, each with
``name``, ``points``, ``max_points``, ``message`` (passed or failed) and ``output`` (how it
ended, why, every expectation). These are the Gradescope results
(:mod:`roboscript.grading.gradescope`) in PrairieLearn's words, so both platforms say the same
things; PrairieLearn shows every test at once, so a hidden run is named ``hidden run N`` and
says only pass or fail and the reason, as on Gradescope.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

from roboscript.grading.batch import ClassReport
from roboscript.grading.gradescope import gradescope_results

__all__ = ["from_gradescope", "prairielearn_results", "write_prairielearn"]


def from_gradescope(results: dict[str, Any]) -> dict[str, Any]:
    """Gradescope ``results.json`` content as PrairieLearn's."""
    possible = sum(test["max_score"] for test in results["tests"])
    return {
        "gradable": True,
        "score": round(results["score"] / possible, 4) if possible else 0.0,
        "message": results["output"],
        "tests": [
            {
                "name": test["name"],
                "points": test["score"],
                "max_points": test["max_score"],
                "message": test["status"],
                "output": test["output"],
            }
            for test in results["tests"]
        ],
    }


def prairielearn_results(report: ClassReport) -> dict[str, Any]:
    """The report of one submission as PrairieLearn's ``results.json``.

    Raises:
        ValueError: The report holds more than one student.
    """
    return from_gradescope(gradescope_results(report))


def write_prairielearn(report: ClassReport | dict[str, Any], path: str | Path) -> None:
    """Write :func:`prairielearn_results` (or Gradescope-shaped results) to ``path``."""
    data = from_gradescope(report) if isinstance(report, dict) else prairielearn_results(report)
    target = Path(path)
    target.parent.mkdir(parents=True, exist_ok=True)
    target.write_text(json.dumps(data, indent=2, ensure_ascii=False) + "\n", encoding="utf-8")
