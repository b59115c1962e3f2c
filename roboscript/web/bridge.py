"""What the browser app asks of roboscript: check, run and draw a mission given as text.

The page (``roboscript web build``) runs this very package in Pyodide and calls these
functions with the editor's text; each answers a JSON string, so the page needs no Python
objects. They are ordinary functions: the tests call them in CPython too, and a mission
gives the same JSON for a seed in either runtime.

A teacher's test spec (shipped in the page by ``web build --spec``, or opened by the student)
is written under ``/home/pyodide/specs`` and :func:`grade_text` gives the practice grade
(:mod:`roboscript.grading.practice`): the grader's runs and judging, in the page's one process.

A mission in the editor is written to a scratch folder (``/home/pyodide/missions`` in the
browser, a temporary folder of the process's own elsewhere) under the name the student gave
it, so messages name the file as on the command line: ``hello.yaml:4:28: error: ...``.
"""

from __future__ import annotations

import atexit
import contextlib
import functools
import json
import os
import re
import shutil
import tempfile
from pathlib import Path
from typing import Any

from roboscript.errors import InputError, MissionError, RoboscriptError
from roboscript.grading.judge import failure_marks
from roboscript.grading.practice import practice_grade
from roboscript.grading.spec import TestSpec, is_test_spec, load_test_spec
from roboscript.grading.text import advice, format_points, public_reason, student_text
from roboscript.inputs.kinds import FileKind, NotAMissionError
from roboscript.interrupts import Interrupted
from roboscript.mission import mission_for_robot
from roboscript.mission.channels import MAX_PRINTED_LINES
from roboscript.mission.graph_picture import to_svg
from roboscript.mission.student_code import is_student_file, shown_path, stuck_at
from roboscript.replay.session_tap import RunRecording
from roboscript.replay.viewer import viewer_block
from roboscript.session import run_session, session_record
from roboscript.watchdog import DEFAULT_LIMIT_S, RunawayCode, Watchdog
from roboscript.web.connect import on_robot

__all__ = ["check_text", "diagram_text", "grade_text", "load_specs", "run_text"]

_SAFE_NAME = re.compile(r"[^\w.-]")
_MAX_TIME_S = 300.0

ON_THE_PAGE: dict[FileKind, str] = {
    "world": (
        'a simulator world: to run your mission in it, set World to "the mission\'s own" and'
        " name it in your mission: 'world: {path}' in YAML, world = \"{path}\" in a Python"
        " mission's class"
    ),
    "profile": (
        'a robot profile: to run your mission on it, set Robot to "the mission\'s own" and'
        " name it in your mission: 'robot: {path}' in YAML, robot = \"{path}\" in a Python"
        " mission's class"
    ),
    "test spec": (
        'a teacher\'s test spec: open it with "Open a test spec…" under Practice grade, then'
        ' press "✓ Grade my mission"'
    ),
}
"""What a world, robot profile or test spec opened as the mission is for, said with the page's
own controls (its World and Robot lists, its practice grade): a page has no ``--world``. A file
opened in the page stays in its folder while the page is open, so a mission beside it finds it
by its name."""


@functools.cache
def _own_home() -> Path:
    """Outside the browser (CPython: the tests, a script), a folder of this process's own in
    place of the page's home: two programs calling these functions at once each check and
    grade their own files (a shared one was overwritten by the other's mission or spec)."""
    home = Path(tempfile.mkdtemp(prefix="roboscript-page-"))
    atexit.register(shutil.rmtree, home, ignore_errors=True)
    return home


def _folder() -> Path:
    browser_home = Path("/home/pyodide")
    base = browser_home if browser_home.is_dir() else _own_home()
    folder = base / "missions"
    folder.mkdir(parents=True, exist_ok=True)
    return folder


def _write(name: str, text: str) -> Path:
    """The mission's text as a file named as the student named it (cleaned for a path)."""
    clean = _SAFE_NAME.sub("_", Path(name).name) or "mission.yaml"
    if not clean.endswith((".yaml", ".yml", ".py")):
        clean += ".yaml"
    path = _folder() / clean
    path.write_text(text, encoding="utf-8")
    return path


def _named(text: str) -> str:
    """``text`` with the scratch folder left out of its paths: each file in it named as the
    student named it. The folder is left out in full and as :func:`shown_path` writes it
    (``missions/``: the browser works in ``/home/pyodide``)."""
    folder = _folder()
    for shown in dict.fromkeys((str(folder), shown_path(folder))):
        if shown != ".":  # working in the folder itself, a file is already shown by its name
            text = text.replace(shown + os.sep, "")
    return text


def _problem(problem: InputError) -> dict[str, Any]:
    return {
        "line": problem.line,
        "col": problem.col,
        "severity": problem.severity,
        "message": _named(problem.message),
        "hint": _named(problem.hint) if problem.hint is not None else None,
        "text": _named(problem.format()),
    }


