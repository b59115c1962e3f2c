"""``roboscript grade`` as a teacher runs it: the table, exit codes, JSON, JUnit and CSV, with
points."""

from __future__ import annotations

import csv
import json
import shutil
import xml.etree.ElementTree as ET
from pathlib import Path

import pytest
from helpers import MISSIONS, OUT_TURN_BEEP, run_cli

TEACHER = MISSIONS / "teacher"
SQUARE = TEACHER / "square" / "test.yaml"


@pytest.fixture(scope="module")
def graded(tmp_path_factory: pytest.TempPathFactory) -> dict[str, object]:
    """The square test on a class of two, one good and one off by one, with every report."""
    root = tmp_path_factory.mktemp("grade")
    folder = root / "class"
    folder.mkdir()
    shutil.copy(TEACHER / "square" / "good.yaml", folder / "amy.yaml")
    shutil.copy(TEACHER / "square" / "bad.yaml", folder / "bo.yaml")
    junit, gradebook = root / "junit.xml", root / "grades.csv"
    table = run_cli(
        "grade", str(SQUARE), "--mission", str(folder), "--junit", str(junit),
        "--csv", str(gradebook), "--jobs", "2",
    )  # fmt: skip
    as_json = run_cli("grade", str(SQUARE), "--mission", str(folder), "--json", "--jobs", "1")
    return {"table": table, "json": as_json, "junit": junit, "csv": gradebook}


def test_the_table_shows_each_student_with_runs_score_and_worst_margin(
    graded: dict[str, object],
) -> None:
    result = graded["table"]
    assert result.returncode == 1, result.stderr  # type: ignore[attr-defined]
    lines = result.stdout.splitlines()  # type: ignore[attr-defined]
    assert lines[0].split() == [
        "student", "test", "runs", "score", "points", "worst", "margin", "/", "why",
    ]  # fmt: skip
    amy = next(line for line in lines if line.startswith("amy"))
    bo = next(line for line in lines if line.startswith("bo "))
    assert "✓ 3/3" in amy and "100%" in amy
    assert "✗ 0/3" in bo and " 0%" in bo and "path_visits failed by" in bo  # required
    for line in (amy, bo):  # three runs, a point each: the points are 3 × the score
        score, points = line.split()[4:6]
        earned, possible = points.split("/")
        assert float(earned) == pytest.approx(3 * int(score.rstrip("%")) / 100, abs=0.02)
        assert possible == "3"
    assert lines[-1] == "3 of 6 runs passed; 1 of 2 students passed every test"
    assert "Traceback" not in result.stderr  # type: ignore[attr-defined]


def test_json_holds_specs_students_results_and_runs_with_verdicts(
    graded: dict[str, object],
) -> None:
    result = graded["json"]
    report = json.loads(result.stdout)  # type: ignore[attr-defined]
    assert report["passed"] is False
    assert [s["test"] for s in report["specs"]] == ["square-50cm"]
    assert [s["name"] for s in report["students"]] == ["amy", "bo"]
    assert [(r["student"], r["passed_runs"], r["total_runs"]) for r in report["results"]] == [
        ("amy", 3, 3),
        ("bo", 0, 3),
    ]
    run = report["runs"][3]
    assert (run["student"], run["variant"], run["status"]) == ("bo", 0, "failed")
    pose = next(v for v in run["verdicts"] if v["name"] == "final_pose_within")
    assert pose["passed"] is False
    assert pose["margin"].startswith("failed by ")
    assert pose["first_violation_s"] == run["record"]["duration_s"]
    assert run["record"]["sim"]["path"][0][:3] == [0.0, 0.0, 0.0]
    assert len(run["record"]["sim"]["tones"]) == 3
    assert (run["points"], run["max_points"], run["hidden"]) == (run["score"], 1.0, False)
    for cell in report["results"]:
        assert cell["points"] == pytest.approx(3 * cell["score"], abs=1e-3)
        assert cell["max_points"] == 3.0


