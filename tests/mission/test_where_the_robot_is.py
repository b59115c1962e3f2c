"""Conditions that read where the robot is: ``driven``, ``pose``, ``in_region`` (issue 14, item 5).

A mission says "after 50 cm" or "in the goal" instead of guessing a time; headings follow one
convention everywhere (-180 to 180, clockwise positive).
"""

from __future__ import annotations

import math
from pathlib import Path

import pytest

from roboscript.errors import CapabilityError
from roboscript.mission import mission_for_robot
from roboscript.mission.checks import check_capabilities, check_world_regions
from roboscript.mission.guards import GuardError, compile_guard
from roboscript.mission.yaml_loader import parse_yaml_mission
from roboscript.profiles import get_profile
from roboscript.session import run_session, session_record

SIDE = """
mission: side
robot: mirto
states:
  go:
    do: {drive: {speed: 20 cm/s, duration: 10 s}}
    when:
      - {if: driven.state_mm > 50 cm, goto: turn}
    on: {done: lost, failed: lost}
  turn:
    do: {rotate: {angle: -90 deg}}
    on: {done: look, failed: lost}
  look:
    when:
      - {if: pose.y_mm > 45 cm and pose.heading_deg < -80 and driven.total_cm > 49, goto: done}
    timeout: 1 s
    on: {timeout: lost}
  done: {final: success}
  lost: {final: failure}
"""


def _run(text: str, robot: str = "mirto", world: str = "empty") -> dict[str, object]:
    spec, _ = parse_yaml_mission(text)
    session = run_session(spec, get_profile(robot), world=world, max_time_s=30.0)
    return session_record(session).to_dict()


def test_driven_in_a_state_stops_the_drive_after_that_distance() -> None:
    summary = _run(SIDE)
    states = [name for _, name in summary["states"]]  # type: ignore[attr-defined]
    assert states == ["go", "turn", "look", "done"]
    assert summary["outcome"] == "success"


@pytest.mark.parametrize("robot", ["mirto", "spike-prime", "stackmod-rover"])
def test_the_side_is_50_cm_as_the_simulator_measures_it(robot: str) -> None:
    text = SIDE.replace("robot: mirto", f"robot: {robot}").replace("look}", "done}")
    summary = _run(text, robot)
    path = summary["sim"]["path"]  # type: ignore[index]
    turn_starts = next(t for t, name in summary["states"] if name == "turn")  # type: ignore[attr-defined]
    y_at_turn = next(y for t, _, y, _ in path if t >= turn_starts)
    assert 480 <= y_at_turn <= 560


def test_headings_are_minus_180_to_180_in_the_json_and_the_path() -> None:
    summary = _run(SIDE)
    heading = summary["sim"]["final_pose"]["heading_deg"]  # type: ignore[index]
    assert -95 < heading < -85  # a quarter turn left reads -90, never 270
    assert all(-180 <= h <= 180 for *_, h in summary["sim"]["path"])  # type: ignore[index]


def test_the_status_line_shows_the_same_heading() -> None:
    from roboscript.robot import Robot
    from roboscript.status import describe_robot

    with Robot.connect("mirto", start=(0.0, 0.0, 270.0)) as bot:
        assert "heading  -90.0°" in describe_robot(bot)


REGIONS = """
mission: regions
robot: mirto
world: square-room
states:
  go:
    do: {drive: {speed: 20 cm/s, duration: 10 s}}
    when:
      - {if: not in_region.centre and in_region.north-wall, goto: done}
    on: {done: lost, failed: lost}
  done: {final: success}
  lost: {final: failure}
"""


def test_in_region_reads_the_simulated_world() -> None:
    summary = _run(REGIONS, world="square-room")
    assert summary["final_state"] == "done"
    y_mm = summary["sim"]["final_pose"]["y_mm"]  # type: ignore[index]
    assert y_mm >= 800 - 60  # in the north-wall box (y from 800 mm), less the body's radius


def test_a_region_the_world_lacks_is_named_with_a_did_you_mean() -> None:
    spec, _ = parse_yaml_mission(REGIONS.replace("in_region.centre", "in_region.center"), "m.yaml")
    [problem] = check_world_regions(spec, "square-room")
    assert problem.format() == (
        "m.yaml:9:9: error: the world 'square-room' has no region 'center' (its regions: "
        "centre, north-wall) (did you mean 'in_region.centre'?)"
    )
    with pytest.raises(CapabilityError, match="no region 'center'"):
        run_session(spec, get_profile("mirto"), world="square-room", max_time_s=5.0)


def test_in_region_on_a_robot_reached_on_a_port_is_refused() -> None:
    spec, _ = parse_yaml_mission(REGIONS, "m.yaml")
    problems = check_world_regions(spec, None)
    assert len(problems) == 2
    assert "a robot on a port has no world map" in problems[0].message


