"""What every report owes a teacher and an LMS: points, JUnit errors, hidden runs kept hidden in
what CI shows, and student-controlled text capped (a 20 MB message once made 60 MB pages)."""

from __future__ import annotations

import csv
import json
import xml.etree.ElementTree as ET
from dataclasses import replace
from pathlib import Path

import pytest
from hand_graded import HIDDEN_SECRETS, hand_report, hand_spec, one_student

from roboscript.errors import SpecError
from roboscript.grading.batch import ClassReport
from roboscript.grading.gradebook import gradebook_csv
from roboscript.grading.gradescope import gradescope_results
from roboscript.grading.html_report import write_html
from roboscript.grading.json_report import report_dict
from roboscript.grading.junit import junit_xml
from roboscript.grading.record import RunRecord, Verdict
from roboscript.grading.spec import load_test_spec
from roboscript.grading.table import format_table
from roboscript.grading.text import (
    DEBUG_CHARS,
    MESSAGE_CHARS,
    cap,
    clean_name,
    public_reason,
    student_text,
    xml_safe,
)

# ------------------------------------------------------------------------------- the spec


def test_points_and_hidden_are_spec_keys(tmp_path: Path) -> None:
    spec = hand_spec(tmp_path)
    assert spec.max_points == 12.0
    assert [v.hidden for v in spec.variants] == [False, False, True]
    assert [v.public_label for v in spec.variants][1:] == [
        "seed 2, start (300, -200) mm 0°",
        "hidden run 3",
    ]
    assert spec.to_dict()["points"] == 12.0
    assert [r["hidden"] for r in spec.to_dict()["runs"]] == [False, False, True]


def test_without_points_a_test_is_worth_one_point_per_run(tmp_path: Path) -> None:
    path = tmp_path / "t.yaml"
    path.write_text("test: t\nruns: [{seed: 1}, {seed: 2}]\nexpect:\n  - outcome: success\n")
    assert load_test_spec(path).max_points == 2.0


@pytest.mark.parametrize(
    ("line", "message"),
    [
        ("points: -1", "'points' must be a number of at least 0"),
        ("points: ten", "'points' must be a number of at least 0"),
        ("runs: [{seed: 1, hidden: maybe}]", "'hidden' must be true or false"),
        ("runs: [{seed: 1, hiden: true}]", "unknown key 'hiden' in a run"),
    ],
)
def test_wrong_points_or_hidden_are_located(tmp_path: Path, line: str, message: str) -> None:
    path = tmp_path / "t.yaml"
    path.write_text(f"test: t\n{line}\nexpect:\n  - outcome: success\n")
    with pytest.raises(SpecError, match=message) as raised:
        load_test_spec(path)
    assert raised.value.line == 2


# ------------------------------------------------------------------------------ points


def test_points_add_up_in_the_json_csv_and_table(tmp_path: Path) -> None:
    report = hand_report(tmp_path)
    data = report_dict(report)
    runs = [r for r in data["runs"] if r["student"] == "Quentin"]
    assert [(r["points"], r["max_points"]) for r in runs] == [(4.0, 4.0), (0.0, 4.0), (2.0, 4.0)]
    assert [r["hidden"] for r in runs] == [False, False, True]
    cell = next(r for r in data["results"] if r["student"] == "Quentin")
    assert (cell["points"], cell["max_points"]) == (6.0, 12.0)
    assert cell["points"] == sum(r["points"] for r in runs)
    quentin = next(s for s in data["students"] if s["name"] == "Quentin")
    assert (quentin["points"], quentin["max_points"]) == (6.0, 12.0)

    rows = list(csv.reader(gradebook_csv(report).splitlines()))
    assert rows[0] == [
        "student", "square-50cm", "total", "passed", "square-50cm points (of 12)", "points",
        "max points",
    ]  # fmt: skip
    assert rows[1] == ["Quentin", "50.0", "50.0", "no", "6", "6", "12"]
    assert rows[2] == ["Zelda", "100.0", "100.0", "yes", "12", "12", "12"]

    lines = format_table(report).splitlines()
    assert lines[0].split()[:5] == ["student", "test", "runs", "score", "points"]
    assert lines[1].split()[2:6] == ["✗", "1/3", "50%", "6/12"]
    assert lines[2].split()[2:6] == ["✓", "3/3", "100%", "12/12"]