def test_junit_is_a_suite_per_test_and_a_case_per_student_and_run(
    graded: dict[str, object],
) -> None:
    root = ET.parse(graded["junit"]).getroot()  # type: ignore[arg-type]
    assert root.tag == "testsuites"
    assert (root.get("tests"), root.get("failures"), root.get("errors")) == ("6", "3", "0")
    assert root.get("skipped") == "0"
    (suite,) = root.findall("testsuite")
    assert suite.get("name") == "square-50cm"
    cases = suite.findall("testcase")
    assert [c.get("classname") for c in cases] == ["square-50cm.amy"] * 3 + ["square-50cm.bo"] * 3
    assert cases[0].get("name") == "seed 1"
    assert cases[0].find("failure") is None
    failure = cases[3].find("failure")
    assert failure is not None
    assert failure.get("type") == "failed"
    assert (failure.get("message") or "").startswith("path_visits failed by")
    assert "FAIL tones failed by 1 tone" in (failure.text or "")
    for case in cases:
        assert float(case.get("time") or "x") >= 0.0


def test_csv_is_a_gradebook_row_per_student(graded: dict[str, object]) -> None:
    text = Path(graded["csv"]).read_text(encoding="utf-8-sig")  # type: ignore[arg-type]
    rows = list(csv.reader(text.splitlines()))
    header, *body = rows
    assert header == [
        "student", "square-50cm", "total", "passed", "square-50cm points (of 3)", "points",
        "max points",
    ]  # fmt: skip
    assert [row[:4] for row in body] == [
        ["amy", "100.0", "100.0", "yes"],
        ["bo", "0.0", "0.0", "no"],
    ]
    for row in body:  # three runs, a point each: the points are 3 × the score
        assert float(row[4]) == pytest.approx(3 * float(row[1]) / 100, abs=0.01)
        assert row[5:] == [row[4], "3"]


def test_every_run_passing_exits_0(tmp_path: Path) -> None:
    good = tmp_path / "amy.yaml"
    shutil.copy(TEACHER / "square" / "good.yaml", good)
    result = run_cli("grade", str(SQUARE), "--mission", str(good), "--quiet")
    assert result.returncode == 0, result.stdout + result.stderr
    assert result.stderr == ""


def test_an_invalid_spec_exits_2_with_its_location(tmp_path: Path) -> None:
    spec = tmp_path / "spec.yaml"
    spec.write_text("test: t\nexpect:\n  - final_pose: {x: 0, y: 0, radius: 5 cm}\n")
    result = run_cli("grade", str(spec), "--mission", str(MISSIONS / "square.yaml"))
    assert result.returncode == 2
    assert result.stderr.strip() == (
        f"{spec}:3:5: error: unknown expectation 'final_pose' (did you mean 'final_pose_within'?)"
    )
    assert result.stdout == ""


def test_a_teachers_check_that_cannot_judge_is_told_to_the_teacher_and_exits_2(
    tmp_path: Path,
) -> None:
    # It fails every student's run whatever their robot did: the grades are the teacher's
    # mistake, said last, where a teacher reading the table looks, not a class that failed.
    (tmp_path / "laps.py").write_text("def lap(run):\n    return 1 / 0\n", encoding="utf-8")
    spec = tmp_path / "test.yaml"
    spec.write_text(
        "test: laps\nworld: empty\nrobot: mirto\nruns:\n  - {seed: 1}\nmax_time: 10 s\n"
        "expect:\n  - outcome: success\n  - check: 'laps.py:lap'\n",
        encoding="utf-8",
    )
    folder = tmp_path / "class"
    folder.mkdir()
    shutil.copy(MISSIONS / "there_and_back.yaml", folder / "amy.yaml")
    result = run_cli("grade", str(spec), "--mission", str(folder), "--quiet")
    assert result.returncode == 2, result.stdout + result.stderr
    assert result.stderr.splitlines()[-1] == (
        "error: check: lap failed to judge 1 of 1 runs (first: amy, laps: the teacher's check"
        " raised ZeroDivisionError: division by zero (laps.py:2)); those runs fail it whatever"
        " the robot did, so their grades are not to be trusted: fix the check and grade again"
    )
    assert "amy" in result.stdout  # the table is still printed, and every report written


def test_no_missions_found_exits_2(tmp_path: Path) -> None:
    result = run_cli("grade", str(SQUARE), "--mission", str(tmp_path / "nobody-*.yaml"))
    assert result.returncode == 2
    assert "no mission matches" in result.stderr


