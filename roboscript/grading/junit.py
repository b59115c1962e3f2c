"""``roboscript grade --junit FILE``: JUnit XML for learning platforms and CI.

One ``<testsuite>`` per test spec, one ``<testcase>`` per student and run variant
(``classname`` = test.student, ``name`` = the variant). How a run ended decides its element:

* ``passed``: none;
* ``failed`` (an expectation did not hold): ``<failure type="failed">``;
* ``missing`` (no mission for the test): ``<skipped>``: nothing ran. It still scores 0 and
  makes ``grade`` exit 1, so a CI job fails on it;
* anything else, the run did not finish (``too slow``, ``hung``, ``crashed``, ``invalid``...):
  ``<error type="STATUS">``.

``message`` is the student's one sentence and the element's text lists every verdict. A CI
log is read by the student whose work it graded, so the file holds nothing a student may not
see: a hidden variant is named ``hidden run N`` and shows only pass or fail, each
expectation's margin and the reason; tracebacks (the ``debug`` field) stay in ``--json``; the
spec is named by its file name, not its path. Text is capped (:mod:`roboscript.grading.text`).
"""

from __future__ import annotations

import xml.etree.ElementTree as ET
from pathlib import Path

from roboscript.grading.batch import ClassReport
from roboscript.grading.record import RunResult
from roboscript.grading.text import format_points, public_reason, xml_safe

__all__ = ["junit_kind", "junit_xml", "write_junit"]


def junit_kind(status: str) -> str | None:
    """The JUnit element for a run's status: ``failure``, ``skipped``, ``error``, or ``None``."""
    if status == "passed":
        return None
    if status == "failed":
        return "failure"
    if status == "missing":
        return "skipped"
    return "error"


def _verdict_lines(result: RunResult, hidden: bool) -> str:
    lines = []
    for verdict in result.verdicts:
        mark = "PASS" if verdict.passed else "FAIL"
        if hidden:  # details name positions, which would give a hidden start away
            word = "" if verdict.margin else (" passed" if verdict.passed else " failed")
            lines.append(f"{mark} {verdict.name} {verdict.margin}".rstrip() + word)
        else:
            lines.append(f"{mark} {verdict.text}")
    for verdict in result.verdicts:
        if verdict.first_violation_s is not None:
            lines.append(f"first violation of {verdict.name} at {verdict.first_violation_s:.2f} s")
    return "\n".join(lines) or public_reason(result, hidden)


def junit_xml(report: ClassReport) -> str:
    """The report as a JUnit XML document."""
    report = report.capped()
    root = ET.Element("testsuites", name="roboscript grade")
    totals = {"tests": 0, "failures": 0, "errors": 0, "skipped": 0}
    total_time = 0.0
    for spec in report.specs:
        results = [r for r in report.results if r.test == spec.name]
        kinds = [junit_kind(r.status) for r in results]
        counts = {
            "tests": len(results),
            "failures": kinds.count("failure"),
            "errors": kinds.count("error"),
            "skipped": kinds.count("skipped"),
        }
        suite_time = sum(r.wall_time_s for r in results)
        attributes = {"name": spec.name, **{k: str(n) for k, n in counts.items()}}
        suite = ET.SubElement(root, "testsuite", attributes, time=f"{suite_time:.3f}")
        properties = ET.SubElement(suite, "properties")
        for name, value in (
            ("spec", Path(spec.path).name),
            ("world", Path(spec.world).name),
            ("robot", spec.robot),
            ("points", format_points(spec.max_points)),
        ):
            ET.SubElement(properties, "property", name=name, value=value)
        for result, kind in zip(results, kinds, strict=True):
            hidden = report.is_hidden(result)
            case = ET.SubElement(
                suite,
                "testcase",
                classname=f"{spec.name}.{result.student}",
                name=report.public_label(result),
                time=f"{result.wall_time_s:.3f}",
            )
            if kind is not None:
                element = ET.SubElement(
                    case, kind, message=public_reason(result, hidden), type=result.status
                )
                element.text = _verdict_lines(result, hidden)
            if result.mission:
                ET.SubElement(case, "system-out").text = f"mission: {report.shown_mission(result)}"
        for key, count in counts.items():
            totals[key] += count
        total_time += suite_time
    for key, count in totals.items():
        root.set(key, str(count))
    root.set("time", f"{total_time:.3f}")
    ET.indent(root)
    # Whatever reached the tree, a character XML 1.0 does not allow never reaches the file.
    text = xml_safe(ET.tostring(root, encoding="unicode"))
    return '<?xml version="1.0" encoding="UTF-8"?>\n' + text + "\n"


def write_junit(report: ClassReport, path: str | Path) -> None:
    """Write :func:`junit_xml` to ``path`` (UTF-8)."""
    Path(path).parent.mkdir(parents=True, exist_ok=True)
    Path(path).write_text(junit_xml(report), encoding="utf-8")