def test_a_formula_in_a_student_name_is_text_in_the_gradebook(tmp_path: Path) -> None:
    report = hand_report(tmp_path, good="=HYPERLINK(1)")
    assert "\n'=HYPERLINK(1)," in gradebook_csv(report)


@pytest.mark.parametrize("blank", [" ", "\u00a0", "\u2003"])
def test_a_formula_after_a_separator_and_any_blank_is_text_in_the_gradebook(
    tmp_path: Path, blank: str
) -> None:
    # a spreadsheet that splits the cell at ';' could read what follows, blanks and all
    report = hand_report(tmp_path, good=f"x;{blank}=2+5")
    assert f"\nx;{blank}'=2+5," in gradebook_csv(report)


# ------------------------------------------------------------------------------- JUnit


def test_junit_errors_for_runs_that_did_not_finish(tmp_path: Path) -> None:
    report = hand_report(tmp_path)
    crashed = report.results[1]
    statuses = ("too slow", "hung", "invalid")
    extra = [
        replace(crashed, status=s, variant=0, message=f"it was {s}", student=f"S{s}")
        for s in statuses
    ]
    missing = replace(crashed, status="missing", message="no mission for the test", student="M")
    report = replace(report, results=[*report.results, *extra, missing])
    root = ET.fromstring(junit_xml(report))
    (suite,) = root.findall("testsuite")
    assert {k: suite.get(k) for k in ("tests", "failures", "errors", "skipped")} == {
        "tests": "10",
        "failures": "1",
        "errors": "4",
        "skipped": "1",
    }
    assert root.get("errors") == "4" and root.get("skipped") == "1"
    cases = {(c.get("classname"), c.get("name")): c for c in suite.findall("testcase")}
    error = cases[("square-50cm.Quentin", "seed 2, start (300, -200) mm 0°")].find("error")
    assert error is not None
    assert error.get("type") == "crashed"
    assert error.get("message") == (
        "the run crashed: ZeroDivisionError: division by zero (square.py:12)"
    )
    for status in statuses:
        element = cases[(f"square-50cm.S{status}", "seed 1")].find("error")
        assert element is not None and element.get("type") == status
    skipped = cases[("square-50cm.M", "seed 2, start (300, -200) mm 0°")].find("skipped")
    assert skipped is not None and skipped.get("message") == "no mission for the test"
    failure = cases[("square-50cm.Quentin", "hidden run 3")].find("failure")
    assert failure is not None and failure.get("message") == "final_pose_within failed by 41.5 cm"


def test_junit_and_the_table_keep_hidden_runs_hidden(tmp_path: Path) -> None:
    """A CI job's log and test report are read by the student whose work it graded."""
    report = hand_report(tmp_path)
    for text in (junit_xml(report), format_table(report)):
        for secret in HIDDEN_SECRETS:
            assert secret not in text, secret
        assert "Traceback" not in text


# -------------------------------------------------------------------------------- caps


def test_cap_cuts_visibly_cleans_and_changes_nothing_twice() -> None:
    long = "x" * 10_000
    capped = cap(long, 2_000)
    assert len(capped) <= 2_000
    assert capped.endswith("… (cut: 8040 characters)")
    assert cap(capped, 2_000) == capped
    assert cap("short", 2_000) == "short"
    assert cap("a\x00b\x1b[2Jc\ud800d\te\nf", 100) == "a\ufffdb\ufffd[2Jc\ufffdd\te\nf"


