"""Reading teacher test specs: the values teachers write, and their mistakes at file:line:col."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import pytest
from helpers import MISSIONS, checked_by_file, run_cli

from roboscript.errors import InputError, SpecError
from roboscript.grading.expectations import (
    KINDS,
    FinalPose,
    Selection,
    Tones,
    WallDistance,
)
from roboscript.grading.spec import (
    DEFAULT_MAX_TIME_S,
    DEFAULT_WALL_TIME_LIMIT_S,
    GRADER_BACKSTOP_S,
    WALL_TIME_STRETCH,
    is_test_spec,
    load_test_spec,
)

TEACHER = MISSIONS / "teacher"


def _write(tmp_path: Path, text: str, name: str = "spec.yaml") -> Path:
    path = tmp_path / name
    path.write_text(text, encoding="utf-8")
    return path


def test_the_interfaces_example_reads_with_units(tmp_path: Path) -> None:
    path = _write(
        tmp_path,
        "test: square-50cm\n"
        "world: empty\n"
        "robot: mirto\n"
        "runs:\n"
        "  - {seed: 1}\n"
        "  - {seed: 2, start: {x: 100 mm, y: 0 mm, heading: 10 deg}}\n"
        "max_time: 60 s\n"
        "expect:\n"
        "  - outcome: success\n"
        "  - final_pose_within: {x: 0 mm, y: 0 mm, radius: 8 cm}\n"
        "  - tones: {count: 4}\n"
        "  - no_collisions: true\n",
    )
    spec = load_test_spec(path)
    assert spec.name == "square-50cm"
    assert spec.robot == "mirto"
    assert [v.seed for v in spec.variants] == [1, 2]
    assert spec.variants[1].start == (100.0, 0.0, 10.0)
    assert spec.variants[1].label == "seed 2, start (100, 0) mm 10°"
    assert spec.max_time_s == 60.0
    assert spec.wall_time_limit_s == DEFAULT_WALL_TIME_LIMIT_S
    kinds = [e.kind for e in spec.expectations]
    assert kinds == ["outcome", "final_pose_within", "tones", "no_collisions"]
    assert spec.expectations[1].rule == FinalPose(0.0, 0.0, 80.0)
    assert spec.expectations[2].rule == Tones(count=4)
    assert spec.expectations[1].location is not None
    assert (spec.expectations[1].location.line, spec.expectations[1].location.col) == (10, 5)


def test_defaults_one_seeded_run_in_the_empty_world(tmp_path: Path) -> None:
    spec = load_test_spec(_write(tmp_path, "test: t\nexpect:\n  - outcome: success\n"))
    assert [(v.seed, v.world, v.start) for v in spec.variants] == [(1, "empty", None)]
    assert spec.max_time_s == DEFAULT_MAX_TIME_S
    assert spec.robot == "mirto"


def test_weights_settle_and_world_files_next_to_the_spec(tmp_path: Path) -> None:
    _write(tmp_path, "world: hall\nwalls:\n  - segment: [[0, 1 m], [1 m, 1 m]]\n", "hall.yaml")
    spec = load_test_spec(
        _write(
            tmp_path,
            "test: t\n"
            "world: hall.yaml\n"
            "wall_time_limit: 5 s\n"
            "expect:\n"
            "  - {outcome: success, weight: 3}\n"
            "  - wall_distance: {state: follow, min: 15 cm, max: 25 cm, side: left, settle: 2 s}\n",
        )
    )
    assert spec.variants[0].world == str((tmp_path / "hall.yaml").resolve())
    assert spec.wall_time_limit_s == 5.0
    assert spec.expectations[0].weight == 3.0
    assert spec.expectations[1].rule == WallDistance(
        side="left", min_mm=150.0, max_mm=250.0, selection=Selection(state="follow", settle_s=2.0)
    )


def test_a_run_is_given_its_wall_time_limit_plus_the_backstop_and_shows_at_most_a_stretch(
    tmp_path: Path,
) -> None:
    spec = load_test_spec(
        _write(tmp_path, "test: t\nwall_time_limit: 5 s\nexpect:\n  - outcome: success\n")
    )
    assert spec.longest_wall_time_s == 5.0 + GRADER_BACKSTOP_S
    assert spec.longest_wall_time_shown_s == (5.0 + GRADER_BACKSTOP_S) * WALL_TIME_STRETCH
    assert GRADER_BACKSTOP_S > 0 and WALL_TIME_STRETCH >= 1


@pytest.mark.parametrize(
    ("text", "expected"),
    [
        (
            "test: t\nexpect:\n  - outcom: success\n",
            "3:5: error: unknown expectation 'outcom' (did you mean 'outcome'?)",
        ),
        (
            "test: t\nexpect:\n  - outcome: sucess\n",
            (
                "3:14: error: outcome must be success or failure (got 'sucess')"
                " (did you mean 'success'?)"
            ),
        ),
        (
            "test: t\nrun:\n  - {seed: 1}\nexpect:\n  - outcome: success\n",
            "2:1: error: unknown key 'run' in a test spec (did you mean 'runs'?)",
        ),
        (
            "test: t\nmax_time: 60 deg\nexpect:\n  - outcome: success\n",
            "2:11: error: 'deg' is a unit of angle, but this is a time (use s, sec, ms, min)",
        ),
        (
            # past what a system timer takes: it stopped the whole class with an OverflowError
            "test: t\nwall_time_limit: 1e9 s\nexpect:\n  - outcome: success\n",
            "2:18: error: 'wall_time_limit' must be at most 1 hour (3600 s)",
        ),
        (
            "test: t\nmax_time: 61 min\nexpect:\n  - outcome: success\n",
            "2:11: error: 'max_time' must be at most 1 hour (3600 s)",
        ),
        (
            "test: t\nworld: coridor\nexpect:\n  - outcome: success\n",
            "2:8: error: no world called 'coridor' (built-in worlds:",
        ),
        (
            "test: t\nworld: corridor\nexpect:\n  - regions_in_order: [start-zone, far-nd]\n",
            (
                "4:36: error: the world 'corridor' has no region 'far-nd' (its regions: far-end,"
                " start-zone) (did you mean 'far-end'?)"
            ),
        ),
        (
            "test: t\nexpect:\n  - final_pose_within: {x: 0, y: 0, radius: 8 cm, heding: 5}\n",
            "3:51: error: unknown key 'heding' in final_pose_within (did you mean 'heading'?)",
        ),
        (
            "test: t\nexpect:\n  - wall_distance: {state: s, min: 25 cm, max: 15 cm}\n",
            "3:36: error: min must be less than max",
        ),
        (
            "test: t\nexpect:\n  - tones: {count: 4, min_count: 2}\n",
            "3:13: error: give either count or min_count/max_count, not both",
        ),
        (
            "test: t\nrobot: mirtoo\nexpect:\n  - outcome: success\n",
            "2:8: error: no robot called 'mirtoo'",
        ),
        (
            "test: t\nruns:\n  - {seed: -1}\nexpect:\n  - outcome: success\n",
            "3:12: error: 'seed' must be a whole number of at least 0",
        ),
        (
            "test: t\nexpect:\n  - {outcome: success, weight: 0}\n",
            "3:32: error: weight must be a number above 0",
        ),
        ("test: t\nexpect: []\n", "2:9: error: expect lists at least one expectation"),
        ("expect:\n  - outcome: success\n", "1:1: error: a test spec needs 'test'"),
        (
            "test: t\nexpect:\n  - no_collisions: yes\n",
            "3:20: error: write 'no_collisions: true' (got 'yes')",
        ),
    ],
)
def test_mistakes_are_located_with_a_suggestion(tmp_path: Path, text: str, expected: str) -> None:
    path = _write(tmp_path, text)
    with pytest.raises(SpecError) as caught:
        load_test_spec(path)
    assert caught.value.format().startswith(f"{path}:{expected}")


@pytest.mark.parametrize(
    ("runs", "expected"),
    [
        pytest.param(
            "  - {seed: 1}\n  - {seed: 2}\n  - {seed: 1}\n",
            "5:5: error: this run is run 1 again (seed 1, the same world and start): a simulated"
            " run gives the same result every time, so give it another seed or start",
            id="copied",
        ),
        pytest.param(
            # the start the world gives, written out: still the same run (and a hidden copy of
            # a visible run would show students the hidden one's start)
            "  - {seed: 4}\n"
            "  - {seed: 4, start: {x: 0 mm, y: 0 mm, heading: 0 deg}, hidden: true}\n",
            "4:5: error: this run is run 1 again (seed 4, the same world and start)",
            id="copied-start-spelt-out",
        ),
        pytest.param(
            "  - {seed: 1, name: wide}\n  - {seed: 2, name: wide}\n",
            "4:5: error: runs 1 and 2 are both named 'wide': reports could not tell them apart;"
            " give each its own name",
            id="same-name",
        ),
        pytest.param(
            "  - {seed: 3, name: 'seed 1'}\n  - {seed: 1}\n",
            "4:5: error: runs 1 and 2 are both named 'seed 1'",
            id="named-as-another-is-labelled",
        ),
    ],
)
def test_a_run_copied_without_a_change_or_named_as_another_is_refused(
    tmp_path: Path, runs: str, expected: str
) -> None:
    path = _write(tmp_path, f"test: t\nruns:\n{runs}expect:\n  - outcome: success\n")
    with pytest.raises(SpecError) as caught:
        load_test_spec(path)
    assert caught.value.format().startswith(f"{path}:{expected}")


def test_a_check_function_is_found_without_running_it(tmp_path: Path) -> None:
    _write(
        tmp_path,
        "raise SystemExit('never imported by the spec reader')\n"
        "def lap_time(run):\n    return True\n",
        "checks.py",
    )
    spec = load_test_spec(_write(tmp_path, "test: t\nexpect:\n  - check: checks.py:lap_time\n"))
    assert spec.expectations[0].name == "check: lap_time"
    with pytest.raises(SpecError) as caught:
        load_test_spec(_write(tmp_path, "test: t\nexpect:\n  - check: checks.py:lap_tme\n"))
    assert caught.value.format().endswith(
        "3:12: error: checks.py has no function 'lap_tme' (did you mean 'lap_time'?)"
    )


def test_is_test_spec_tells_specs_from_missions() -> None:
    assert is_test_spec(TEACHER / "square" / "test.yaml")
    assert not is_test_spec(TEACHER / "square" / "good.yaml")
    assert not is_test_spec(MISSIONS / "square.py")


@pytest.mark.parametrize("spec", sorted(TEACHER.glob("*/test.yaml")), ids=lambda p: p.parent.name)
def test_the_shipped_teacher_specs_are_valid(spec: Path) -> None:
    loaded = load_test_spec(spec)
    assert len(loaded.variants) >= 2
    # Every run's world was loaded once, with the spec, for the workers and the reports.
    assert {variant.world for variant in loaded.variants} <= set(loaded.worlds)


def test_a_spec_error_is_an_input_error() -> None:
    # The CLI maps InputError to exit 2: a bad spec must be the teacher's input error.
    assert issubclass(SpecError, InputError)


GUIDE = MISSIONS.parent / "docs" / "teachers" / "grading.md"


def test_the_guide_documents_every_expectation() -> None:

    text = GUIDE.read_text(encoding="utf-8")
    for kind in KINDS:
        assert f"| `{kind}" in text, f"docs/teachers/grading.md lacks a row for {kind}"


def test_the_guides_example_spec_is_valid(tmp_path: Path) -> None:
    text = GUIDE.read_text(encoding="utf-8")
    example = text.split("```yaml\n", 1)[1].split("```", 1)[0]
    spec = load_test_spec(_write(tmp_path, example))
    assert spec.name == "square-50cm"
    assert spec.variants[2].label == "turned start"
    assert spec.expectations[2].weight == 2.0


@pytest.mark.parametrize(
    ("expect", "expected"),
    [
        pytest.param(
            "  - outcome: success\n  - outcome: failure\n",
            "5:5: error: this outcome contradicts the outcome on line 4: a mission ends in"
            " success or in failure, not both",
            id="outcomes",
        ),
        pytest.param(
            "  - final_state: home\n  - final_state: [dock, garage]\n",
            "5:5: error: this final_state contradicts the final_state on line 4: a mission ends"
            " in one state, and they name different ones ('home' and 'dock' or 'garage')",
            id="final-states",
        ),
        pytest.param(
            "  - never_enter: far-end\n  - regions_in_order: [start-zone, far-end]\n",
            "5:5: error: this regions_in_order contradicts the never_enter on line 4: the robot"
            " must enter 'far-end' for one and never enter it for the other",
            id="never-enter-and-visit",
        ),
        pytest.param(
            "  - never_enter: start-zone\n",
            "4:5: error: no run can pass this never_enter: run 1 starts inside 'start-zone'"
            " (-100, 0) mm, so the robot is in it before it moves",
            id="never-enter-the-start",
        ),
        pytest.param(
            "  - never_enter: far-end\n"
            "  - final_pose_within: {x: 0 mm, y: 2750 mm, radius: 10 cm}\n",
            "5:5: error: this final_pose_within contradicts the never_enter on line 4: the circle"
            " the robot must end in lies wholly inside 'far-end', which it must never enter",
            id="end-inside-a-forbidden-region",
        ),
        pytest.param(
            "  - final_pose_within: {x: 0 mm, y: 0 mm, radius: 10 cm}\n"
            "  - final_pose_within: {x: 0 mm, y: 50 cm, radius: 10 cm}\n",
            "5:5: error: this final_pose_within contradicts the final_pose_within on line 4: the"
            " robot cannot end in both circles: their centres are 50 cm apart, more than their"
            " radii (10 cm and 10 cm) together",
            id="two-far-circles",
        ),
        pytest.param(
            "  - tones: {count: 4}\n  - tones: {min_count: 5}\n",
            "5:5: error: this tones contradicts the tones on line 4: one wants 4 tones and the"
            " other at least 5",
            id="tone-counts",
        ),
        pytest.param(
            "  - tones: {count: 2, frequency: 440 Hz}\n"
            "  - tones: {frequencies: [440 Hz, 880 Hz]}\n",
            "5:5: error: this tones contradicts the tones on line 4: tone 2 cannot be both"
            " 440 Hz (±5) and 880 Hz (±5)",
            id="tone-frequencies",
        ),
        pytest.param(
            "  - turns: {direction: left}\n  - turns: {direction: right, count: 2}\n",
            "5:5: error: this turns contradicts the turns on line 4: one wants left turns only"
            " and the other right turns only",
            id="turn-directions",
        ),
        pytest.param(
            "  - turns: {count: 0, direction: left}\n",
            "4:5: error: no run can pass this turns: count: 0 means no turn, and direction: left"
            " needs turns",
            id="no-turn-that-turns",
        ),
        pytest.param(
            "  - max_duration: 10 s\n"
            "  - wall_distance: {side: left, min: 10 cm, during: {from: 20 s}}\n",
            "5:5: error: this wall_distance contradicts the max_duration on line 4: the mission"
            " must end within 10 s, but the wall_distance judges only from 21 s on (with its"
            " settle time)",
            id="judged-after-the-end",
        ),
        pytest.param(
            "  - wall_distance: {side: left, min: 10 cm, during: {from: 70 s}}\n",
            "4:5: error: no run can pass this wall_distance: it judges from 71 s on (with its"
            " settle time), but every run ends by the spec's max_time of 60 s",
            id="judged-after-max-time",
        ),
        pytest.param(
            "  - wall_distance: {side: left, max: 10 cm}\n"
            "  - wall_distance: {side: left, min: 20 cm}\n",
            "5:5: error: this wall_distance contradicts the wall_distance on line 4: over the"
            " same stretch the left gap cannot stay both at most 10.0 cm and at least 20.0 cm",
            id="wall-bands",
        ),
        pytest.param(
            "  - wall_ahead_at_end: {distance: 10 cm, tolerance: 2 cm}\n"
            "  - wall_ahead_at_end: {distance: 30 cm, tolerance: 2 cm}\n",
            "5:5: error: this wall_ahead_at_end contradicts the wall_ahead_at_end on line 4: the"
            " wall ahead at the end cannot be both 10 cm ± 20 mm and 30 cm ± 20 mm away",
            id="walls-ahead",
        ),
    ],
)
def test_expectations_no_run_can_meet_together_are_refused_naming_both_lines(
    tmp_path: Path, expect: str, expected: str
) -> None:
    path = _write(tmp_path, f"test: t\nworld: corridor\nexpect:\n{expect}")
    with pytest.raises(SpecError) as caught:
        load_test_spec(path)
    assert caught.value.format().startswith(f"{path}:{expected}"), caught.value.format()


@pytest.mark.parametrize(
    "expect",
    [
        "  - outcome: success\n  - outcome: success\n",
        "  - never_enter: far-end\n  - regions_in_order: [start-zone]\n",
        (
            "  - final_pose_within: {x: 0 mm, y: 0 mm, radius: 10 cm}\n"
            "  - final_pose_within: {x: 0 mm, y: 15 cm, radius: 10 cm}\n"
        ),
        "  - tones: {min_count: 2}\n  - tones: {max_count: 4}\n",
        "  - tones: {frequency: 440 Hz}\n  - tones: {frequencies: [443 Hz, 437 Hz]}\n",
        (
            "  - max_duration: 30 s\n"
            "  - wall_distance: {side: left, min: 10 cm, during: {from: 20 s}}\n"
        ),
        (
            "  - wall_distance: {side: left, max: 10 cm, during: {to: 5 s}}\n"
            "  - wall_distance: {side: left, min: 20 cm, during: {from: 5 s}}\n"
        ),
    ],
)
def test_expectations_a_run_can_meet_together_are_kept(tmp_path: Path, expect: str) -> None:
    path = _write(tmp_path, f"test: t\nworld: corridor\nexpect:\n{expect}")
    assert len(load_test_spec(path).expectations) == 2


@pytest.mark.parametrize(
    ("text", "expected"),
    [
        pytest.param(
            "test: t\nruns:\n  seed: 1\nexpect:\n  - outcome: success\n",
            "3:3: error: runs is a list: put '- ' before each run (here, '- seed: ...' on line 3)",
            id="runs-without-dashes",
        ),
        pytest.param(
            "test: t\nruns: 3\nexpect:\n  - outcome: success\n",
            "2:7: error: runs is a list of runs, one '- ' line each, such as - {seed: 1} (got 3)",
            id="runs-a-number",
        ),
        pytest.param(
            "test: t\nruns: [1, 2]\nexpect:\n  - outcome: success\n",
            "2:8: error: a run is a mapping such as - {seed: 1} (got 1)",
            id="runs-of-bare-seeds",
        ),
        pytest.param(
            "test: t\nruns:\n  -\nexpect:\n  - outcome: success\n",
            "3:4: error: a run is a mapping such as - {seed: 1} (got nothing)",
            id="an-empty-run",
        ),
        pytest.param(
            "test: t\nseeds: [1, 2]\nexpect:\n  - outcome: success\n",
            "2:1: error: unknown key 'seeds' in a test spec (each seed is a run: runs:"
            " [{seed: 1}, {seed: 2}])",
            id="seeds-at-the-top",
        ),
        pytest.param(
            "test: t\nexpect:\n  outcome: success\n  no_collisions: true\n",
            "3:3: error: expect is a list: put '- ' before each expectation (here, '- outcome:"
            " ...' on line 3)",
            id="expect-without-dashes",
        ),
        pytest.param(
            "test: t\nexpect:\n",
            "2:8: error: expect is empty: list each expectation under it, such as - outcome:"
            " success",
            id="expect-nothing",
        ),
        pytest.param(
            "test: t\nexpect: []\n",
            "2:9: error: expect lists at least one expectation, such as - outcome: success: a"
            " test that expects nothing would pass every mission",
            id="expect-an-empty-list",
        ),
        pytest.param(
            "test: t\nexpect:\n  - outcome success\n",
            "3:5: error: an expectation is KIND: VALUE, such as - outcome: success (got"
            " 'outcome success': is the ':' after 'outcome' missing?)",
            id="a-colon-missing",
        ),
        pytest.param(
            "test: t\nruns:\n"
            + "".join(f"  - {{seed: {i}}}\n" for i in range(1, 252))
            + "expect:\n  - outcome: success\n",
            "3:3: error: a test lists at most 200 runs, and this one lists 251: every student's"
            " mission runs once per run (a class of 30 would need 7,530 runs)",
            id="a-huge-number-of-runs",
        ),
        pytest.param(
            "test: t\nmax_time: 10 s\nmax_time: 20 s\nexpect:\n  - outcome: success\n",
            "3:1: error: 'max_time' is given twice (first on line 2)",
            id="a-key-twice",
        ),
        pytest.param(
            "test: t\nruns:\n  - {seed: 1, start: {heading: 5 mm/s}}\nexpect:\n"
            "  - outcome: success\n",
            "3:32: error: 'mm/s' is a unit of speed, but this is an angle",
            id="a-speed-for-an-angle",
        ),
        pytest.param(
            "test: t\nmax_time: 5 secs\nexpect:\n  - outcome: success\n",
            "2:11: error: unknown unit 'secs' for a time (write 5 s)",
            id="a-unit-typo",
        ),
        pytest.param(
            "test: t\nexpect:\n- outcome: success\n  - no_collisions: true\n",
            "4:3: error: this line is indented differently from the lines above it",
            id="wrong-indentation",
        ),
        pytest.param(
            "test: t\nworld: coridor\nexpect:\n  - outcome: success\n",
            "2:8: error: no world called 'coridor' (built-in worlds: corridor, empty,"
            " line-track, maze, square-room; or a world file next to the spec) (did you mean"
            " 'corridor'?)",
            id="a-world-typo",
        ),
    ],
)
def test_a_quick_sloppy_spec_is_told_its_mistake_at_its_line(
    tmp_path: Path, text: str, expected: str
) -> None:
    path = _write(tmp_path, text)
    with pytest.raises(SpecError) as caught:
        load_test_spec(path)
    assert caught.value.format().startswith(f"{path}:{expected}"), caught.value.format()


def test_the_runs_of_a_spec_are_told_apart_without_comparing_every_pair() -> None:
    # Counted, not timed: each run's world is looked up a fixed number of times (comparing
    # every pair of 3,000 runs took most of a minute on a busy machine).
    from roboscript.grading.spec import Variant, _check_runs_differ
    from roboscript.inputs.fields import FieldReader
    from roboscript.sim.world import load_world

    class Counted(dict[str, Any]):
        lookups = 0

        def __getitem__(self, key: str) -> Any:
            Counted.lookups += 1
            return super().__getitem__(key)

    worlds = Counted(empty=load_world("empty"))
    reader = FieldReader("spec.yaml", SpecError)
    counts = []
    for runs in (100, 400):
        Counted.lookups = 0
        variants = [Variant(i, i + 1, "empty") for i in range(runs)]
        _check_runs_differ(reader, variants, set(), worlds, [(i + 3, 3) for i in range(runs)])
        counts.append(Counted.lookups)
    assert counts[1] <= 4.5 * counts[0], counts


def test_a_test_whose_runs_are_all_hidden_loads_as_an_exam_does(tmp_path: Path) -> None:
    path = tmp_path / "exam.yaml"
    path.write_text(
        "test: exam\nruns:\n  - {seed: 1, hidden: true}\n  - {seed: 2, hidden: true}\n"
        "expect:\n  - outcome: success\n",
        encoding="utf-8",
    )
    spec = load_test_spec(path)
    assert [variant.hidden for variant in spec.variants] == [True, True]


# ------------------------------------------------------------- a sweep of quick specs' mistakes
# Specs written the night before, each with one mistake, checked with `roboscript check` as a
# teacher checks them: each is told in one sentence, at the line of the mistake, and no
# traceback. Files beside the specs: a mission, a robot profile and teachers' checks.
_RUNS = "test: t\nworld: empty\nruns:\n  - {seed: 1}\n  - {seed: 2}\n"
_CORRIDOR_RUNS = _RUNS.replace("empty", "corridor")
BESIDE = {
    "square.yaml": (TEACHER / "square" / "good.yaml").read_text(encoding="utf-8"),
    "bigger.yaml": "extends: mirto\nwheel_diameter_mm: 60\n",
    "missing.py": "import no_such_module_for_checks\n\n\ndef ok(run):\n    return True\n",
    "checks.py": (
        "from roboscript.grading.record import RunRecord\n\n\n"
        "def no_argument():\n    return True\n\n\n"
        "def two(run, other):\n    return True\n\n\n"
        "def fine(run: RunRecord, margin_mm: float = 10.0) -> bool:\n    return True\n"
    ),
}
QUICK_SPEC_MISTAKES = {
    "misspelt-kind": (_RUNS + "expect:\n  - outcom: success\n", "7:5", "did you mean 'outcome'"),
    "time-in-cm": (_RUNS + "expect:\n  - max_duration: 20 cm\n", "7:19", "unit of distance"),
    "percent-for-hz": (
        _RUNS + "expect:\n  - tones: {count: 4, tolerance: 5 %}\n",
        "7:34",
        "but this is a frequency",
    ),
    "window-past-max-time": (
        _CORRIDOR_RUNS + "max_time: 20 s\nexpect:\n"
        "  - wall_distance: {side: right, min: 12 cm, during: {from: 25 s, to: 30 s}}\n",
        "8:5",
        "max_time of 20 s",
    ),
    "window-backwards": (
        _CORRIDOR_RUNS + "expect:\n"
        "  - wall_distance: {side: right, min: 12 cm, during: {from: 25 s, to: 5 s}}\n",
        "7:71",
        "'from' must come before 'to'",
    ),
    "negative-points": (_RUNS + "points: -5\nexpect:\n  - outcome: success\n", "6:9", "at least 0"),
    "hidden-copy": (
        (
            "test: t\nruns:\n  - {seed: 1}\n  - {seed: 1, hidden: true}\nexpect:\n"
            "  - outcome: success\n"
        ),
        "4:5",
        "this run is run 1 again",
    ),
    "start-in-wall": (
        (
            "test: t\nworld: corridor\nruns:\n  - {seed: 1, start: {x: 250 mm, y: 0 mm}}\n"
            "expect:\n  - outcome: success\n"
        ),
        "4:22",
        "run 1 starts the robot at (250, 0) mm, 50 mm from a wall of 'corridor'",
    ),
    "default-start-in-wall-of-a-run's-world": (
        (
            "test: t\nworld: corridor\nruns:\n  - {seed: 1}\n"
            "  - {seed: 2, start: {x: -250 mm, heading: 0 deg}}\nexpect:\n  - outcome: success\n"
        ),
        "5:22",
        "it would start inside the wall; move the start at least 50 mm away from it",
    ),
    "turns-beyond-max-time": (
        _RUNS + "max_time: 5 s\nexpect:\n  - {turns: {count: 40}, required: true}\n",
        "8:6",
        "40 turns take at least 7.8 s",
    ),
    "turns-beyond-max-duration": (
        _RUNS + "expect:\n  - max_duration: 2 s\n  - turns: {count: 12}\n",
        "8:5",
        "contradicts the max_duration on line 7: 12 turns take at least 2.2 s",
    ),
    "world-is-a-mission": (
        "test: t\nworld: square.yaml\nexpect:\n  - outcome: success\n",
        "2:8",
        "world names 'square.yaml': this is a mission file, not a simulator world",
    ),
    "world-is-a-robot-profile": (
        "test: t\nworld: bigger.yaml\nexpect:\n  - outcome: success\n",
        "2:8",
        "this is a profile file, not a simulator world",
    ),
    "robot-misspelt": (
        "test: t\nrobot: spike\nexpect:\n  - outcome: success\n",
        "2:8",
        "did you mean 'spike-prime'",
    ),
    "tab": ("test: t\nexpect:\n\t- outcome: success\n", "3:1", "a tab"),
    "key-twice": (
        _RUNS + "expect:\n  - outcome: success\nmax_time: 10 s\nmax_time: 20 s\n",
        "9:1",
        "'max_time' is given twice (first on line 8)",
    ),
    "bom-and-crlf": (
        "\ufefftest: t\r\nexpect:\r\n  - outcome: sucess\r\n",
        "3:14",
        "did you mean 'success'",
    ),
    "required-yes": (
        _RUNS + "expect:\n  - outcome: success\n    required: yes\n",
        "8:15",
        "'required' must be true or false",
    ),
    "kind-value-not-indented": (
        _RUNS + "expect:\n  - tones:\n    count: 4\n",
        "7:5",
        "an expectation has exactly one of",
    ),
    "max-time-in-ms": (
        _RUNS + "max_time: 60000\nexpect:\n  - outcome: success\n",
        "6:11",
        "at most 1 hour",
    ),
    "never-enter-the-start": (
        "test: t\nworld: corridor\nexpect:\n  - never_enter: start-zone\n",
        "4:5",
        "run 1 starts inside 'start-zone'",
    ),
    "check-imports-what-is-missing": (
        _RUNS + "expect:\n  - check: missing.py:ok\n",
        "7:12",
        (
            "missing.py:1: it imports 'no_such_module_for_checks', which is not installed: the"
            " check would fail every run, whatever the robot did"
        ),
    ),
    "check-takes-no-argument": (
        _RUNS + "expect:\n  - check: checks.py:no_argument\n",
        "7:12",
        "checks.py:4: no_argument() must take one argument, the run's record",
    ),
    "check-takes-two-arguments": (
        _RUNS + "expect:\n  - check: checks.py:two\n",
        "7:12",
        "checks.py:8: two() must take one argument",
    ),
    "check-misspelt": (
        _RUNS + "expect:\n  - check: checks.py:fien\n",
        "7:12",
        "did you mean 'fine'",
    ),
    "wall-distance-in-a-world-without-walls": (
        _RUNS + "expect:\n  - wall_distance: {side: right, min: 12 cm, max: 28 cm}\n",
        "7:20",
        "the world 'empty' has no walls, so there is never a wall beside the robot",
    ),
    "heading-tolerance-of-any-way": (
        _RUNS + "expect:\n  - final_pose_within: {x: 0 mm, y: 0 mm, radius: 5 cm, heading: 0 deg,"
        " heading_tolerance: 200 deg}\n",
        "7:92",
        "a heading_tolerance of 200° lets the robot end facing any way",
    ),
    "settle-past-max-time": (
        (
            "test: t\nworld: corridor\nmax_time: 5 s\nexpect:\n"
            "  - wall_distance: {side: right, min: 12 cm, settle: 10 s}\n"
        ),
        "5:5",
        (
            "it judges from 10 s on (with its settle time), but every run ends by the spec's"
            " max_time of 5 s"
        ),
    ),
    "description-a-list": (
        _RUNS + "description: [square, beeps]\nexpect:\n  - outcome: success\n",
        "6:14",
        "description is text",
    ),
    "target-outside-a-closed-room": (
        (
            "test: t\nworld: square-room\nexpect:\n"
            "  - final_pose_within: {x: 5 m, y: 0 mm, radius: 5 cm}\n"
        ),
        "4:5",
        (
            "the circle it must end in lies outside the walls of 'square-room' that shut in run 1's"
            " start, so the robot can never get there"
        ),
    ),
    "waypoint-outside-a-closed-room": (
        (
            "test: t\nworld: square-room\nruns:\n  - {seed: 1}\n"
            "  - {seed: 2, start: {x: 50 cm, heading: 90 deg}}\nexpect:\n"
            "  - path_visits: [{forward: 60 cm}, start]\n"
        ),
        "7:5",
        (
            "the waypoint at (1100, 0) mm lies outside the walls of 'square-room' that shut in run"
            " 2's start"
        ),
    ),
    "start-outside-a-closed-room": (
        (
            "test: t\nworld: square-room\nruns:\n  - {seed: 1}\n"
            "  - {seed: 2, start: {x: 2 m, y: 0 mm}}\nexpect:\n  - outcome: success\n"
        ),
        "5:22",
        (
            "run 2 starts the robot at (2000, 0) mm, outside the walls that shut in the start of"
            " 'square-room'"
        ),
    ),
    "region-misspelt": (
        "test: t\nworld: corridor\nexpect:\n  - regions_in_order: [start-zone, far-edn]\n",
        "4:36",
        "did you mean 'far-end'",
    ),
}


@pytest.fixture(scope="module")
def quick_specs_checked(tmp_path_factory: pytest.TempPathFactory) -> dict[str, list[str]]:
    folder = tmp_path_factory.mktemp("quick")
    for name, text in BESIDE.items():
        (folder / name).write_text(text, encoding="utf-8")
    for name, (text, _, _) in QUICK_SPEC_MISTAKES.items():
        # Written as bytes: the BOM and CRLF spec keeps its own.
        (folder / f"{name}.yaml").write_bytes(text.encode("utf-8"))
    names = [f"{name}.yaml" for name in QUICK_SPEC_MISTAKES]
    printed, last = checked_by_file(folder, names)
    assert last.startswith(f"checked {len(names)} files:"), last
    return printed


@pytest.mark.parametrize("name", sorted(QUICK_SPEC_MISTAKES))
def test_a_quick_spec_mistake_is_one_sentence_at_its_line(
    quick_specs_checked: dict[str, list[str]], name: str
) -> None:
    _, where, sentence = QUICK_SPEC_MISTAKES[name]
    [line] = quick_specs_checked[f"{name}.yaml"]
    assert line.startswith(f"{where}: error: "), line
    assert sentence in line, line


def test_a_check_with_a_default_argument_is_read(tmp_path: Path) -> None:
    for name, text in BESIDE.items():
        _write(tmp_path, text, name)
    spec = load_test_spec(_write(tmp_path, _RUNS + "expect:\n  - check: checks.py:fine\n"))
    assert [e.name for e in spec.expectations] == ["check: fine"]


@pytest.mark.parametrize(
    ("name", "text"),
    [
        ("empty", ""),
        ("only-comments", "# the square test, to finish tomorrow\n"),
        *[
            (name, QUICK_SPEC_MISTAKES[name][0])
            for name in ("start-in-wall", "check-takes-two-arguments")
        ],
    ],
)
def test_grading_a_class_against_a_mistaken_spec_says_so_before_any_run(
    tmp_path: Path, name: str, text: str
) -> None:
    for beside, content in BESIDE.items():
        _write(tmp_path, content, beside)
    spec = _write(tmp_path, text, f"{name}.yaml")
    students = tmp_path / "class"
    students.mkdir()
    for solution in ("good", "bad"):
        (students / f"{solution}.yaml").write_bytes(
            (TEACHER / "square" / f"{solution}.yaml").read_bytes()
        )
    result = run_cli("grade", str(spec), "--mission", str(students))
    assert result.returncode == 2, result.stderr
    assert result.stdout == ""  # no table: no student was graded
    [line] = result.stderr.splitlines()
    where, sentence = (
        QUICK_SPEC_MISTAKES[name][1:]
        if name in QUICK_SPEC_MISTAKES
        else ("1:1", "this test spec is empty")
    )
    assert line.startswith(f"{spec}:{where}: error: "), line
    assert sentence in line, line


def test_runs_written_with_an_anchor_and_merge_keys_override_what_they_merge(
    tmp_path: Path,
) -> None:
    # YAML's own shorthand for "like run 1, but": the run's own keys win over the merged ones.
    spec = load_test_spec(
        _write(
            tmp_path,
            "test: t\nruns:\n  - &first {seed: 1, start: {x: 10 cm, heading: 30 deg}}\n"
            "  - {<<: *first, seed: 2}\n  - <<: *first\n    seed: 3\n    hidden: true\n"
            "expect:\n  - outcome: success\n",
        )
    )
    assert [(v.seed, v.start, v.hidden) for v in spec.variants] == [
        (1, (100.0, 0.0, 30.0), False),
        (2, (100.0, 0.0, 30.0), False),
        (3, (100.0, 0.0, 30.0), True),
    ]


def test_a_key_given_twice_beside_a_merge_key_is_still_told(tmp_path: Path) -> None:
    path = _write(
        tmp_path,
        "test: t\nruns:\n  - &first {seed: 1}\n  - {<<: *first, seed: 2, seed: 3}\n"
        "expect:\n  - outcome: success\n",
    )
    with pytest.raises(SpecError, match=r"'seed' is given twice \(first on line 4\)") as caught:
        load_test_spec(path)
    assert (caught.value.line, caught.value.col) == (4, 27)


def test_targets_inside_a_closed_room_or_beyond_an_open_end_are_read(tmp_path: Path) -> None:
    room = _write(
        tmp_path,
        "test: t\nworld: square-room\nexpect:\n"
        "  - final_pose_within: {x: 0 mm, y: 1.1 m, radius: 20 cm}\n"  # reaches into the room
        "  - regions_in_order: [centre, north-wall]\n"
        "  - path_visits: [{forward: 90 cm}]\n",
    )
    assert len(load_test_spec(room).expectations) == 3
    # The corridor is open at its far end: a robot can drive out of it.
    corridor = _write(
        tmp_path,
        "test: t\nworld: corridor\nexpect:\n"
        "  - final_pose_within: {x: 0 mm, y: 5 m, radius: 5 cm}\n",
        "open.yaml",
    )
    assert len(load_test_spec(corridor).expectations) == 1


BARE_BAND = (
    "test: t\nworld: corridor\nexpect:\n"
    "  - wall_distance: {side: right, min: 12, max: 28}\n"  # 12 to 28 mm: the wall, scraped
    "  - final_pose_within: {x: 0, y: 2.7 m, radius: 30 cm}\n"  # 0 is 0 in any unit
)


def test_a_bare_distance_likely_meant_in_cm_is_a_warning_at_its_line(tmp_path: Path) -> None:
    _write(tmp_path, BARE_BAND)
    printed, last = checked_by_file(tmp_path, ["spec.yaml"])
    assert printed["spec.yaml"] == [
        "4:39: warning: min: 12 taken as 12 mm; write `12 mm` (or did you mean 12 cm?)",
        "4:48: warning: max: 28 taken as 28 mm; write `28 mm` (or did you mean 28 cm?)",
    ]
    assert last == "checked 1 file: 0 with errors"
    strict = run_cli("check", "--strict", "spec.yaml", cwd=tmp_path)
    assert strict.returncode == 2
    assert "spec.yaml:4:39: error: min: 12 taken as 12 mm" in strict.stderr


def test_grading_tells_a_specs_warnings_before_its_table(tmp_path: Path) -> None:
    spec = _write(tmp_path, BARE_BAND)
    mission = tmp_path / "good.yaml"
    mission.write_bytes((TEACHER / "corridor" / "good.yaml").read_bytes())
    result = run_cli("grade", str(spec), "--mission", str(mission))
    assert "Traceback" not in result.stderr, result.stderr
    assert result.stderr.splitlines()[0] == (
        f"{spec}:4:39: warning: min: 12 taken as 12 mm; write `12 mm` (or did you mean 12 cm?)"
    )


def test_a_max_duration_not_under_max_time_is_a_warning_at_its_line(tmp_path: Path) -> None:
    # Every run that ends by itself meets it: a free share of every student's score.
    _write(
        tmp_path, _RUNS + "max_time: 20 s\nexpect:\n  - outcome: success\n  - max_duration: 40 s\n"
    )
    printed, last = checked_by_file(tmp_path, ["spec.yaml"])
    assert printed["spec.yaml"] == [
        (
            "9:5: warning: max_duration of 40 s is not under the spec's max_time of 20 s: every run"
            " that ends by itself meets it (give it less than max_time, or leave it out)"
        )
    ]
    assert last == "checked 1 file: 0 with errors"


def test_a_region_across_a_closed_room_with_every_corner_outside_is_reachable(
    tmp_path: Path,
) -> None:
    # a band drawn wider than the room: no corner inside, yet the robot crosses it
    (tmp_path / "banded.yaml").write_text(
        "world: banded\nstart: {x: 0 mm, y: 0 mm, heading: 0 deg}\nwalls:\n"
        "  - box: {x: -1 m, y: -1 m, width: 2 m, height: 2 m}\nregions:\n"
        "  band: {box: {x: -2 m, y: 30 cm, width: 4 m, height: 20 cm}}\n",
        encoding="utf-8",
    )
    spec = tmp_path / "test.yaml"
    spec.write_text(
        "test: t\nworld: banded.yaml\nexpect:\n  - regions_in_order: [band]\n", encoding="utf-8"
    )
    assert load_test_spec(spec).name == "t"
