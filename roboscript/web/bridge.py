"""What the browser app asks of roboscript: check, run and draw a mission given as text.

The page (``roboscript web build``) runs this very package in Pyodide and calls these
functions with the editor's text; each answers a JSON string, so the page needs no Python
objects. They are ordinary functions: the tests call them in CPython too, and a mission
gives the same JSON for a seed in either runtime.

A mission in the editor is written to a scratch folder (``/home/pyodide/missions`` in the
browser) under the name the student gave it, so messages name the file as on the command
line: ``hello.yaml:4:28: error: ...``.
"""

from __future__ import annotations

import json
import re
import tempfile
from pathlib import Path
from typing import Any

from roboscript.errors import InputError, MissionError, RoboscriptError
from roboscript.interrupts import Interrupted
from roboscript.mission import mission_for_robot
from roboscript.mission.graph_picture import to_svg
from roboscript.replay.session_tap import RunRecording
from roboscript.replay.viewer import viewer_block
from roboscript.session import run_session, session_record
from roboscript.web.connect import on_robot

__all__ = ["check_text", "diagram_text", "run_text"]

_SAFE_NAME = re.compile(r"[^\w.-]")
_MAX_TIME_S = 300.0


def _folder() -> Path:
    browser_home = Path("/home/pyodide")
    base = browser_home if browser_home.is_dir() else Path(tempfile.gettempdir())
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


def _problem(problem: InputError, path: Path) -> dict[str, Any]:
    return {
        "line": problem.line,
        "col": problem.col,
        "severity": problem.severity,
        "message": problem.message,
        "hint": problem.hint,
        "text": problem.format().replace(str(path), path.name),
    }


def _load(name: str, text: str, robot: str | None) -> tuple[Path, Any, Any, list[dict[str, Any]]]:
    path = _write(name, text)
    try:
        spec, profile, warnings = mission_for_robot(path, robot or None)
    except InputError as exc:
        problems = getattr(exc, "problems", None) or [exc]
        return path, None, None, [_problem(p, path) for p in problems]
    return path, spec, profile, [_problem(w, path) for w in warnings]


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
        replay viewer's HTML block or null}``, and ``"wire_log"`` (its text) on a robot. A
        mission with errors is not run.
    """
    path, spec, profile, problems = _load(name, text, robot)
    if spec is None or any(p["severity"] == "error" for p in problems):
        return json.dumps({"problems": problems, "summary": None, "viewer": None})
    recording = RunRecording()
    with on_robot(port, path.parent) as on:
        try:
            session = run_session(
                spec,
                profile,
                world=world or spec.world or "empty",
                seed=seed,
                max_time_s=_MAX_TIME_S,
                recording=recording,
                runaway_after_s=None,  # no thread to watch with in a browser tab
                **on.options,
            )
        except (RoboscriptError, Interrupted) as exc:  # Interrupted: stopped while connecting
            error = exc.reason if isinstance(exc, Interrupted) else str(exc)
            return json.dumps(
                {"problems": problems, "summary": None, "viewer": None, "error": error}
                | on.answer()
            )
    summary = session_record(session).to_dict()
    viewer = None
    if recording.recorder is not None:
        viewer = viewer_block(recording.recorder.recording(), label=f"replay of {path.name}")
    return json.dumps({"problems": problems, "summary": summary, "viewer": viewer} | on.answer())


def diagram_text(name: str, text: str) -> str:
    """The mission's state diagram as SVG text, or ``""`` when the mission has errors."""
    try:
        spec = _load(name, text, None)[1]
    except MissionError:
        return ""
    return "" if spec is None else to_svg(spec)