def test_a_mission_without_in_region_reads_no_world() -> None:
    spec, _ = parse_yaml_mission(SIDE)
    assert check_world_regions(spec, "no-such-world") == []


def test_a_walking_robot_cannot_read_the_distance_driven() -> None:
    spec, _ = parse_yaml_mission(SIDE.replace("robot: mirto", "robot: plen2"), "m.yaml")
    problems = [p.message for p in check_capabilities(spec, get_profile("plen2"))]
    assert any("'driven.state_mm > 50 cm' reads drive_base" in p for p in problems)


@pytest.mark.parametrize(
    ("written", "same_as"),
    [
        ("range.distance < 20 cm", "range.distance_mm < 200"),
        ("driven.state > 1 m", "driven.state_mm > 1000"),
        ("driven.state_mm > 1 m", "driven.state_cm > 100"),
    ],
)
def test_a_name_without_its_unit_takes_the_unit_of_the_number(written: str, same_as: str) -> None:
    class Env:
        def sensor(self, root: str, attr: str | None) -> float:
            mm = {"range": 150.0, "driven": 1200.0}[root]
            return mm / 10 if attr and attr.endswith("_cm") else mm

    env = Env()
    assert compile_guard(written)(env) == compile_guard(same_as)(env)  # type: ignore[arg-type]
    assert compile_guard(written)(env) is True  # type: ignore[arg-type]


def test_a_name_without_its_unit_and_a_bare_number_names_both_spellings() -> None:
    with pytest.raises(GuardError) as caught:
        compile_guard("range.distance < 20")
    assert str(caught.value) == (
        "'range.distance' needs its unit in the name: 'range.distance_cm' or 'range.distance_mm'"
    )
    assert caught.value.offset == 6


PYTHON = """
from roboscript import Drive, Mission, state


class Out(Mission):
    robot = "mirto"
    world = "square-room"
    go = state(Drive(speed_mm_s=200, duration_s=10), initial=True,
               when=[("far", "done")], on_done="lost")
    done = state(final="success")
    lost = state(final="failure")

    def far(self) -> bool:
        return self.driven.state_mm > 300 and self.pose.y_mm > 250 and self.in_region("REGION")
"""


def test_a_python_mission_reads_driven_pose_and_regions(tmp_path: Path) -> None:
    path = tmp_path / "out.py"
    path.write_text(PYTHON.replace("REGION", "north-wall"))
    spec, profile, _ = mission_for_robot(path)
    assert "drive_base" in spec.requires()
    result = run_session(spec, profile, world="square-room", max_time_s=30.0).result
    assert (result.outcome, result.final_state) == ("success", "done")


def test_a_python_mission_asking_for_a_missing_region_fails_naming_the_regions(
    tmp_path: Path,
) -> None:
    path = tmp_path / "out.py"
    path.write_text(PYTHON.replace("REGION", "goal"))
    spec, profile, _ = mission_for_robot(path)
    result = run_session(spec, profile, world="square-room", max_time_s=30.0).result
    assert result.outcome == "failure"
    assert "the world has no region 'goal' (its regions: centre, north-wall)" in (
        result.reason or ""
    )


def test_check_refuses_a_region_the_missions_own_world_lacks(tmp_path: Path) -> None:
    from helpers import run_cli

    path = tmp_path / "m.yaml"
    path.write_text(REGIONS.replace("north-wall", "north_wall"))
    done = run_cli("check", str(path))
    assert done.returncode == 2
    assert "has no region 'north_wall'" in done.stderr
    assert "did you mean 'in_region.north-wall'?" in done.stderr


TWO_LEGS = """
mission: two-legs
states:
  first:
    do: {drive: {distance: 30 cm, speed: 20 cm/s}}
    on: {done: second, failed: lost}
  second:
    do: {drive: {speed: 20 cm/s, duration: 10 s}}
    when:
      - {if: driven.state_mm > 20 cm, goto: total}
    on: {done: lost, failed: lost}
  total:
    when:
      - {if: driven.total_cm > 48 and driven.total_cm < 55, goto: done}
    timeout: 1 s
    on: {timeout: lost}
  done: {final: success}
  lost: {final: failure}
"""


def test_the_distance_in_a_state_starts_again_at_each_state() -> None:
    summary = _run(TWO_LEGS)
    times = {name: t for t, name in summary["states"]}  # type: ignore[attr-defined]
    assert summary["final_state"] == "done"
    # 20 cm at 20 cm/s is about a second: not at once, as the 30 cm driven before would give
    assert 0.8 < times["total"] - times["second"] < 1.5


