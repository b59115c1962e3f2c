"""``roboscript grade --junit FILE``: JUnit XML for learning platforms and CI.

One ``<testsuite>`` per test spec, one ``<testcase>`` per student and run variant
(``classname`` = test.student, ``name`` = the variant). A run that did not pass has a
``<failure>`` whose ``message`` is the student's one sentence and whose text lists every
verdict; its ``type`` says how it ended (``failed``, ``timeout``, ``crashed``, ``invalid``,
``missing``).
"""

from __future__ import annotations

import xml.etree.ElementTree as ET
from pathlib import Path

from roboscript.grading.batch import ClassReport
from roboscript.grading.record import RunResult

__all__ = ["junit_xml", "write_junit"]


def _verdict_lines(result: RunResult) -> str:
    lines = [f"{'PASS' if v.passed else 'FAIL'} {v.text}" for v in result.verdicts]
    for verdict in result.verdicts:
        if verdict.first_violation_s is not None:
            lines.append(f"first violation of {verdict.name} at {verdict.first_violation_s:.2f} s")
    return "\n".join(lines) or result.message


def junit_xml(report: ClassReport) -> str:
    """The report as a JUnit XML document."""
    root = ET.Element("testsuites", name="roboscript grade")
    total = failures = 0
    total_time = 0.0
    for spec in report.specs:
        results = [r for r in report.results if r.test == spec.name]
        failed = sum(1 for r in results if not r.passed)
        suite_time = sum(r.wall_time_s for r in results)
        suite = ET.SubElement(
            root,
            "testsuite",
            name=spec.name,
            tests=str(len(results)),
            failures=str(failed),
            errors="0",
            skipped="0",
            time=f"{suite_time:.3f}",
        )
        properties = ET.SubElement(suite, "properties")
        for key, value in (("spec", spec.path), ("world", spec.world), ("robot", spec.robot)):
            ET.SubElement(properties, "property", name=key, value=value)
        for result in results:
            case = ET.SubElement(
                suite,
                "testcase",
                classname=f"{spec.name}.{result.student}",
                name=result.label,
                time=f"{result.wall_time_s:.3f}",
            )
            if not result.passed:
                failure = ET.SubElement(case, "failure", message=result.message, type=result.status)
                failure.text = _verdict_lines(result)
            if result.mission:
                ET.SubElement(case, "system-out").text = f"mission: {result.mission}"
        total += len(results)
        failures += failed
        total_time += suite_time
    root.set("tests", str(total))
    root.set("failures", str(failures))
    root.set("errors", "0")
    root.set("time", f"{total_time:.3f}")
    ET.indent(root)
    return '<?xml version="1.0" encoding="UTF-8"?>\n' + ET.tostring(root, encoding="unicode") + "\n"


def write_junit(report: ClassReport, path: str | Path) -> None:
    """Write :func:`junit_xml` to ``path`` (UTF-8)."""
    Path(path).write_text(junit_xml(report), encoding="utf-8")
