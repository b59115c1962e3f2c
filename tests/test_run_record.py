"""One run record: ``run --json``, the Python API, a graded run's record and the page agree."""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
from dataclasses import fields, replace
from pathlib import Path
from typing import Any

import pytest
from helpers import HANG_BOUND_S, MISSIONS, ROOT, run_cli

import roboscript
from roboscript.grading.record import Collision, GradedRecord, RunResult
from roboscript.grading.shards import read_results, spec_hash
from roboscript.grading.spec import load_test_spec
from roboscript.run_record import Pose, RunRecord, SimulatedRun, Tone
from roboscript.sim.world import World

GOLDEN = Path(__file__).resolve().parent / "golden"
"""Outputs written by the roboscript before the record was one class (the bytes to keep)."""

GOLDEN_RUNS = {
    "run_square_seed2.json": ("missions/square.yaml", "--seed", "2"),
    "run_square_corridor_seed1.json": (
        "missions/square.yaml",
        *("--world", "corridor", "--seed", "1", "--max-time", "30"),
    ),
}
"""Each golden ``run --json`` output and the command line that wrote it."""

SQUARE_SPEC = "missions/teacher/square/test.yaml"
SQUARE_GOOD = "missions/teacher/square/good.yaml"

CAUSE = {
    "kind": "when",
    "from": "go",
    "action": None,
    "reason": None,
    "condition": "bumper.any",
    "values": {"bumper.any": True},
    "timeout_s": None,
    "text": "'bumper.any' held (bumper.any = true)",
}


def _every_field_set() -> RunRecord:
    """A record with every field away from its default, the rare counts included."""
    return RunRecord(
        mission="lap",
        robot="mirto",
        outcome="failure",
        final_state="stuck",
        reason="the mission did not finish within 5 s",
        duration_s=5.0,
        states=((0.0, "go"), (2.5, "stuck")),
        transitions=({"t_s": 2.5, "state": "stuck", "cause": CAUSE},),
        states_dropped=3,
        code_stopped="too slow",
        sim=SimulatedRun(
            seed=4,
            world="corridor",
            final_pose=Pose(10.0, 420.5, -90.0),
            distance_travelled_mm=431.2,
            collisions=2,
            tones=(Tone(1.0, 880.0, 0.2),),
            path=((0.0, 0.0, 0.0, 0.0), (0.1, 0.0, 9.8, 0.0)),
            tones_not_listed=5,
        ),
    )


def test_a_record_read_back_from_its_json_is_the_same_record() -> None:
    record = _every_field_set()
    assert RunRecord.from_json(record.to_json()) == record
    on_a_real_robot = replace(record, sim=None, states_dropped=0)
    assert RunRecord.from_json(on_a_real_robot.to_json()) == on_a_real_robot


def test_a_real_robots_record_has_no_sim_key() -> None:
    # run --json on a port: there is no simulator to tell of, not a null one
    assert "sim" not in replace(_every_field_set(), sim=None).to_dict()


def test_the_json_has_one_key_per_field_in_the_fields_order() -> None:
    data = _every_field_set().to_dict()
    assert list(data) == [item.name for item in fields(RunRecord)]
    assert list(data["sim"]) == [item.name for item in fields(SimulatedRun)]
    assert data["sim"]["final_pose"] == {"x_mm": 10.0, "y_mm": 420.5, "heading_deg": -90.0}
    assert data["sim"]["tones"] == [{"t_s": 1.0, "frequency_hz": 880.0, "duration_s": 0.2}]


def test_counts_of_what_was_left_out_are_written_only_when_something_was() -> None:
    record = _every_field_set()
    assert record.sim is not None
    whole = replace(record, states_dropped=0, sim=replace(record.sim, tones_not_listed=0))
    data = whole.to_dict()
    assert "states_dropped" not in data and "tones_not_listed" not in data["sim"]
    assert RunRecord.from_dict(data) == whole


def test_a_record_missing_a_field_is_refused() -> None:
    data = _every_field_set().to_dict()
    del data["outcome"]
    with pytest.raises(KeyError, match="outcome"):
        RunRecord.from_dict(data)


def test_a_graded_record_is_the_run_record_plus_where_each_collision_was() -> None:
    world = World("corridor")
    graded = GradedRecord(
        **{item.name: getattr(_every_field_set(), item.name) for item in fields(RunRecord)},
        collisions=(Collision(1.2, 250.0, 300.0, "left"), Collision(2.4, -250.0, 310.0, "right")),
        body_radius_mm=90.0,
        world=world,
    )
    data = graded.to_dict()
    assert {k: v for k, v in data.items() if k in _every_field_set().to_dict()} == (
        _every_field_set().to_dict()
    )
    assert "world" not in data  # named by sim.world; the World stays in the process
    back = GradedRecord.from_json(graded.to_json(), world=world)
    assert back == graded and back.world is world
    assert (back.world_name, back.seed, back.final_pose) == ("corridor", 4, (10.0, 420.5, -90.0))


@pytest.mark.parametrize("name", sorted(GOLDEN_RUNS))
def test_the_record_writes_the_run_json_of_before_byte_for_byte(name: str) -> None:
    text = (GOLDEN / name).read_text(encoding="utf-8")
    assert RunRecord.from_json(text).to_json(indent=2) + "\n" == text


@pytest.mark.parametrize("name", sorted(GOLDEN_RUNS))
def test_run_json_prints_what_it_printed_before_for_the_seed(name: str) -> None:
    result = run_cli("run", *GOLDEN_RUNS[name], "--json", cwd=ROOT)
    assert result.stdout == (GOLDEN / name).read_text(encoding="utf-8"), result.stderr