def test_a_name_is_made_one_safe_line_once() -> None:
    assert clean_name("ana\n1 2\x1b[2J\u202etxt\x85 ") == "ana\ufffd1 2\ufffd[2J\ufffdtxt\ufffd"
    assert clean_name(clean_name("a\tb")) == clean_name("a\tb") == "a\ufffdb"
    assert clean_name("  ") == "student"
    assert len(clean_name("n" * 1000)) <= 200 and clean_name("n" * 1000).endswith("characters)")


def test_a_student_reads_no_folder_of_the_teachers() -> None:
    message = "error: /home/t/class/ana/sub/turns.py:3: bad; see /usr/lib/python3/x.py"
    assert student_text(message, "/home/t/class/ana") == "error: sub/turns.py:3: bad; see x.py"
    assert student_text("20 cm/s, https://a.org/b/c") == "20 cm/s, https://a.org/b/c"


def test_a_hidden_run_that_did_not_finish_tells_nothing_of_the_mission(tmp_path: Path) -> None:
    run = hand_report(tmp_path).results[1]  # crashed, with the mission's own words
    assert "ZeroDivisionError" in public_reason(run, hidden=False)
    assert public_reason(run, hidden=True) == "the run crashed (a hidden run does not show why)"
    assert xml_safe("a\x01b\rc\ud800") == "a\ufffdb\nc\ufffd"


def _huge(report: ClassReport, size: int = 20_000_000) -> ClassReport:
    """Quentin's hidden run, its every student-controlled text 20 MB long."""
    huge = "Z" * size
    results = list(report.results)
    run = results[2]
    assert run.record is not None
    record: RunRecord = replace(
        run.record,
        mission=huge,
        reason=huge,
        final_state=huge,
        states=((0.0, huge), (5.0, "corner\x00" + huge)),
    )
    verdict = Verdict("check: custom", False, "failed by 1 cm", 3.0, huge)
    results[2] = replace(
        run, message=huge, debug=huge, record=record, verdicts=(*run.verdicts, verdict)
    )
    results[1] = replace(results[1], message=huge, debug=huge)
    return replace(report, results=results)


def test_a_20_mb_message_gives_reports_of_bounded_size(tmp_path: Path) -> None:
    report = _huge(hand_report(tmp_path))
    sizes = {
        "json": len(json.dumps(report_dict(report), ensure_ascii=False)),
        "junit": len(junit_xml(report)),
        "csv": len(gradebook_csv(report)),
        "table": len(format_table(report)),
        "gradescope": len(json.dumps(gradescope_results(one_student(report, "Quentin")))),
    }
    write_html(report, tmp_path / "html")
    pages = sorted((tmp_path / "html").rglob("*.html"))
    sizes["html"] = max(p.stat().st_size for p in pages)
    limits = {"json": 200_000, "junit": 40_000, "csv": 1_000, "table": 2_000}
    for name, size in sizes.items():
        assert size < limits.get(name, 150_000), (name, size)
    data = report_dict(report)
    run = data["runs"][2]
    assert len(run["message"]) <= MESSAGE_CHARS and "(cut: " in run["message"]
    assert len(run["debug"]) <= DEBUG_CHARS and run["debug"].endswith(" characters)")
    assert run["record"]["reason"].endswith("… (cut: 19998040 characters)")
    assert "\x00" not in json.dumps(data)
    assert "(cut: " in (tmp_path / "html" / "runs" / "Quentin--square-50cm--3.html").read_text(
        encoding="utf-8"
    )


def test_a_name_that_looks_like_a_classmates_shows_what_tells_it_apart() -> None:
    for invisible in ("\u200b", "\u00ad", "\u2060", "\ufeff", "\u3164", "\u200d"):
        assert clean_name(f"bob{invisible}") == "bob\ufffd", repr(invisible)
        assert clean_name(f"b{invisible}ob") == "b\ufffdob", repr(invisible)
    assert clean_name("José") == clean_name("Jose\u0301") == "Jos\u00e9"  # one name, composed
    assert clean_name("Анна 王芳") == "Анна 王芳"