def test_a_folder_per_student_and_a_set_of_tests(tmp_path: Path) -> None:
    # Each student's folder holds one mission per test, named after the test.
    for student, kind in (("amy", "good"), ("bo", "bad")):
        folder = tmp_path / "class" / student
        folder.mkdir(parents=True)
        shutil.copy(TEACHER / "square" / f"{kind}.yaml", folder / "square-50cm.yaml")
        shutil.copy(TEACHER / "corridor" / f"{kind}.yaml", folder / "corridor-wall-follow.yaml")
    result = run_cli(
        "grade", str(SQUARE), str(TEACHER / "corridor" / "test.yaml"),
        "--mission", str(tmp_path / "class"), "--json",
    )  # fmt: skip
    report = json.loads(result.stdout)
    cells = {(r["student"], r["test"]): r["passed"] for r in report["results"]}
    assert cells == {
        ("amy", "square-50cm"): True,
        ("amy", "corridor-wall-follow"): True,
        ("bo", "square-50cm"): False,
        ("bo", "corridor-wall-follow"): False,
    }


def test_check_accepts_test_specs_and_reports_their_mistakes(tmp_path: Path) -> None:
    assert run_cli("check", str(TEACHER)).returncode == 0
    spec = tmp_path / "spec.yaml"
    spec.write_text("test: t\nexpect:\n  - tones: {cuont: 4}\n")
    result = run_cli("check", str(spec))
    assert result.returncode == 2
    assert f"{spec}:3:13: error: unknown key 'cuont' in tones (did you mean 'count'?)" in (
        result.stderr
    )


def test_what_a_class_folder_holds_that_is_no_students_work_is_named_once(
    tmp_path: Path,
) -> None:
    folder = tmp_path / "class"
    folder.mkdir()
    shutil.copy(TEACHER / "square" / "good.yaml", folder / "alice.yaml")
    (folder / "alice_helpers.py").write_text("X = 1\n", encoding="utf-8")  # alice's own
    (folder / "bo.zip").write_bytes(b"PK")  # handed in in a form the grader does not take
    (folder / "notes").mkdir()
    (folder / "notes" / "todo.txt").write_text("", encoding="utf-8")
    (folder / ".git").mkdir()  # hidden: nobody's business
    (folder / "cy\n| forged | row.txt").write_text("", encoding="utf-8")
    result = run_cli("grade", str(SQUARE), "--mission", str(folder))
    notes = [line for line in result.stderr.splitlines() if line.startswith("note:")]
    assert notes == [
        (
            "note: not graded, as no student's work: bo.zip, cy\ufffd| forged | row.txt, notes/"
            " (a student is a .yaml or .py mission, or a folder holding one)"
        )
    ]
    quiet = run_cli("grade", str(SQUARE), "--mission", str(folder), "--quiet")
    assert "note:" not in quiet.stderr


@pytest.mark.parametrize(
    ("options", "error"),
    [
        (["--csv", "{tmp}"], "cannot write {tmp}: it is a folder"),
        (["--html", "{spec}"], "cannot write {spec}: it is a file"),
        (["--junit", "{spec}/junit.xml"], "cannot write {spec}/junit.xml: {spec} is a file"),
        (["--csv", "{tmp}/g.csv", "--results", "{tmp}/g.csv"], "--csv and --results both name"),
    ],
    ids=["a folder as a file", "a file as a folder", "under a file", "one file twice"],
)
def test_a_report_that_cannot_be_written_is_refused_before_grading(
    tmp_path: Path, options: list[str], error: str
) -> None:
    # Refused at once, not after a class's grading: nothing was graded, no other report written.
    spec = tmp_path / "test.yaml"
    shutil.copy(SQUARE, spec)
    asked = [option.format(tmp=tmp_path, spec=spec) for option in options]
    result = run_cli(
        "grade", str(spec), "--mission", str(TEACHER / "square" / "good.yaml"),
        "--junit", str(tmp_path / "out" / "junit.xml"), *asked,
    )  # fmt: skip
    assert result.returncode == 2
    assert result.stderr.startswith("error: " + error.format(tmp=tmp_path, spec=spec))
    assert result.stdout == "" and not (tmp_path / "out").exists()


