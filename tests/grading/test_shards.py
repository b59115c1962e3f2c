"""``grade --shard I/N --results PART.jsonl`` and ``roboscript gradebook PART.jsonl...``: a class
graded in parts, on any machines, merges into the reports one run would have written."""

from __future__ import annotations

import contextlib
import json
import os
import re
import subprocess
import sys
import tracemalloc
from pathlib import Path
from typing import Any

import pytest
from helpers import OUT_TURN_BEEP, run_cli

from roboscript.grading.record import MAX_GRADED_STATES
from roboscript.grading.shards import Shard, shard_number

STUDENTS = ("ada", "Bea", "cyd", "dan", "eve", "fay", "gus")
SPEC = """\
test: out-and-turn
runs:
  - {seed: 1}
  - {seed: 2, start: {heading: 30 deg}, hidden: true}
max_time: 20 s
expect:
  - outcome: success
  - final_pose_within: {x: 0 mm, y: 200 mm, radius: 25 mm}
"""
# The class is graded four times, once for the whole module's tests, on a loaded machine.
pytestmark = pytest.mark.timeout(900)
# Under a loaded machine a run may wait its turn: no run may be called hung for that here.
PATIENT = ("--hang-after", "60", "--jobs", "2", "--quiet")


def _without_wall_time(report: dict[str, Any]) -> dict[str, Any]:
    """The report without the one field that differs between two gradings of the same class."""
    for run in report["runs"]:
        run.pop("wall_time_s")
    return report


@pytest.fixture(scope="module")
def graded(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Any]:
    """A class graded once whole and once in three parts, in the same folder."""
    root = tmp_path_factory.mktemp("sharded")
    (root / "spec.yaml").write_text(SPEC, encoding="utf-8")
    (root / "class").mkdir()
    for i, name in enumerate(STUDENTS):
        # each drives a little further (18 to 24 cm): some end within 25 mm of 20 cm, some not;
        # every third turns the other way (the heading differs, the points do not)
        text = OUT_TURN_BEEP if i % 3 else OUT_TURN_BEEP.replace("angle: 90 deg", "angle: -90 deg")
        text = text.replace("distance: 20 cm", f"distance: {18 + i} cm")
        (root / "class" / f"{name}.yaml").write_text(text, encoding="utf-8")
    # hal hands in two missions, neither named after the test: missing, and in the report
    (root / "class" / "hal").mkdir()
    for name in ("first", "second"):
        (root / "class" / "hal" / f"{name}.yaml").write_text(OUT_TURN_BEEP, encoding="utf-8")
    whole = run_cli(
        "grade", "spec.yaml", "--mission", "class", "--results", "all.jsonl", "--json",
        "--csv", "all.csv", *PATIENT, cwd=root,
    )  # fmt: skip
    assert whole.returncode in (0, 1), whole.stderr
    parts = []
    for i in (1, 2, 3):
        # parts/ is not there yet: it is made, as the guide's Kubernetes Job needs on its first run
        part = run_cli(
            "grade", "spec.yaml", "--mission", "class", "--shard", f"{i}/3",
            "--results", f"parts/part{i}.jsonl", *PATIENT, cwd=root,
        )  # fmt: skip
        assert part.returncode in (0, 1), part.stderr
        parts.append(f"parts/part{i}.jsonl")
    return {"root": root, "whole": whole.stdout, "parts": parts}


def test_a_class_graded_in_three_parts_merges_into_the_report_of_one_run(
    graded: dict[str, Any],
) -> None:
    root = graded["root"]
    statuses = {run["status"] for run in json.loads(graded["whole"])["runs"]}
    assert {"passed", "failed", "missing"} <= statuses  # every kind of result crosses
    merged = run_cli("gradebook", *graded["parts"], "--json", "--csv", "merged.csv", cwd=root)
    assert merged.returncode in (0, 1), merged.stderr
    assert json.dumps(_without_wall_time(json.loads(merged.stdout))) == json.dumps(
        _without_wall_time(json.loads(graded["whole"]))
    )
    assert (root / "merged.csv").read_bytes() == (root / "all.csv").read_bytes()