def _stuck_problem(exc: RunawayCode, path: Path) -> dict[str, Any]:
    """A mission file stopped while loading, as a problem of :func:`check_text`: at the line
    it was stuck at when that is the mission's own (else at its first line: the loop is in
    another file, which the message names)."""
    in_mission = exc.file is not None and Path(exc.file).resolve() == path.resolve()
    line = exc.line if in_mission and exc.line is not None else 1
    message = _named(exc.reason)
    return {
        "line": line,
        "col": 1,
        "severity": "error",
        "message": message,
        "hint": "",
        "text": f"{path.name}:{line}:1: error: {message}",
    }


def _load(
    name: str, text: str, robot: str | None, recording: RunRecording | None = None
) -> tuple[Path, Any, Any, list[dict[str, Any]]]:
    path = _write(name, text)
    try:
        # a Python mission runs when imported: a loop there is stopped at its line, not the tab
        with (
            Watchdog(DEFAULT_LIMIT_S, stuck_at, watched=is_student_file),
            # what it prints while it loads is the run's too, before the start
            recording.loading() if recording is not None else contextlib.nullcontext(),
        ):
            spec, profile, warnings = mission_for_robot(path, robot or None)
    except RunawayCode as exc:
        return path, None, None, [_stuck_problem(exc, path)]
    except NotAMissionError as exc:
        return path, None, None, [_problem(exc.advised(ON_THE_PAGE))]
    except InputError as exc:
        problems = getattr(exc, "problems", None) or [exc]
        return path, None, None, [_problem(p) for p in problems]
    return path, spec, profile, [_problem(w) for w in warnings]


def check_text(name: str, text: str, robot: str = "") -> str:
    """``roboscript check`` of one mission's text.

    Args:
        name: The file name the student gave it (``hello.yaml``, ``square.py``).
        text: The mission.
        robot: A built-in robot to check it against (``""``: the mission's own, or mirto).

    Returns:
        JSON ``{"problems": [{line, col, severity, message, hint, text}, ...]}``, errors and
        warnings in the order ``check`` prints them; lines and columns are 1-based.
    """
    _, _, _, problems = _load(name, text, robot)
    return json.dumps({"problems": problems})


def run_text(
    name: str, text: str, robot: str = "", world: str = "", seed: int = 1, port: str = ""
) -> str:
    """``roboscript run --json --record`` of one mission's text, on the simulator or a robot.

    Args:
        port: A robot the student connected in the page (:func:`roboscript.web.connect.
            remember`), run in real time with a wire log; ``""``: the simulator. The page
            calls a run on a robot with Pyodide's ``callPromising``, so it can wait.

    Returns:
        JSON ``{"problems": [...], "summary": run --json's object or null, "viewer": the
        replay viewer's HTML block or null, "note": a sentence on what the record left out
        (a flood of ``print``) or ""}``, and ``"wire_log"`` (its text) on a robot. A mission
        with errors is not run.
    """
    recording = RunRecording()
    path, spec, profile, problems = _load(name, text, robot, recording)
    if spec is None or any(p["severity"] == "error" for p in problems):
        return json.dumps({"problems": problems, "summary": None, "viewer": None})
    with on_robot(port, path.parent, profile) as on:
        try:
            session = run_session(
                spec,
                profile,
                world=world or spec.world or "empty",
                seed=seed,
                max_time_s=_MAX_TIME_S,
                recording=recording,
                # the tab has no timer signal: stuck code is stopped between two of its lines
                runaway_after_s=DEFAULT_LIMIT_S,
                **on.options,
            )
        except (RoboscriptError, Interrupted) as exc:  # Interrupted: stopped while connecting
            error = exc.reason if isinstance(exc, Interrupted) else str(exc)
            return json.dumps(
                {"problems": problems, "summary": None, "viewer": None, "error": error}
                | on.answer()
            )
    summary = session_record(session).to_dict()
    reason = summary.get("reason")
    if isinstance(reason, str):  # the page's scratch folder means nothing to the student
        summary["reason"] = _named(reason)
    viewer = None
    note = ""
    if recording.recorder is not None:
        viewer = viewer_block(recording.recorder.recording(), label=f"replay of {path.name}")
        note = _prints_note(recording.recorder.result or {})
    answer = {"problems": problems, "summary": summary, "viewer": viewer, "note": note}
    return json.dumps(answer | on.answer())


def _prints_note(result: dict[str, Any]) -> str:
    """One sentence on a flood of ``print``: how many lines the mission printed and how many
    the record kept (``""`` when it kept them all)."""
    dropped = result.get("prints_not_recorded")
    if not isinstance(dropped, int) or dropped <= 0:
        return ""
    return (
        f"Your mission printed {MAX_PRINTED_LINES + dropped} lines: the replay keeps the first"
        f" {MAX_PRINTED_LINES} and counted the other {dropped} (print less often, or log() a"
        " value to plot it)."
    )


def diagram_text(name: str, text: str) -> str:
    """The mission's state diagram as SVG text, or ``""`` when the mission has errors."""
    try:
        spec = _load(name, text, None)[1]
    except MissionError:
        return ""
    return "" if spec is None else to_svg(spec)


# ------------------------------------------------------------------------- practice grade


def _specs_folder(slot: str) -> Path:
    return _folder().parent / "specs" / (_SAFE_NAME.sub("_", slot) or "specs")