def test_a_report_that_fails_to_write_leaves_the_others_written(tmp_path: Path) -> None:
    html = tmp_path / "html"
    (html / "index.html").mkdir(parents=True)  # the class page cannot be written
    reports = tmp_path / "new" / "folder"  # made when the reports are written
    result = run_cli(
        "grade", str(SQUARE), "--mission", str(TEACHER / "square" / "good.yaml"),
        "--html", str(html), "--csv", str(reports / "grades.csv"),
        "--gradescope", str(reports / "results.json"), "--quiet",
    )  # fmt: skip
    assert result.returncode == 1
    assert f"error: cannot write {html}" in result.stderr
    # written before the page that failed, and after it
    assert (reports / "grades.csv").is_file() and (reports / "results.json").is_file()


def _one_student_class(root: Path) -> Path:
    """A spec of one short run and a class of one student who passes it; the spec's path."""
    (root / "class").mkdir()
    (root / "class" / "amy.yaml").write_text(OUT_TURN_BEEP, encoding="utf-8")
    spec = root / "test.yaml"
    spec.write_text("test: out\nruns: [{seed: 1}]\nexpect: [{outcome: success}]\n")
    return spec


@pytest.mark.skipif(shutil.which("taskset") is None, reason="needs taskset to limit the cores")
def test_jobs_beyond_the_cores_grades_one_run_per_core_and_says_so(tmp_path: Path) -> None:
    spec = _one_student_class(tmp_path)
    # On one core (taskset), however many runs the teacher asks for at once.
    result = run_cli(
        "grade", str(spec), "--mission", str(tmp_path / "class"), "--jobs", "1000", "--quiet",
        wrap=("taskset", "-c", "0"),
    )  # fmt: skip
    assert result.returncode == 0, result.stderr
    assert result.stderr.splitlines()[0] == (
        "warning: --jobs 1000 is more than the 1 CPU core this machine gives roboscript:"
        " grading 1 run at once (more would only wait for each other)"
    )
    assert "amy" in result.stdout and "Traceback" not in result.stderr


def test_jobs_of_zero_is_one_sentence(tmp_path: Path) -> None:
    spec = _one_student_class(tmp_path)
    result = run_cli("grade", str(spec), "--mission", str(tmp_path / "class"), "--jobs", "0")
    assert result.returncode == 2
    assert result.stderr == "error: --jobs must be 1 or more\n"


def test_two_folders_named_alike_in_other_unicode_forms_are_graded_apart_and_named(
    tmp_path: Path,
) -> None:
    _one_student_class(tmp_path)
    composed, decomposed = "Jos\u00e9", "Jose\u0301"  # both show as "José"
    for name, distance in ((composed, "20 cm"), (decomposed, "10 cm")):
        (tmp_path / "class" / name).mkdir()
        mission = OUT_TURN_BEEP.replace("distance: 20 cm", f"distance: {distance}")
        (tmp_path / "class" / name / "mission.yaml").write_text(mission, encoding="utf-8")
    result = run_cli(
        "grade", "test.yaml", "--mission", "class", "--csv", "grades.csv", "--quiet", cwd=tmp_path
    )  # fmt: skip
    assert result.returncode == 0, result.stderr
    assert result.stderr.splitlines() == [
        (
            "warning: the students 'José' and 'José-2' have names that look the same: they are"
            " class/Jos\\u00e9 and class/Jose\\u0301, which differ only in how their names"
            " are written (each character that is not plain ASCII is shown as its code); each"
            " is graded on its own: check which is whose"
        )
    ]
    rows = (tmp_path / "grades.csv").read_text(encoding="utf-8-sig").splitlines()
    assert [row.split(",")[0] for row in rows[1:]] == ["amy", "José", "José-2"]


HUGE_AT_LOAD = """\
from roboscript import Drive, Mission, state

{line}


class Huge(Mission):
    {member}
    go = state(Drive(distance_mm=200), initial=True, on_done="fin")
    fin = state(final="success")
"""


