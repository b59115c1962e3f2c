"""Wrong usage of the command line: each mistake is one sentence naming what was meant."""

from __future__ import annotations

import json
import os
import shutil
import subprocess
from pathlib import Path

import pytest
from helpers import MISSIONS, run_cli


def _last_line(done: subprocess.CompletedProcess[str]) -> str:
    return done.stderr.splitlines()[-1]


@pytest.mark.parametrize(
    ("args", "answer"),
    [
        (("rn", "missions/square.yaml"), ("roboscript: error: 'rn' is not a roboscript command"
         " (did you mean 'run'?)")),
        (("chek", "missions"), ("roboscript: error: 'chek' is not a roboscript command"
         " (did you mean 'check'?)")),
        (("missions/square.yaml",), ("roboscript: error: 'missions/square.yaml' is not a"
         " roboscript command (to run a mission: roboscript run missions/square.yaml)")),
        (("web", "biuld", "app"), ("roboscript web: error: 'biuld' is not a roboscript web"
         " command (did you mean 'build'?)")),
        (("autograder", "moodle", "x.yaml", "-o", "out"), ("roboscript autograder: error:"
         " 'moodle' is not one of gradescope, classroom, prairielearn")),
        (("robot",), ("roboscript: error: 'robot' is not a roboscript command (did you mean"
         " 'robots'?)")),
        (("simulate",), ("roboscript: error: 'simulate' is not a roboscript command (the"
         " commands: run, view, check, grade, gradebook, autograder, graph, sim, ports, robots,"
         " web, examples)")),
        (("graph", "missions/square.yaml", "--format", "svgg"), ("roboscript graph: error:"
         " 'svgg' is not one of mermaid, dot, svg, png (did you mean 'svg'?)")),
    ],
)  # fmt: skip
def test_a_mistyped_command_or_choice_is_answered_with_the_one_meant(
    args: tuple[str, ...], answer: str
) -> None:
    done = run_cli(*args)
    assert (done.returncode, _last_line(done)) == (2, answer)


@pytest.mark.parametrize(
    ("args", "answer"),
    [
        (("run", "missions/square.yaml", "--recrod", "run.jsonl"),
         "roboscript run: error: unknown option --recrod (did you mean '--record'?)"),
        (("run", "--jsn", "missions/square.yaml"),
         "roboscript run: error: unknown option --jsn (did you mean '--json'?)"),
        (("grade", "missions/teacher/square", "--mission", "x.yaml", "--jbos", "2"),
         "roboscript grade: error: unknown option --jbos (did you mean '--jobs'?)"),
        (("check", "missions", "--json"),
         "roboscript check: error: unknown option --json (see roboscript check --help)"),
    ],
)  # fmt: skip
def test_a_mistyped_option_is_answered_by_its_command_with_the_one_meant(
    args: tuple[str, ...], answer: str
) -> None:
    done = run_cli(*args)
    assert (done.returncode, _last_line(done)) == (2, answer)
    command = answer.split(":")[0]
    assert done.stderr.startswith(f"usage: {command} ")  # that command's usage, not the top's


def test_one_argument_too_many_is_named() -> None:
    done = run_cli("run", "missions/square.yaml", "missions/there_and_back.yaml")
    assert done.returncode == 2
    assert _last_line(done) == (
        "roboscript run: error: 'missions/there_and_back.yaml' is one argument too many for"
        ' roboscript run (a path with spaces goes in quotes: "my mission.yaml")'
    )


def test_a_path_with_spaces_typed_without_quotes_is_named_whole(tmp_path: Path) -> None:
    shutil.copy(MISSIONS / "square.yaml", tmp_path / "my mission.yaml")
    done = run_cli("run", "my", "mission.yaml", cwd=tmp_path)
    assert (done.returncode, _last_line(done)) == (
        2,
        (
            "roboscript run: error: one argument too many: 'mission.yaml' (did you mean"
            ' "my mission.yaml"? A path with spaces goes in quotes)'
        ),
    )
    done = run_cli("check", "my", "mission.yaml", cwd=tmp_path)
    assert (done.returncode, done.stderr) == (
        2,
        (
            'my: error: there is no such file or folder (did you mean "my mission.yaml"? A path'
            " with spaces goes in quotes)\nchecked 1 file: 1 with errors\n"
        ),
    )
    assert run_cli("run", "my mission.yaml", cwd=tmp_path).returncode == 0