def test_the_gradebook_of_one_run_repeats_its_json_byte_for_byte(graded: dict[str, Any]) -> None:
    again = run_cli("gradebook", "all.jsonl", "--json", cwd=graded["root"])
    assert again.stdout == graded["whole"]


def test_the_parts_hold_every_student_once(graded: dict[str, Any]) -> None:
    root = graded["root"]
    held = []
    for part in graded["parts"]:
        header = json.loads((root / part).read_text(encoding="utf-8").splitlines()[0])
        held += [s["name"] for s in header["students"]]
        runs = (root / part).read_text(encoding="utf-8").splitlines()[1:]
        assert {json.loads(r)["student"] for r in runs} == {s["name"] for s in header["students"]}
    assert sorted(held) == sorted([*STUDENTS, "hal"])


def test_a_missing_part_is_refused_naming_it(graded: dict[str, Any]) -> None:
    merged = run_cli("gradebook", *graded["parts"][:2], "--json", cwd=graded["root"])
    assert merged.returncode == 2
    assert merged.stderr.strip() == "error: part 3 of 3 missing: give every part's results file"
    assert merged.stdout == ""


def test_a_part_cut_short_is_refused(graded: dict[str, Any], tmp_path: Path) -> None:
    root = graded["root"]
    lines = (root / "all.jsonl").read_text(encoding="utf-8").splitlines()
    (root / "cut.jsonl").write_text("\n".join(lines[:-1]) + "\n", encoding="utf-8")
    merged = run_cli("gradebook", "cut.jsonl", "--csv", "cut.csv", cwd=root)
    assert merged.returncode == 2
    assert (
        "cut.jsonl lacks the run of" in merged.stderr and "grade that part again" in merged.stderr
    )
    assert not (root / "cut.csv").exists()


def test_a_spec_changed_since_grading_is_refused(graded: dict[str, Any], tmp_path: Path) -> None:
    root = graded["root"]
    moved = tmp_path / "elsewhere"
    moved.mkdir()
    (moved / "spec.yaml").write_text(SPEC.replace("radius: 25 mm", "radius: 10 mm"), "utf-8")
    (moved / "all.jsonl").write_bytes((root / "all.jsonl").read_bytes())
    merged = run_cli("gradebook", "all.jsonl", "--json", cwd=moved)
    assert merged.returncode == 2
    assert "the test spec spec.yaml (or a world it names) changed since" in merged.stderr


def test_a_class_gradebook_is_no_gradescope_results(graded: dict[str, Any]) -> None:
    merged = run_cli("gradebook", "all.jsonl", "--gradescope", "gs.json", cwd=graded["root"])
    assert merged.returncode == 2
    assert "a Gradescope results.json is one student's" in merged.stderr
    assert not (graded["root"] / "gs.json").exists()


def test_a_students_part_is_the_same_in_every_process() -> None:
    """Python's own hash() changes with PYTHONHASHSEED; the part must not."""
    here = [shard_number(name, 5) for name in STUDENTS]
    code = "from roboscript.grading.shards import shard_number as s; print([s(n, 5) for n in %r])"
    for seed in ("1", "2"):
        other = subprocess.run(
            [sys.executable, "-c", code % (STUDENTS,)],
            capture_output=True,
            text=True,
            env={**os.environ, "PYTHONHASHSEED": seed},
            check=True,
        )
        assert other.stdout.strip() == str(here)
    assert all(1 <= n <= 5 for n in here) and len(set(here)) > 1


def test_each_student_is_in_exactly_one_part() -> None:
    names = [f"student{i}" for i in range(200)]
    for count in (1, 2, 3, 7):
        owners = [[i for i in range(1, count + 1) if Shard(i, count).holds(n)] for n in names]
        assert all(len(found) == 1 for found in owners)


