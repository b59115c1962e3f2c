"""``check``, ``run`` and ``grade`` tell missions, worlds, profiles and test specs apart."""

from __future__ import annotations

import shutil
from pathlib import Path

from helpers import ROOT, run_cli

from roboscript.cli import _parser

WORLD = ROOT / "roboscript" / "sim" / "worlds" / "square-room.yaml"
SPEC = ROOT / "missions" / "teacher" / "square" / "test.yaml"


def test_check_reads_a_world_as_a_world(tmp_path: Path) -> None:
    done = run_cli("check", str(WORLD))
    assert (done.returncode, done.stderr) == (0, "checked 1 file: 0 with errors\n")
    broken = tmp_path / "w.yaml"
    broken.write_text("world: w\nstart: {x: 0 mm, y: 0 mm, heading: 0 deg}\nwals: []\n")
    done = run_cli("check", str(broken))
    assert done.returncode == 2
    assert f"{broken}:3:1: error: unknown key 'wals' in world (did you mean 'walls'?)" in (
        done.stderr
    )


def test_check_reads_a_profile_as_a_profile(tmp_path: Path) -> None:
    profile = tmp_path / "fast.yaml"
    profile.write_text("extends: mirto\nname: fast\nmax_speed_mm_s: 300\n")
    assert run_cli("check", str(profile)).returncode == 0
    profile.write_text("extends: mirto\nmax_speed_mm_s: -3\n")
    done = run_cli("check", str(profile))
    assert done.returncode == 2 and "'max_speed_mm_s' must be a positive number" in done.stderr


def test_run_says_a_world_is_a_world_and_how_to_use_it() -> None:
    done = run_cli("run", str(WORLD))
    assert done.returncode == 2
    assert done.stderr == (
        f"{WORLD}:1:1: error: this is a world file, not a mission (it is a simulator world: "
        f"run a mission in it with 'roboscript run MISSION --world {WORLD}')\n"
    )


def test_run_says_a_test_spec_is_a_test_spec_with_a_grade_command_that_works() -> None:
    done = run_cli("run", str(SPEC))
    assert done.returncode == 2
    assert "this is a test spec file, not a mission" in done.stderr
    said = done.stderr.split("'roboscript ", 1)[1].split("'", 1)[0]
    assert said == f"grade {SPEC} --mission MISSIONS"
    # the command as said, with the missions named, is one the command line takes
    typed = [*said.replace("MISSIONS", str(ROOT / "missions" / "square.yaml")).split()]
    assert _parser().parse_args(typed).missions == [str(ROOT / "missions" / "square.yaml")]


def test_grade_never_lists_a_world_or_a_profile_as_a_student(tmp_path: Path) -> None:
    subs = tmp_path / "subs"
    subs.mkdir()
    shutil.copy(ROOT / "missions" / "square.yaml", subs / "ana.yaml")
    shutil.copy(WORLD, subs / "room.yaml")
    (subs / "fast.yaml").write_text("extends: mirto\nname: fast\nmax_speed_mm_s: 300\n")
    from roboscript.grading.batch import find_submissions

    assert [s.student for s in find_submissions([str(subs)]).submissions] == ["ana"]
    done = run_cli("grade", str(SPEC), "--mission", str(subs / "room.yaml"))
    assert done.returncode == 2
    assert "this is a world file, not a mission" in done.stderr


def test_grade_says_a_world_given_as_the_test_spec_is_a_world() -> None:
    done = run_cli("grade", str(WORLD), "--mission", str(ROOT / "missions" / "square.yaml"))
    assert done.returncode == 2
    assert f"{WORLD}:1:1: error: this is a world file, not a test spec" in done.stderr


def test_run_says_a_mission_or_a_spec_given_as_the_robot_or_the_world_is_what_it_is() -> None:
    mission = ROOT / "missions" / "square.yaml"
    done = run_cli("run", str(mission), "--robot", str(mission))
    assert (done.returncode, done.stderr) == (
        2,
        (
            f"{mission}:1:1: error: this is a mission file, not a robot profile (it is a mission:"
            f" run it with 'roboscript run {mission}')\n"
        ),
    )
    done = run_cli("run", str(mission), "--world", str(SPEC))
    assert (done.returncode, done.stderr) == (
        2,
        (
            f"{SPEC}:1:1: error: this is a test spec file, not a simulator world (it is a"
            f" teacher's test spec: grade missions with 'roboscript grade {SPEC} --mission"
            " MISSIONS')\n"
        ),
    )
    done = run_cli("sim", "--robot", str(WORLD), "--tcp", "127.0.0.1:0")
    assert (done.returncode, done.stderr) == (
        2,
        (
            f"{WORLD}:1:1: error: this is a world file, not a robot profile (it is a simulator"
            f" world: run a mission in it with 'roboscript run MISSION --world {WORLD}')\n"
        ),
    )


def test_a_profile_or_world_whose_keys_tell_nothing_is_judged_by_its_own_reader(
    tmp_path: Path,
) -> None:
    nameless = tmp_path / "fast.yaml"
    nameless.write_text("name: fast\n", encoding="utf-8")
    done = run_cli("run", str(ROOT / "missions" / "square.yaml"), "--robot", str(nameless))
    assert done.returncode == 2
    assert f"{nameless}:1:1: error: 'extends' must name a built-in robot" in done.stderr


def test_grade_says_a_mission_given_as_the_test_spec_is_a_mission() -> None:
    mission = ROOT / "missions" / "square.yaml"
    done = run_cli("grade", str(mission), "--mission", str(mission))
    assert (done.returncode, done.stderr) == (
        2,
        (
            f"{mission}:1:1: error: this is a mission file, not a test spec (it is a mission:"
            f" run it with 'roboscript run {mission}')\n"
        ),
    )


def test_gradebook_says_a_spec_or_a_mission_is_no_results_file() -> None:
    for given in (SPEC, ROOT / "missions" / "square.py"):
        done = run_cli("gradebook", str(given))
        assert (done.returncode, done.stderr) == (
            2,
            (
                f"error: {given} is not a results file of this roboscript (written by"
                " `roboscript grade --results FILE`)\n"
            ),
        ), given