def test_a_path_with_spaces_and_accents_is_read_and_written(tmp_path: Path) -> None:
    shutil.copy(MISSIONS / "square.yaml", tmp_path / "carré été.yaml")
    done = run_cli(
        "run", "carré été.yaml", "--quiet", "--record", "runs été/mon run.jsonl", cwd=tmp_path
    )
    assert done.returncode == 0, done.stderr
    done = run_cli("view", "runs été/mon run.jsonl", cwd=tmp_path)
    assert (done.returncode, done.stderr) == (0, "replay: runs été/mon run.html\n")


@pytest.mark.skipif(os.sep != "/", reason="a backslash separates folders on Windows")
def test_a_path_written_as_on_windows_is_answered_with_slashes() -> None:
    done = run_cli("run", "missions\\square.yaml")
    assert (done.returncode, done.stderr) == (
        2,
        (
            "missions\\square.yaml: error: cannot read the file: No such file or directory (folders"
            " are separated by '/' here: did you mean 'missions/square.yaml'?)\n"
        ),
    )
    done = run_cli("check", "C:\\Users\\ana\\square.yaml")
    assert done.returncode == 2
    assert "(this is a Windows path: here a path has no drive letter and '/' separates" in (
        done.stderr
    )


def test_a_folder_named_where_a_mission_belongs_names_a_mission_in_it() -> None:
    for command in ("run", "graph"):
        done = run_cli(command, "missions/teacher/square")
        assert (done.returncode, done.stderr) == (
            2,
            (
                "missions/teacher/square: error: this is a folder, not a mission file (name a"
                " mission in it, e.g. missions/teacher/square/bad.yaml)\n"
            ),
        ), command


def test_view_given_a_folder_or_a_runs_summary_says_what_it_is(tmp_path: Path) -> None:
    summary = run_cli("run", "missions/square.yaml", "--json")
    (tmp_path / "run.json").write_text(summary.stdout, encoding="utf-8")
    json.loads(summary.stdout)
    shutil.copy(MISSIONS / "square.yaml", tmp_path)
    record = "a recorded run is the file `roboscript run MISSION --record RUN.jsonl` writes"
    done = run_cli("view", "run.json", cwd=tmp_path)
    assert (done.returncode, done.stderr) == (
        2,
        (
            "run.json: error: this is a run's summary, as `roboscript run --json` prints it, not a"
            f" recorded run ({record})\n"
        ),
    )
    done = run_cli("graph", "square.yaml", "--format", "svg", "--run", "run.json", cwd=tmp_path)
    assert done.returncode == 2
    assert "run.json: error: this is a run's summary" in done.stderr
    done = run_cli("view", ".", cwd=tmp_path)
    assert (done.returncode, done.stderr) == (
        2,
        f".: error: this is a folder, not a recorded run ({record})\n",
    )
    assert not list(tmp_path.glob("*.html"))


def test_gradebook_given_a_folder_asks_for_the_results_files(tmp_path: Path) -> None:
    (tmp_path / "parts").mkdir()
    done = run_cli("gradebook", "parts", cwd=tmp_path)
    assert (done.returncode, done.stderr) == (
        2,
        (
            "error: parts is a folder: give the files `grade --results FILE` wrote"
            " (e.g. parts/part-*.jsonl)\n"
        ),
    )


def test_roboscript_alone_shows_its_commands() -> None:
    done = run_cli()
    assert done.returncode == 2
    assert done.stderr.startswith("usage: roboscript ")
    for command in ("run", "check", "grade", "examples"):
        assert f"\n    {command} " in done.stderr, command


def test_debug_is_accepted_after_a_command_of_a_command(tmp_path: Path) -> None:
    # `roboscript web build DIR --debug`, as after any other command
    done = run_cli("web", "build", "app", "--pyodide", str(tmp_path), "--debug", cwd=tmp_path)
    assert "unrecognized" not in done.stderr and "unknown option" not in done.stderr
    assert "is not an unpacked pyodide package" in done.stderr


def test_a_misspelt_key_of_a_sim_url_is_refused_with_the_one_meant() -> None:
    # `?wrld=maze` ran the mission in the empty world, as if nothing had been asked
    done = run_cli("run", "missions/square.yaml", "--port", "sim://mirto?wrld=maze")
    assert (done.returncode, done.stderr) == (
        1,
        (
            "error: cannot open sim://mirto?wrld=maze: a sim:// URL takes world, seed, x, y,"
            " heading, reset, not 'wrld' (did you mean 'world'?)\n"
        ),
    )


