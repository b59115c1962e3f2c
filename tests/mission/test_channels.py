"""The student's own values: log() and plot: channels, and prints stamped with the time."""

from __future__ import annotations

import csv
import json
from pathlib import Path

import pytest
from helpers import LOGGING_MISSION, run_cli

from roboscript import log
from roboscript.mission.channels import (
    MAX_CHANNELS,
    PRINTED_LINE_CHARS,
    Channels,
    logging_to,
    printed_line,
)


def _frames(path: Path) -> list[dict[str, object]]:
    lines = path.read_text(encoding="utf-8").splitlines()
    return [json.loads(line) for line in lines[1:-1]]


def test_log_keeps_the_last_value_of_each_name_while_a_mission_runs() -> None:
    channels: Channels = {}
    with logging_to(channels):
        log(gap_cm=12, turning=True)
        log(gap_cm=11.5)
    assert channels == {"gap_cm": 11.5, "turning": True}


def test_log_outside_a_mission_does_nothing() -> None:
    log(gap_cm=3)  # a behaviour file imported on its own, or tested without a robot


def test_log_refuses_a_value_it_cannot_plot() -> None:
    with pytest.raises(TypeError, match=r"log\(\) records numbers and True/False, not str"):
        log(name="left")


def test_log_keeps_a_bounded_number_of_names() -> None:
    channels: Channels = {}
    with logging_to(channels):
        log(**{f"v{i}": i for i in range(MAX_CHANNELS)})
        log(v0=-1)  # a name already there is still welcome
        with pytest.raises(ValueError, match="at most 16 names"):
            log(one_more=1)
    assert len(channels) == MAX_CHANNELS


def test_a_value_that_is_not_a_number_is_recorded_as_none() -> None:
    channels: Channels = {}
    with logging_to(channels):
        log(ratio=float("nan"))
    assert channels == {"ratio": None}


def test_logged_values_and_prints_are_recorded_with_their_time(tmp_path: Path) -> None:
    (tmp_path / "logged.py").write_text(LOGGING_MISSION, encoding="utf-8")
    result = run_cli("run", "logged.py", "--record", "run.jsonl", cwd=tmp_path)
    assert result.returncode == 0, result.stderr
    # the terminal lines the print up with the states, by the mission time
    assert "    1.02 s  > one second in\n" in result.stdout
    frames = _frames(tmp_path / "run.jsonl")
    assert frames[0]["log"] == {"driven_cm": 0.0, "halfway": False}
    printed = [f for f in frames if "print" in f]
    assert [(f["t"], f["print"]) for f in printed] == [(1.02, ["one second in"])]
    became_true = next(f for f in frames if f.get("log", {}).get("halfway") is True)  # type: ignore[union-attr]
    assert float(became_true["t"]) > 0.5  # type: ignore[arg-type]


def test_a_yaml_mission_plots_condition_values(tmp_path: Path) -> None:
    (tmp_path / "m.yaml").write_text(
        "mission: m\nplot: [driven.total_cm, visits.go >= 1]\nstates:\n"
        "  go:\n    do: {drive: {distance: 20 cm}}\n    on: {done: end, failed: end}\n"
        "  end: {final: success}\n",
        encoding="utf-8",
    )
    result = run_cli("run", "m.yaml", "--record", "run.jsonl", cwd=tmp_path)
    assert result.returncode == 0, result.stderr
    frames = _frames(tmp_path / "run.jsonl")
    assert frames[0]["log"] == {"driven.total_cm": 0.0, "visits.go >= 1": True}
    driven = [f["log"]["driven.total_cm"] for f in frames if "driven.total_cm" in f.get("log", {})]  # type: ignore[index,operator]
    assert driven == sorted(driven) and driven[-1] == pytest.approx(20, abs=1)


def test_a_plot_with_a_mistake_is_an_error_at_its_line(tmp_path: Path) -> None:
    (tmp_path / "m.yaml").write_text(
        "mission: m\nplot: [rnage.distance_cm]\nstates:\n  go: {final: success}\n",
        encoding="utf-8",
    )
    result = run_cli("check", "m.yaml", cwd=tmp_path)
    assert result.stderr.splitlines()[0] == (
        "m.yaml:2:8: error: unknown name 'rnage' in a condition (did you mean 'range'?)"
    )


def test_view_exports_the_run_as_columns(tmp_path: Path) -> None:
    (tmp_path / "logged.py").write_text(LOGGING_MISSION, encoding="utf-8")
    assert run_cli("run", "logged.py", "--record", "run.jsonl", cwd=tmp_path).returncode == 0
    result = run_cli("view", "run.jsonl", "--csv", "run.csv", cwd=tmp_path)
    assert result.returncode == 0, result.stderr
    with open(tmp_path / "run.csv", encoding="utf-8", newline="") as table:
        rows = list(csv.DictReader(table))
    assert len(rows) == len(_frames(tmp_path / "run.jsonl"))
    assert rows[0]["why"] == "the mission started" and rows[1]["why"] == ""
    assert [r["print"] for r in rows if r["print"]] == ["one second in"]
    assert rows[-1]["log.halfway"] == "True"
    assert float(rows[-1]["log.driven_cm"]) == pytest.approx(30, abs=1)


def test_a_run_from_python_gives_its_values_as_columns(tmp_path: Path) -> None:
    import roboscript

    (tmp_path / "logged.py").write_text(LOGGING_MISSION, encoding="utf-8")
    result = roboscript.run(str(tmp_path / "logged.py"))
    columns = result.columns()
    lengths = {len(column) for column in columns.values()}
    assert len(lengths) == 1  # every column has a row per tick
    assert columns["log.driven_cm"][0] == 0.0
    assert result.transitions[-1]["cause"]["text"] == "drive done"


def test_a_printed_line_is_kept_printable_and_cut_at_its_length() -> None:
    assert printed_line("\x1b[1mbold\x1b[0m\tend\x07") == " [1mbold [0m end "
    assert printed_line("é" * PRINTED_LINE_CHARS) == "é" * PRINTED_LINE_CHARS  # whole: it fits
    assert printed_line("é" * (PRINTED_LINE_CHARS + 1)) == "é" * PRINTED_LINE_CHARS + "…"
