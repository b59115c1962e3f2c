"""A recorded run as columns: one row per tick, for a spreadsheet or a notebook's plots.

``roboscript view RUN.jsonl --csv RUN.csv`` writes them; ``RunResult.columns()`` returns them
(``pandas.DataFrame(result.columns())`` makes a table of them). Column names carry their units
as every name in roboscript does: ``t_s``, ``x_mm``, ``sensors.range_mm``,
``motors.left_mm_s``, and the student's own ``log.NAME`` (as they named it).
"""

from __future__ import annotations

import csv
from collections.abc import Iterable, Mapping
from pathlib import Path
from typing import Any

from roboscript.replay.recording import Recording

__all__ = ["run_columns", "write_csv"]

Column = list[Any]


def _names(frames: Iterable[Mapping[str, Any]], group: str) -> list[str]:
    seen: dict[str, None] = {}
    for frame in frames:
        for name in frame.get(group) or {}:
            seen.setdefault(name, None)
    return list(seen)


def _cell(value: Any) -> Any:
    """A value as one cell: lists (line sensors, bumpers) joined, so each column is flat."""
    if isinstance(value, list):
        return " ".join(str(v) for v in value)
    return value


def run_columns(recording: Recording) -> dict[str, Column]:
    """Every tick of ``recording`` as columns of equal length.

    Columns: ``t_s``, ``state``, ``why`` (on the tick of a transition, else empty), ``x_mm``,
    ``y_mm``, ``heading_deg`` (when the run has poses), then ``sensors.*``, ``motors.*``,
    ``log.*`` and ``print`` (what the mission printed on that tick, lines joined).
    """
    frames = recording.frames
    columns: dict[str, Column] = {"t_s": [], "state": [], "why": []}
    has_pose = any(frame.get("pose") for frame in frames)
    if has_pose:
        columns.update({"x_mm": [], "y_mm": [], "heading_deg": []})
    groups = {group: _names(frames, group) for group in ("sensors", "motors", "log")}
    for group, names in groups.items():
        for name in names:
            columns[f"{group}.{name}"] = []
    columns["print"] = []
    last_why: Any = None
    for frame in frames:
        columns["t_s"].append(frame.get("t"))
        columns["state"].append(frame.get("state"))
        why = frame.get("why")
        columns["why"].append(
            why.get("text") if isinstance(why, dict) and why != last_why else None
        )
        last_why = why
        if has_pose:
            pose = frame.get("pose") or [None, None, None]
            for key, value in zip(("x_mm", "y_mm", "heading_deg"), pose, strict=False):
                columns[key].append(value)
        for group, names in groups.items():
            values = frame.get(group) or {}
            for name in names:
                columns[f"{group}.{name}"].append(_cell(values.get(name)))
        printed = frame.get("print")
        columns["print"].append("\n".join(printed) if printed else None)
    return columns


def write_csv(recording: Recording, path: str | Path) -> None:
    """Write :func:`run_columns` as a CSV file (UTF-8, a header row, empty cells for none).

    Raises:
        OSError: The file cannot be written.
    """
    columns = run_columns(recording)
    names = list(columns)
    rows = zip(*(columns[name] for name in names), strict=True)
    with open(path, "w", encoding="utf-8", newline="") as out:
        writer = csv.writer(out)
        writer.writerow(names)
        for row in rows:
            writer.writerow(["" if cell is None else cell for cell in row])