@pytest.mark.parametrize(
    ("line", "member", "message"),
    [
        (
            "",
            'locals()["s" * 10_000_000] = state(final="failure")',
            (
                "the mission has an error: amy.py:7: error: this state name is 10000000 characters"
                " long; names are at most 200 ('ssssssssssssssssssss...')"
            ),
        ),
        (
            "",
            'name = "s" * 10_000_000',
            (
                "the mission has an error: amy.py:6:1: error: this mission name is 10000000"
                " characters long; names are at most 200 ('ssssssssssssssssssss...')"
            ),
        ),
        (
            'raise ValueError("x" * 10_000_000)',
            "",
            "the mission has an error: amy.py:3:1: error: ValueError: xxxxxxxxxx",
        ),
    ],
    ids=["a state name", "the mission name", "an exception's message"],
)
def test_ten_megabytes_in_a_missions_name_or_error_is_invalid_saying_why(
    tmp_path: Path, line: str, member: str, message: str
) -> None:
    spec = _one_student_class(tmp_path)
    (tmp_path / "class" / "amy.yaml").unlink()
    mission = HUGE_AT_LOAD.replace("{line}", line).replace("{member}", member)
    (tmp_path / "class" / "amy.py").write_text(mission, encoding="utf-8")
    result = run_cli("grade", str(spec), "--mission", str(tmp_path / "class"), "--json")
    assert result.returncode == 1, result.stderr
    (run,) = json.loads(result.stdout)["runs"]
    assert run["status"] == "invalid"  # the student's mistake, not the grading wire's
    assert run["message"].startswith(message), run["message"]
    assert len(run["message"]) < 2000


@pytest.mark.parametrize(
    ("line", "error"),
    [
        (
            'test: "out\\nfake row ✓ 3/3 100%"',
            (
                "1:7: error: 'test' must be one line of visible text: reports would show it as"
                " 'out\ufffdfake row ✓ 3/3 100%'"
            ),
        ),
        ("test: x" + "y" * 300 + " z", "1:7: error: this 'test' is 303 characters long"),
        (
            'test: out\nruns: [{seed: 1, name: "a\\tb"}]',
            "2:24: error: 'name' must be one line of visible text",
        ),
        (
            "test: out\nexpect: [{outcome: success, weight: .inf}]",
            "3:37: error: weight must be a finite number below a billion",
        ),
        (
            "test: out\nexpect: [{outcome: success, weight: .nan}]",
            "3:37: error: weight must be a finite number below a billion",
        ),
        (
            "test: out\nruns: [{seed: 1, start: {x: 1e12 mm}}]",
            "2:29: error: 'x' puts the start more than 1 km from the world's origin",
        ),
    ],
    ids=["a newline in the name", "a long name", "a tab in a run's name", "weight inf",
         "weight nan", "a start far away"],
)  # fmt: skip
def test_a_spec_a_report_would_show_wrongly_is_refused_where_it_is_wrong(
    tmp_path: Path, line: str, error: str
) -> None:
    _one_student_class(tmp_path)
    lines = ["test: out", "runs: [{seed: 1}]", "expect: [{outcome: success}]"]
    written = line.split("\n")
    for new in written:
        lines = [new if old.split(":")[0] == new.split(":")[0] else old for old in lines]
    (tmp_path / "test.yaml").write_text("\n".join(lines) + "\n", encoding="utf-8")
    result = run_cli("grade", "test.yaml", "--mission", "class", cwd=tmp_path)
    assert result.returncode == 2
    assert result.stderr.startswith(f"test.yaml:{error}"), result.stderr
    assert "Traceback" not in result.stderr