@pytest.mark.parametrize("text", ["3", "0/3", "4/3", "1/0", "a/b", "-1/2", "1/2/3"])
def test_a_bad_shard_is_one_sentence(text: str) -> None:
    with pytest.raises(ValueError, match=r"^--shard (is )?I/N"):
        Shard.parse(text)
    result = run_cli("grade", "x.yaml", "--mission", "y", f"--shard={text}")
    assert result.returncode == 2
    assert result.stderr.startswith("error: --shard ") and "Traceback" not in result.stderr


def test_a_part_of_one_submission_is_refused() -> None:
    result = run_cli("grade", "x.yaml", "--mission", "y", "--shard=1/2", "--gradescope=r.json")
    assert result.returncode == 2
    assert result.stderr == (
        "error: --shard splits a class, and a platform's results.json is one submission's\n"
    )


def _rewrite_header(source: Path, target: Path, change: Any) -> None:
    lines = source.read_text(encoding="utf-8").splitlines()
    header = json.loads(lines[0])
    change(header)
    target.write_text("\n".join([json.dumps(header), *lines[1:]]) + "\n", encoding="utf-8")


@pytest.mark.parametrize(
    "damage",
    [
        lambda header: header.pop("specs"),
        lambda header: header.update(students=[{"name": "ada"}]),
        lambda header: header.update(specs=[{"path": 1}]),
        lambda header: header.update(shard=["a", 3]),
        lambda header: header.update(shard=[0, 0]),
        lambda header: header["students"][0].update(own=[1, 2]),
        lambda header: header["students"][0].update(problem=["x" * 10_000_000]),
    ],
    ids=[
        "no specs",
        "a student without missions",
        "a spec without a path",
        "a shard of text",
        "shard 0 of 0",
        "own files that are numbers",
        "a problem of 10 MB",
    ],
)
def test_a_damaged_results_header_is_one_sentence(graded: dict[str, Any], damage: Any) -> None:
    root = graded["root"]
    _rewrite_header(root / "all.jsonl", root / "damaged.jsonl", damage)
    merged = run_cli("gradebook", "damaged.jsonl", "--csv", "damaged.csv", cwd=root)
    assert merged.returncode == 2
    assert merged.stderr.startswith("error: damaged.jsonl is damaged: "), merged.stderr
    assert "Traceback" not in merged.stderr and len(merged.stderr) < 1000
    assert not (root / "damaged.csv").exists()


def test_a_part_whose_names_an_older_grader_cleaned_less_still_merges(
    graded: dict[str, Any],
) -> None:
    root = graded["root"]
    # An older roboscript left a zero-width space in a name; this one shows it as "�".
    text = (root / "all.jsonl").read_text(encoding="utf-8").replace('"ada"', '"ada\\u200b"')
    (root / "older.jsonl").write_text(text, encoding="utf-8")
    merged = run_cli("gradebook", "older.jsonl", "--json", cwd=root)
    assert merged.returncode in (0, 1), merged.stderr
    merged_runs = json.loads(merged.stdout)["runs"]
    whole_runs = json.loads(graded["whole"])["runs"]
    assert [r["status"] for r in merged_runs if r["student"] == "ada\ufffd"] == [
        r["status"] for r in whole_runs if r["student"] == "ada"
    ]


def test_a_message_written_into_a_part_by_hand_moves_no_terminal_and_reorders_nothing(
    graded: dict[str, Any],
) -> None:
    # A part is a file anyone with the folder can edit: what it says is shown as text only,
    # never as a terminal's escape or a control that shows what follows it backwards.
    root = graded["root"]
    header, *lines = (root / "all.jsonl").read_text(encoding="utf-8").splitlines()
    forged = "deliaf \u202epassed\u2067 \x1b[2J 100%"
    edited = [header]
    for line in lines:
        run = json.loads(line)
        run["message"] = forged
        edited.append(json.dumps(run))
    (root / "edited.jsonl").write_text("\n".join(edited) + "\n", encoding="utf-8")
    merged = run_cli(
        "gradebook", "edited.jsonl", "--html", "edited-html", "--junit", "edited.xml", cwd=root
    )  # fmt: skip
    assert merged.returncode in (0, 1), merged.stderr
    assert "deliaf �passed� �[2J 100%" in merged.stdout  # hal's missing runs say it
    pages = [page.read_text(encoding="utf-8") for page in (root / "edited-html").rglob("*.html")]
    junit = (root / "edited.xml").read_text(encoding="utf-8")
    for text in (merged.stdout, merged.stderr, junit, *pages):
        assert not re.search("[\x1b\u202a-\u202e\u2066-\u2069]", text)