NESTED = """
mission: nested
states:
  out:
    do: {drive: {distance: 30 cm, speed: 20 cm/s}}
    on: {done: inner, failed: lost}
  inner:
    do:
      initial: wait
      states:
        wait:
          when:
            - {if: pose.y_mm > 28 cm and driven.total_mm > 28 cm, goto: ok}
          timeout: 1 s
          on: {timeout: no}
        ok: {final: success}
        no: {final: failure}
    on: {done: done, failed: lost}
  done: {final: success}
  lost: {final: failure}
"""


def test_inner_states_read_the_whole_missions_pose_and_distance() -> None:
    summary = _run(NESTED)
    assert summary["final_state"] == "done", summary["reason"]


TOWARDS_NORTH_WALL = """
mission: turned
robot: mirto
world: square-room
states:
  go:
    do: {drive: {speed: 20 cm/s, duration: 6 s}}
    when:
      - {if: in_region.north-wall, goto: done}
    on: {done: lost, failed: lost}
  done: {final: success}
  lost: {final: failure}
"""


@pytest.mark.parametrize(
    ("start", "final_state"),
    [
        ((0.0, 0.0, 0.0), "done"),  # facing north: 1.2 m ahead crosses y = 800 mm
        ((0.0, 0.0, 90.0), "lost"),  # facing east: drives along y = 0, never near it
        ((-600.0, 500.0, 45.0), "done"),  # north-east: y grows by cos 45° of the distance
        ((0.0, 700.0, 180.0), "lost"),  # facing south from below the band: away from it
    ],
)
def test_in_region_places_the_odometry_at_the_start_pose(
    start: tuple[float, float, float], final_state: str
) -> None:
    """The robot's odometry (x right, y ahead of the start) is turned by the start heading and
    moved to the start point before it is tested against a region drawn in world coordinates."""
    spec, _ = parse_yaml_mission(TOWARDS_NORTH_WALL, "m.yaml")
    session = run_session(
        spec, get_profile("mirto"), world="square-room", start=start, max_time_s=10.0
    )
    assert session.result.final_state == final_state


GRADED_SPEC = """\
test: regions
world: square-room
robot: mirto
runs:
  - {seed: 1}
  - {seed: 2, start: {x: -600 mm, y: 500 mm, heading: 45 deg}}
max_time: 10 s
expect:
  - final_state: done
"""


def test_a_graded_run_reads_the_same_regions_as_the_run_at_home(tmp_path: Path) -> None:
    """A graded mission runs in a sandbox that cannot see the world; the grader hands it the
    world's regions and start pose, so it leaves the state when the run at home does."""
    from roboscript.grading.run import grade_run, record_from_session
    from roboscript.grading.spec import load_test_spec

    mission = tmp_path / "m.yaml"
    mission.write_text(TOWARDS_NORTH_WALL, encoding="utf-8")
    (tmp_path / "test.yaml").write_text(GRADED_SPEC, encoding="utf-8")
    spec = load_test_spec(tmp_path / "test.yaml")
    for variant in spec.variants:
        graded = grade_run(spec, str(mission), variant)
        assert graded.record is not None, graded.message
        assert graded.record.final_state == "done"
        loaded, _ = parse_yaml_mission(TOWARDS_NORTH_WALL, str(mission))
        home = run_session(
            loaded,
            get_profile("mirto"),
            world=variant.world,
            seed=variant.seed,
            start=variant.start,
            max_time_s=spec.max_time_s,
        )
        assert graded.record.to_dict() == record_from_session(home).to_dict()


def test_a_world_whose_regions_outgrow_a_command_line_is_still_graded(tmp_path: Path) -> None:
    """The grader hands the world map to the sandboxed mission in a file: an argument holds at
    most 128 KiB, and one finely drawn region (here 12,000 points) is more than that."""
    from roboscript.grading.run import grade_run
    from roboscript.grading.spec import load_test_spec

    angles = [i / 12000 * math.tau for i in range(12000)]
    points = ", ".join(f"[{300 * math.cos(a):.3f}, {900 + 50 * math.sin(a):.3f}]" for a in angles)
    world = tmp_path / "fine.yaml"
    world.write_text(
        "world: fine\nwalls:\n  - box: {x: -1 m, y: -1 m, width: 2 m, height: 2 m}\n"
        f"regions:\n  north-wall: {{polygon: [{points}]}}\n",
        encoding="utf-8",
    )
    mission = tmp_path / "m.yaml"
    mission.write_text(TOWARDS_NORTH_WALL.replace("world: square-room", "world: fine.yaml"))
    (tmp_path / "test.yaml").write_text(
        GRADED_SPEC.replace("square-room", "fine.yaml").replace(
            "  - {seed: 2, start: {x: -600 mm, y: 500 mm, heading: 45 deg}}\n", ""
        ),
        encoding="utf-8",
    )
    spec = load_test_spec(tmp_path / "test.yaml")
    graded = grade_run(spec, str(mission), spec.variants[0])
    assert graded.record is not None, graded.message
    assert graded.record.final_state == "done"