@pytest.mark.parametrize(
    ("option", "error"),
    [
        (("--csv", "class/amy.yaml"), "--csv class/amy.yaml is amy's mission"),
        (("--results", "test.yaml"), "--results test.yaml is the test spec test.yaml"),
        (("--junit", "class/zed/m.yaml"), "--junit class/zed/m.yaml is zed's mission"),
        (("--csv", "class/zed/grades.csv"), "--csv class/zed/grades.csv is inside zed's folder"),
        (("--html", "class"), "--html class holds "),
    ],
    ids=["over a mission", "over the spec", "over a folder's mission", "inside a student's folder",
         "around the students"],
)  # fmt: skip
def test_a_report_over_the_students_work_or_the_spec_is_refused_before_grading(
    tmp_path: Path, option: tuple[str, str], error: str
) -> None:
    _one_student_class(tmp_path)
    (tmp_path / "class" / "zed").mkdir()
    (tmp_path / "class" / "zed" / "m.yaml").write_text(OUT_TURN_BEEP, encoding="utf-8")
    before = {p: p.read_bytes() for p in tmp_path.rglob("*") if p.is_file()}
    result = run_cli("grade", "test.yaml", "--mission", "class", *option, cwd=tmp_path)
    assert result.returncode == 2
    assert result.stderr.startswith(f"error: {error}"), result.stderr
    assert "[1/" not in result.stderr  # before any run
    assert {p: p.read_bytes() for p in tmp_path.rglob("*") if p.is_file()} == before


def test_a_gradebook_report_over_its_results_file_is_refused(tmp_path: Path) -> None:
    _one_student_class(tmp_path)
    graded = run_cli(
        "grade", "test.yaml", "--mission", "class", "--results", "all.jsonl", "--quiet",
        cwd=tmp_path,
    )  # fmt: skip
    assert graded.returncode == 0, graded.stderr
    results = (tmp_path / "all.jsonl").read_bytes()
    merged = run_cli("gradebook", "all.jsonl", "--csv", "all.jsonl", cwd=tmp_path)
    assert merged.returncode == 2
    assert merged.stderr == (
        "error: --csv all.jsonl is the results file all.jsonl: writing it would destroy it\n"
    )
    assert (tmp_path / "all.jsonl").read_bytes() == results


@pytest.mark.parametrize(
    ("value", "why"),
    [
        ("inf", "'inf' is not a number of seconds"),
        ("1e9", "--hang-after is at most 3600 s (got 1e9)"),
        ("3601", "--hang-after is at most 3600 s (got 3601)"),
    ],
)
def test_a_hang_limit_beyond_an_hour_is_refused_not_every_run_crashed(
    tmp_path: Path, value: str, why: str
) -> None:
    # --hang-after inf made every run crash setting its timer.
    spec = _one_student_class(tmp_path)
    result = run_cli(
        "grade", str(spec), "--mission", str(tmp_path / "class"), "--hang-after", value
    )
    assert result.returncode == 2
    assert result.stderr.splitlines()[-1] == (
        f"roboscript grade: error: argument --hang-after: {why} (write it in seconds, e.g."
        " --hang-after 2)"
    )


def test_two_specs_whose_names_look_the_same_are_refused_naming_both(tmp_path: Path) -> None:
    _one_student_class(tmp_path)
    for file, name in (("a.yaml", "Jos\u00e9"), ("b.yaml", "Jose\u0301")):
        (tmp_path / file).write_text(
            f"test: {name}\nruns: [{{seed: 1}}]\nexpect: [{{outcome: success}}]\n",
            encoding="utf-8",
        )
    result = run_cli("grade", "a.yaml", "b.yaml", "--mission", "class", cwd=tmp_path)
    assert result.returncode == 2
    assert result.stderr == "error: two specs are both called 'Jose\u0301' (a.yaml and b.yaml)\n"


def test_results_go_to_a_folder_that_does_not_exist_yet_as_every_report_does(
    tmp_path: Path,
) -> None:
    spec = tmp_path / "spec.yaml"
    spec.write_text(
        "test: out\nworld: empty\nmax_time: 20 s\nexpect:\n  - outcome: success\n",
        encoding="utf-8",
    )
    (tmp_path / "amy.yaml").write_text(OUT_TURN_BEEP, encoding="utf-8")
    results = tmp_path / "parts" / "new" / "part.jsonl"
    done = run_cli(
        "grade", str(spec), "--mission", str(tmp_path / "amy.yaml"), "--results", str(results),
        "--csv", str(tmp_path / "reports" / "g.csv"), "--quiet",
    )  # fmt: skip
    assert done.returncode == 0, done.stderr
    _header, run = results.read_text(encoding="utf-8").splitlines()
    assert json.loads(run)["status"] == "passed"