def _set(run: dict[str, Any], where: str, value: Any) -> None:
    """Set the field at a dotted path (``record.sim.path.3.1``) of a run line."""
    *outer, last = where.split(".")
    for key in outer:
        run = run[int(key)] if isinstance(run, list) else run[key]
    if isinstance(run, list):
        run[int(last)] = value
    else:
        run[last] = value


@pytest.mark.parametrize(
    ("field", "value", "said"),
    [
        ("status", "great", "status"),
        ("message", None, "message"),
        ("score", "100%", "score"),
        ("score", 7, "score"),
        ("label", 3, "label"),
        ("replay", 1, "replay"),
        ("variant", 9, "variant"),
        ("wall_time_s", -1.0, "wall_time_s"),
        # the spec's default wall_time_limit (60 s), the backstop, a busy or paused machine
        ("wall_time_s", 75_000.5, "is not a time a run of out-and-turn takes (at most 75000 s)"),
        ("record.duration_s", 1e30, "duration_s"),
        ("record.duration_s", float("nan"), "NaN"),
        ("record.duration_s", -5, "duration_s"),
        ("record.duration_s", "3 s", "record.duration_s"),
        ("record.sim.path.3.1", "x", "record.sim.path[3][1]"),
        ("record.sim.final_pose.x_mm", None, "record.sim.final_pose.x_mm"),
        ("record.sim.path", [[0.0, 0.0, 0.0, 0.0]] * 100_000, "path samples"),
        ("record.states.0.0", 1e12, "time"),
        ("record.states", [[1.0, "go"]] * (MAX_GRADED_STATES + 1), "states, more than"),
        ("record.sim", 5, "SimulatedRun"),
        ("verdicts.0.weight", "x", "verdicts[0].weight"),
        ("verdicts.0", {"name": "x", "passed": True, "evil": 1}, "verdict"),
        ("replay.frames.2.t", 1e30, "outside the run"),
        ("replay.frames.2.pose", "x", "replay.frames[2].pose"),
        ("replay.header.robot", [], "replay.header.robot"),
    ],
)
def test_a_damaged_run_line_is_one_sentence_and_the_others_are_still_reported(
    graded: dict[str, Any], field: str, value: Any, said: str
) -> None:
    root = graded["root"]
    lines = (root / "all.jsonl").read_text(encoding="utf-8").splitlines()
    number = next(n for n, line in enumerate(lines[1:], 2) if json.loads(line)["record"])
    run = json.loads(lines[number - 1])
    _set(run, field, value)
    lines[number - 1] = json.dumps(run)
    (root / "bad-run.jsonl").write_text("\n".join(lines) + "\n")
    merged = run_cli(
        "gradebook", "bad-run.jsonl", "--html", "bad-html", "--csv", "bad.csv", cwd=root
    )  # fmt: skip
    assert merged.returncode == 2
    errors = [line for line in merged.stderr.splitlines() if line.startswith("error:")]
    damaged, left_out, *more = errors
    assert damaged.startswith(f"error: bad-run.jsonl line {number} is damaged: "), errors
    assert said in damaged and not more, merged.stderr
    assert left_out.startswith(f"error: {run['student']} is left out of every report"), left_out
    rows = (root / "bad.csv").read_text(encoding="utf-8-sig").splitlines()[1:]
    everyone = {*STUDENTS, "hal"} - {run["student"]}
    assert {row.split(",")[0] for row in rows} == everyone
    assert (root / "bad-html" / "index.html").is_file()