def _spec_summary(spec: TestSpec) -> dict[str, Any]:
    """What the page shows of a spec before grading: no seed, start or world of a hidden run."""
    return {
        "path": spec.path,
        "test": spec.name,
        "description": spec.description,
        "robot": spec.robot,
        "points": spec.max_points,
        "runs": [{"label": v.public_label, "hidden": v.hidden} for v in spec.variants],
        "expect": [
            {"name": e.name, "weight": e.weight, "required": e.required} for e in spec.expectations
        ],
    }


def _spec_problem(problem: InputError, root: Path) -> dict[str, Any]:
    """A spec's problem, its file named from the folder the specs were loaded in."""
    return _problem(problem) | {"text": student_text(problem.format(), root)}


def load_specs(files: str, slot: str = "shipped") -> str:
    """Write a teacher's spec files into the page's folder and read every test spec among them.

    Args:
        files: JSON ``{path: text}``: test specs and the world and ``check`` files they name,
            each path relative to one folder (as ``web build --spec`` ships them, or the
            names of the files the student opened).
        slot: A folder of its own for this set (``shipped``, ``opened``): loading a set
            replaces the files loaded before in that folder.

    Returns:
        JSON ``{"specs": [{path, test, description, robot, points, runs: [{label,
        hidden}], expect: [{name, weight, required}]}, ...], "problems": [...]}``: a spec
        with a mistake is left out, and its mistake is a problem (``test.yaml:3:5: error:
        ...``).
    """
    folder = _specs_folder(slot)
    shutil.rmtree(folder, ignore_errors=True)
    written: list[Path] = []
    for name, text in json.loads(files).items():
        parts = [
            _SAFE_NAME.sub("_", part)
            for part in Path(name).parts
            if part not in ("", ".", "..", "/")
        ]
        if not parts:
            continue
        path = folder.joinpath(*parts)
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(text, encoding="utf-8")
        written.append(path)
    specs: list[dict[str, Any]] = []
    problems: list[dict[str, Any]] = []
    for path in sorted(p for p in written if p.suffix in (".yaml", ".yml") and is_test_spec(p)):
        try:
            specs.append(_spec_summary(load_test_spec(path)))
        except InputError as exc:
            problems += [_spec_problem(p, folder) for p in getattr(exc, "problems", None) or [exc]]
    return json.dumps({"specs": specs, "problems": problems})


def grade_text(name: str, text: str, spec_path: str) -> str:
    """The practice grade of one mission's text against a spec :func:`load_specs` wrote.

    Runs every run of the spec in this process and judges it as ``roboscript grade`` does
    (:mod:`roboscript.grading.practice`): the student's practice, never the teacher's record.
    A hidden run is named ``hidden run N``, with pass or fail and the grader's words for a
    student; its margins, seed, start and replay are not shown.

    Returns:
        JSON ``{"problems": [...], "spec": the spec's summary or null, "grade": {passed,
        score, points, max_points, points_text, max_points_text, passed_runs, total_runs,
        runs: [{label, hidden, status, passed, score, points, max_points, message, advice,
        verdicts: [{name, passed, required, weight, text, margin, first_violation_s}],
        viewer}]} or null}``.
    """
    path = _write(name, text)
    root = _folder()
    try:
        spec = load_test_spec(spec_path)
    except InputError as exc:
        problems = [
            _spec_problem(p, Path(spec_path).parent)
            for p in getattr(exc, "problems", None) or [exc]
        ]
        return json.dumps({"problems": problems, "spec": None, "grade": None})
    cell, runs = practice_grade(spec, str(path))
    shown = []
    for variant, run in zip(spec.variants, runs, strict=True):
        result = run.result
        hidden = variant.hidden
        verdicts = [
            {"name": v.name, "passed": v.passed, "required": v.required, "weight": v.weight}
            | (
                {}
                if hidden
                else {"text": v.text, "margin": v.margin, "first_violation_s": v.first_violation_s}
            )
            for v in result.verdicts
        ]
        viewer = None
        if run.recording is not None and not hidden:
            marks = failure_marks(result.verdicts)
            viewer = viewer_block(
                run.recording,
                open_at_s=min((m["t"] for m in marks), default=None),
                marks=marks,
                label=f"{spec.name}, {variant.public_label}",
            )
        finished = result.status in ("passed", "failed")
        shown.append(
            {
                "label": variant.public_label,
                "hidden": hidden,
                "status": result.status,
                "passed": result.passed,
                "score": result.score,
                "points": cell.run_points(result),
                "max_points": cell.run_max_points,
                "message": student_text(public_reason(result, hidden), root),
                "advice": "" if finished else advice(result.status),
                "verdicts": verdicts,
                "viewer": viewer,
            }
        )
    grade = {
        "passed": cell.passed,
        "score": cell.score,
        "points": cell.points,
        "max_points": cell.max_points,
        "points_text": format_points(cell.points),
        "max_points_text": format_points(cell.max_points),
        "passed_runs": cell.passed_runs,
        "total_runs": cell.total_runs,
        "runs": shown,
    }
    return json.dumps({"problems": [], "spec": _spec_summary(spec), "grade": grade})