def test_a_spec_written_after_the_missions_is_answered_with_the_order() -> None:
    done = run_cli("grade", "--mission", "missions/teacher/square", "missions/teacher/square")
    assert (done.returncode, _last_line(done)) == (
        2,
        (
            "roboscript grade: error: the following arguments are required: TEST_SPEC (after"
            " --mission, every word is read as a MISSION: write TEST_SPEC before --mission)"
        ),
    )


@pytest.mark.parametrize(
    ("args", "named"),
    [
        (("check", ""), "roboscript check: error: argument PATH"),
        (("check", "missions/square.yaml", ""), "roboscript check: error: argument PATH"),
        (("run", ""), "roboscript run: error: argument MISSION"),
        (("run", "missions/square.yaml", "--robot", ""), "roboscript run: error: argument --robot"),
        (("run", "missions/square.yaml", "--world", ""), "roboscript run: error: argument --world"),
        (("run", "missions/square.yaml", "--port", ""), "roboscript run: error: argument --port"),
        (("examples", ""), "roboscript examples: error: argument DIR"),
        (("web", "build", ""), "roboscript web build: error: argument DIR"),
        (
            ("grade", "missions/teacher/square/test.yaml", "--mission", ""),
            "roboscript grade: error: argument --mission",
        ),
    ],
)
def test_an_empty_argument_is_refused_not_read_as_this_folder_or_as_not_given(
    tmp_path: Path, args: tuple[str, ...], named: str
) -> None:
    shutil.copytree(MISSIONS, tmp_path / "missions")
    before = sorted(tmp_path.rglob("*"))
    done = run_cli(*args, cwd=tmp_path)
    assert (done.returncode, _last_line(done)) == (
        2,
        f'{named} is empty (a variable that is not set, as in "$FILE", gives an empty argument)',
    )
    assert sorted(tmp_path.rglob("*")) == before  # nothing checked, run or written here


def test_view_given_a_mission_or_a_spec_says_what_it_is_and_how_a_run_is_recorded(
    tmp_path: Path,
) -> None:
    shutil.copy(MISSIONS / "square.yaml", tmp_path / "my square.yaml")
    shutil.copy(MISSIONS / "teacher" / "square" / "test.yaml", tmp_path)
    done = run_cli("view", "my square.yaml", cwd=tmp_path)
    assert (done.returncode, done.stderr) == (
        2,
        (
            "my square.yaml: error: this is a mission file, not a recorded run (a recorded run"
            ' is the file `roboscript run "my square.yaml" --record RUN.jsonl` writes)\n'
        ),
    )
    done = run_cli("graph", "my square.yaml", "--format", "svg", "--run", "test.yaml", cwd=tmp_path)
    assert (done.returncode, done.stderr) == (
        2,
        (
            "test.yaml: error: this is a test spec file, not a recorded run (a recorded run is"
            " the file `roboscript run MISSION --record RUN.jsonl` writes)\n"
        ),
    )
    assert not list(tmp_path.glob("*.html")) and not list(tmp_path.glob("*.svg"))


@pytest.mark.parametrize("limit", ["nan", "-1", "0"])
def test_sim_refuses_a_serving_time_that_is_no_time_rather_than_serving_for_ever(
    limit: str,
) -> None:
    done = run_cli("sim", "--tcp", "127.0.0.1:0", "--max-runtime", limit)
    assert (done.returncode, _last_line(done)) == (
        2,
        (
            "roboscript sim: error: argument --max-runtime: a time limit must be more than 0 s"
            f" (got {limit})"
        ),
    )
    assert done.stdout == ""  # it never listened


@pytest.mark.parametrize("limit", ["inf", "infinity", "1e999"])
def test_a_time_limit_that_never_comes_is_refused_rather_than_run_without_end(limit: str) -> None:
    done = run_cli("run", "missions/square.yaml", "--max-time", limit)
    assert (done.returncode, _last_line(done)) == (
        2,
        (
            f"roboscript run: error: argument --max-time: '{limit}' is not a number of seconds"
            " (write it in seconds, e.g. --max-time 60)"
        ),
    )