def test_a_run_that_waited_long_on_a_busy_or_paused_machine_still_merges(
    graded: dict[str, Any],
) -> None:
    root = graded["root"]
    lines = (root / "all.jsonl").read_text(encoding="utf-8").splitlines()
    run = json.loads(lines[1])
    run["wall_time_s"] = 75_000.0  # (60 s + the backstop) a thousand times over: a night's pause
    lines[1] = json.dumps(run)
    (root / "paused.jsonl").write_text("\n".join(lines) + "\n")
    merged = run_cli("gradebook", "paused.jsonl", "--json", cwd=root)
    assert merged.returncode in (0, 1), merged.stderr
    walls = [r["wall_time_s"] for r in json.loads(merged.stdout)["runs"]]
    assert 75_000.0 in walls


def test_a_run_line_given_twice_is_refused_naming_both_lines(graded: dict[str, Any]) -> None:
    root = graded["root"]
    header, first, *rest = (root / "all.jsonl").read_text(encoding="utf-8").splitlines()
    (root / "twice.jsonl").write_text("\n".join([header, first, first, *rest]) + "\n")
    merged = run_cli("gradebook", "twice.jsonl", "--csv", "twice.csv", cwd=root)
    assert merged.returncode == 2
    student = json.loads(first)["student"]
    assert [line for line in merged.stderr.splitlines() if line.startswith("error:")] == [
        (
            f"error: twice.jsonl line 3 is damaged: it repeats the run of {student} in"
            " out-and-turn on line 2"
        )
    ]
    rows = (root / "twice.csv").read_text(encoding="utf-8-sig").splitlines()[1:]
    assert len(rows) == len(STUDENTS) + 1  # nobody was lost: the first line counts


def _class_copied(source: Path, target: Path, copies: int) -> None:
    """The class of the results file ``source``, ``copies`` times over (each student again as
    NAME-1, NAME-2, ...), written to ``target``: a larger class with the same runs."""
    header, *runs = source.read_text(encoding="utf-8").splitlines()
    head = json.loads(header)
    students = head["students"]
    head["students"] = [{**s, "name": f"{s['name']}-{i}"} for i in range(copies) for s in students]
    with target.open("w", encoding="utf-8") as out:
        out.write(json.dumps(head) + "\n")
        for i in range(copies):
            for line in runs:
                run = json.loads(line)
                run["student"] = f"{run['student']}-{i}"
                out.write(json.dumps(run, ensure_ascii=False) + "\n")


def _gradebook_peak_bytes(root: Path, part: Path, out: Path) -> int:
    """The most memory ``roboscript gradebook`` held (bytes, as Python's allocator counts
    them) writing every report of ``part``: the table, --json, --csv, --junit and --html."""
    from roboscript.cli import _parser

    args = _parser().parse_args(
        ["gradebook", str(part), "--json", "--csv", str(out / "g.csv"), "--junit",
         str(out / "j.xml"), "--html", str(out / "html")]
    )  # fmt: skip
    cwd = Path.cwd()
    os.chdir(root)  # the gradebook reads the specs from where grade ran
    tracemalloc.start()
    try:
        with open(os.devnull, "w", encoding="utf-8") as sink, contextlib.redirect_stdout(sink):
            assert args.func(args) in (0, 1)
        return tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
        os.chdir(cwd)


def test_the_gradebook_holds_one_runs_record_at_a_time_however_large_the_class(
    graded: dict[str, Any], tmp_path: Path
) -> None:
    # Counted, not timed: what the gradebook holds at its peak, for a class and for the same
    # class eight times over. Kept whole, the runs' records and replays (tens of kilobytes
    # each) would make the peak grow with the class; read one at a time, it barely moves.
    root = graded["root"]
    peaks = []
    for copies in (1, 8):
        part = tmp_path / f"class-{copies}.jsonl"
        _class_copied(root / "all.jsonl", part, copies)
        (tmp_path / str(copies)).mkdir()
        peaks.append(_gradebook_peak_bytes(root, part, tmp_path / str(copies)))
    assert peaks[1] < 2 * peaks[0], peaks  # whole, 8 times the class held 6.8 times more
