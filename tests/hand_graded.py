"""A class report built by hand (no simulation): fast inputs for the report writers' tests.

The test is worth 12 points over three runs (4 each); run 3 is hidden, with a seed, a start
and a spec path that no student-facing text may contain (:data:`HIDDEN_SECRETS`).
"""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

from roboscript.grading.batch import ClassReport, Submission
from roboscript.grading.record import RunRecord, RunResult, Tone, Verdict
from roboscript.grading.spec import TestSpec, load_test_spec

SPEC_TEXT = """\
test: square-50cm
description: Drive a 50 cm square and come home.
world: empty
points: 12
runs:
  - {seed: 1}
  - {seed: 2, start: {x: 300 mm, y: -200 mm, heading: 0 deg}}
  - {seed: 7919, start: {x: 417 mm, y: -173 mm, heading: 33 deg}, hidden: true}
expect:
  - outcome: success
  - final_pose_within: {x: 0 mm, y: 0 mm, radius: 8 cm, relative_to: start}
"""

HIDDEN_SECRETS = ("7919", "417", "-173", "33°", "secret-tests")
"""Text of the hidden run (seed, start) and of the spec's folder, never shown to a student."""


def hand_spec(tmp_path: Path) -> TestSpec:
    """The spec, in a folder called ``secret-tests``."""
    folder = tmp_path / "secret-tests"
    folder.mkdir(exist_ok=True)
    path = folder / "square.yaml"
    path.write_text(SPEC_TEXT, encoding="utf-8")
    return load_test_spec(path)


def _record(seed: int, start: tuple[float, float, float], end: tuple[float, float]) -> RunRecord:
    x0, y0, h0 = start
    path = tuple(
        (t * 0.5, x0 + (end[0] - x0) * t / 20, y0 + (end[1] - y0) * t / 20, h0) for t in range(21)
    )
    return RunRecord.simulated(
        mission="square",
        robot="mirto",
        world_name="empty",
        seed=seed,
        outcome="success",
        final_state="finished",
        reason=None,
        duration_s=10.0,
        states=((0.0, "side"), (5.0, "corner"), (9.0, "finished")),
        path=path,
        tones=(Tone(5.0, 880.0, 0.2),),
        final_pose=(end[0], end[1], h0),
        distance_travelled_mm=500.0,
    )


def _pose_verdict(passed: bool, target: tuple[float, float]) -> Verdict:
    margin = "passed by 3.0 cm" if passed else "failed by 41.5 cm"
    return Verdict(
        "final_pose_within",
        passed,
        margin,
        None if passed else 10.0,
        f"ended 5.0 cm from the target ({target[0]:.0f}, {target[1]:.0f}) mm (allowed 8 cm)",
        30.0 if passed else -415.0,
        "mm",
        0.375 if passed else -5.2,
    )


def student_runs(spec: TestSpec, student: str, good: bool) -> list[RunResult]:
    """One student's three runs: all pass (``good``), or run 2 crashes and run 3 fails."""
    v1, v2, v3 = spec.variants
    outcome = Verdict("outcome", True, detail="the mission ended in success")
    mission = f"class/{student}.yaml"
    first = spec.result(
        v1,
        student=student,
        mission=mission,
        status="passed",
        score=1.0,
        verdicts=(outcome, _pose_verdict(True, (0, 0))),
        record=_record(1, (0.0, 0.0, 0.0), (0.0, 30.0)),
    )
    if good:
        second = spec.result(
            v2,
            student=student,
            mission=mission,
            status="passed",
            score=1.0,
            verdicts=(outcome, _pose_verdict(True, (300, -200))),
            record=_record(2, (300.0, -200.0, 0.0), (300.0, -170.0)),
        )
        third = spec.result(
            v3,
            student=student,
            mission=mission,
            status="passed",
            score=1.0,
            verdicts=(outcome, _pose_verdict(True, (417, -173))),
            record=_record(7919, (417.0, -173.0, 33.0), (417.0, -143.0)),
        )
        return [first, second, third]
    second = spec.result(
        v2,
        student=student,
        mission=mission,
        status="crashed",
        message="the run crashed: ZeroDivisionError: division by zero (square.py:12)",
        debug='Traceback (most recent call last):\n  File "square.py", line 12\nZeroDivisionError',
    )
    pose = _pose_verdict(False, (417, -173))
    third = spec.result(
        v3,
        student=student,
        mission=mission,
        status="failed",
        message=pose.text,  # as run_message makes it: it names the hidden start
        score=0.5,
        verdicts=(outcome, pose),
        record=_record(7919, (417.0, -173.0, 33.0), (0.0, 0.0)),
    )
    return [first, second, third]


def hand_report(tmp_path: Path, good: str = "Zelda", bad: str = "Quentin") -> ClassReport:
    """A class of two: ``good`` passes everything (12/12), ``bad`` scores 4 + 0 + 2 = 6/12."""
    spec = hand_spec(tmp_path)
    results = student_runs(spec, bad, good=False) + student_runs(spec, good, good=True)
    submissions = [
        Submission(bad, (f"class/{bad}.yaml",)),
        Submission(good, (f"class/{good}.yaml",)),
    ]
    return ClassReport([spec], submissions, results, dict(spec.worlds))


def one_student(report: ClassReport, student: str) -> ClassReport:
    """The report of one of its students, as Gradescope grades them."""
    return replace(
        report,
        submissions=[s for s in report.submissions if s.student == student],
        results=[r for r in report.results if r.student == student],
    )