def test_run_the_api_and_grade_tell_the_same_run_for_the_same_mission_and_seed() -> None:
    cli = json.loads(run_cli("run", SQUARE_GOOD, "--seed", "1", "--json", cwd=ROOT).stdout)
    api = roboscript.run(ROOT / SQUARE_GOOD, seed=1, record=False)
    graded = run_cli("grade", SQUARE_SPEC, "--mission", SQUARE_GOOD, "--json", cwd=ROOT)
    first = json.loads(graded.stdout)["runs"][0]
    assert (first["variant"], first["seed"]) == (0, 1), "the spec's first run: seed 1, its start"
    assert api.summary == cli
    record = first["record"]
    # a graded run's causes live in the mission's process: its transitions are not told
    assert record["transitions"] == []
    assert {key: record[key] for key in cli if key != "transitions"} == {
        key: value for key, value in cli.items() if key != "transitions"
    }
    assert record["sim"]["tones"] and record["sim"]["path"]  # the comparison compared a run


ADDED_FIELD = "    lap_count: int = 7  # planted by the test\n"

REPORTS_OF_A_CHANGED_RECORD = """
import json, sys
from pathlib import Path
import roboscript
from roboscript.grading.record import GradedRecord, RunResult
from roboscript.web.bridge import run_text

assert roboscript.__file__.startswith(sys.argv[1]), roboscript.__file__
mission = Path(sys.argv[2])
api = roboscript.run(mission, seed=2, record=False)
page = json.loads(run_text(mission.name, mission.read_text(), seed=2))["summary"]
record = GradedRecord.simulated(
    mission="m", robot="mirto", world_name="empty", seed=1, outcome="success",
    final_state="done", reason=None, duration_s=1.0, states=((0.0, "go"),), path=(),
)
line = RunResult("s", "t", 0, "seed 1", 1, "m.yaml", "passed", record=record).to_dict()
back = RunResult.from_dict(json.loads(json.dumps(line)))
print(json.dumps({
    "api": api.summary, "api field": api.lap_count, "page": page, "grade": line["record"],
    "grade read back": back.record.lap_count,
}))
"""


def test_a_field_added_to_the_record_shows_in_every_output(tmp_path: Path) -> None:
    package = tmp_path / "roboscript"
    shutil.copytree(ROOT / "roboscript", package, ignore=shutil.ignore_patterns("__pycache__"))
    module = package / "run_record.py"
    source = module.read_text(encoding="utf-8")
    last_field = (
        "    sim: SimulatedRun | None = field(default=None, metadata=OMITTED_WHEN_DEFAULT)\n"
    )
    assert source.count(last_field) == 1
    module.write_text(source.replace(last_field, last_field + ADDED_FIELD), encoding="utf-8")
    env = dict(os.environ, PYTHONPATH=str(tmp_path))
    square = str(MISSIONS / "square.yaml")

    def python(*args: str) -> str:
        done = subprocess.run(
            [sys.executable, *args],
            capture_output=True,
            text=True,
            env=env,
            cwd=tmp_path,
            timeout=HANG_BOUND_S,
            check=False,
        )
        assert done.returncode == 0, done.stderr
        return done.stdout

    cli = json.loads(python("-m", "roboscript", "run", square, "--seed", "2", "--json"))
    outputs: dict[str, Any] = json.loads(
        python("-c", REPORTS_OF_A_CHANGED_RECORD, str(package), square)
    )
    assert cli["lap_count"] == 7
    assert outputs["api"]["lap_count"] == outputs["api field"] == 7
    assert outputs["page"]["lap_count"] == 7
    assert outputs["grade"]["lap_count"] == outputs["grade read back"] == 7


def test_a_results_file_of_format_1_still_merges(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    header_text, *lines = (GOLDEN / "results_format1_square_good.jsonl").read_text().splitlines()
    header = json.loads(header_text)
    assert header["roboscript_results"] == 1
    # the spec may change after this file was written: the file says what it is today
    header["specs"][0]["sha256"] = spec_hash(load_test_spec(ROOT / SQUARE_SPEC))
    part = tmp_path / "old.jsonl"
    part.write_text("\n".join([json.dumps(header), *lines]) + "\n", encoding="utf-8")
    monkeypatch.chdir(ROOT)
    report = read_results([str(part)])
    old_records = [json.loads(line)["record"] for line in lines]
    assert len(report.results) == len(old_records) == 3
    for result, old in zip(report.results, old_records, strict=True):
        record = report.in_full(result).record  # the report keeps a summary
        assert record is not None and record.sim is not None
        assert (record.mission, record.outcome, record.duration_s) == (
            old["mission"],
            old["outcome"],
            old["duration_s"],
        )
        assert [list(s) for s in record.states] == old["states"]
        assert (record.sim.world, record.sim.seed) == (old["world_name"], old["seed"])
        assert list(record.sim.final_pose) == old["final_pose"]
        assert [list(p) for p in record.sim.path] == old["path"]
        assert [t._asdict() for t in record.sim.tones] == old["tones"]
        assert record.sim.collisions == len(old["collisions"]) == 0
        assert record.body_radius_mm == old["body_radius_mm"]
        whole = report.in_full(result)
        assert isinstance(whole, RunResult) and whole.to_dict()["record"] == record.to_dict()


def test_a_value_of_the_wrong_shape_is_refused() -> None:
    data = _every_field_set().to_dict()
    data["sim"]["final_pose"] = [10.0, 420.5, -90.0]  # format 1's shape, not run --json's
    with pytest.raises(TypeError, match="expected an object for Pose"):
        RunRecord.from_dict(data)
    data = _every_field_set().to_dict()
    data["sim"]["path"][0] = [0.0, 0.0, 0.0]
    with pytest.raises(ValueError, match="expected 4 values, got 3"):
        RunRecord.from_dict(data)
