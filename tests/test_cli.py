"""The command line as students, teachers and scripts use it."""

from __future__ import annotations

import json
import os
import socket
import subprocess
import sys
import threading
from pathlib import Path

import pytest
from helpers import ROOT, run_cli

from roboscript.profiles import get_profile


def test_square_succeeds_with_four_tones_and_returns_home() -> None:
    result = run_cli("run", "missions/square.yaml", "--json")
    assert result.returncode == 0, result.stderr
    summary = json.loads(result.stdout)
    assert summary["mission"] == "square"
    assert summary["robot"] == "mirto"
    assert summary["outcome"] == "success"
    assert summary["final_state"] == "finished"
    assert summary["reason"] is None
    assert [tone["frequency_hz"] for tone in summary["sim"]["tones"]] == [880.0] * 4
    pose = summary["sim"]["final_pose"]
    assert (pose["x_mm"] ** 2 + pose["y_mm"] ** 2) ** 0.5 < 50.0
    assert summary["sim"]["collisions"] == 0
    assert [name for _, name in summary["states"]].count("side") == 4
    t, x, y, _heading = summary["sim"]["path"][0]
    assert (t, x, y) == (0.0, 0.0, 0.0)


def test_same_seed_prints_identical_json() -> None:
    first = run_cli("run", "missions/square.yaml", "--json", "--seed", "7")
    second = run_cli("run", "missions/square.yaml", "--json", "--seed", "7")
    assert first.returncode == second.returncode == 0
    assert first.stdout == second.stdout


def test_different_seeds_differ_in_noise() -> None:
    first = json.loads(run_cli("run", "missions/square.yaml", "--json", "--seed", "1").stdout)
    second = json.loads(run_cli("run", "missions/square.yaml", "--json", "--seed", "2").stdout)
    assert first["sim"]["path"] != second["sim"]["path"]


def test_human_output_lists_states_and_result() -> None:
    result = run_cli("run", "missions/square.yaml")
    assert result.returncode == 0
    assert result.stdout == ""
    assert "success: square ended in 'finished'" in result.stderr
    assert "corner" in result.stderr
    assert "Traceback" not in result.stderr


def test_misspelt_action_exits_2_with_location_and_suggestion(tmp_path: Path) -> None:
    mission = tmp_path / "typo.yaml"
    mission.write_text(
        "mission: typo\n"
        "states:\n"
        "  go:\n"
        "    do: {drvie: {distance: 50 cm}}\n"
        "    on: {done: end}\n"
        "  end:\n"
        "    final: success\n",
        encoding="utf-8",
    )
    result = run_cli("run", str(mission))
    assert result.returncode == 2
    assert result.stderr.strip() == (
        f"{mission}:4:10: error: unknown action 'drvie' (did you mean 'drive'?)"
    )


def test_check_accepts_the_examples() -> None:
    result = run_cli("check", "missions/")
    assert result.returncode == 0, result.stderr
    assert "0 with errors" in result.stderr


def test_check_reports_every_problem_in_a_file(tmp_path: Path) -> None:
    mission = tmp_path / "two.yaml"
    mission.write_text(
        "states:\n"
        "  a:\n"
        "    do: {drive: {distance: 50 deg}}\n"
        "    on: {done: bb}\n"
        "  b:\n"
        "    final: success\n",
        encoding="utf-8",
    )
    result = run_cli("check", str(mission))
    assert result.returncode == 2
    lines = result.stderr.strip().splitlines()
    assert lines[0].startswith(f"{mission}:3:") and "'deg' is a unit of angle" in lines[0]
    assert lines[1] == f"{mission}:4:16: error: there is no state 'bb' (did you mean 'b'?)"


_accepted: list[socket.socket] = []


def _silent_server() -> tuple[socket.socket, int]:
    """A TCP server that accepts one client and never says anything."""
    server = socket.socket(socket.AF_INET, socket.SOCK_STREAM)
    server.bind(("127.0.0.1", 0))
    server.listen(1)
    accepted = _accepted

    def accept() -> None:
        try:
            conn, _ = server.accept()
            accepted.append(conn)
        except OSError:
            pass

    threading.Thread(target=accept, daemon=True).start()
    return server, server.getsockname()[1]


def test_port_where_nothing_answers_fails_in_a_few_seconds_with_one_sentence() -> None:
    server, port = _silent_server()
    try:
        # it ends by itself (run_cli's bound is for a hang); how long it waited is its own
        # handshake limit, said in the sentence, whatever the machine's load
        result = run_cli("run", "missions/square.yaml", "--port", f"socket://127.0.0.1:{port}")
    finally:
        server.close()
    assert result.returncode == 1
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 1, result.stderr
    assert "did not answer" in lines[0]
    limit_s = get_profile("mirto").handshake_timeout_s
    assert f"did not answer on socket://127.0.0.1:{port} within {limit_s:g} s:" in lines[0]
    assert "Traceback" not in result.stderr


def test_port_that_does_not_exist_is_one_sentence() -> None:
    result = run_cli("run", "missions/square.yaml", "--port", "/dev/does-not-exist-42")
    assert result.returncode == 1
    assert len(result.stderr.strip().splitlines()) == 1
    assert "cannot open /dev/does-not-exist-42" in result.stderr


def test_unknown_robot_is_invalid_input() -> None:
    result = run_cli("run", "missions/square.yaml", "--robot", "mirt")
    assert result.returncode == 2
    assert "did you mean 'mirto'?" in result.stderr


def test_robots_lists_profiles() -> None:
    result = run_cli("robots")
    assert result.returncode == 0
    assert "mirto" in result.stdout and "asip-basic" in result.stdout


def test_robots_says_how_each_robot_moves() -> None:
    rows = {
        line.split()[0]: line for line in run_cli("robots").stdout.splitlines() if line[:1] != " "
    }
    assert "firmware PID" in rows["mirto"]
    assert "host PID" in rows["asip-basic"]
    assert "timed moves" in rows["stackmod-rover"]
    assert "gait motions" in rows["plen2"]


def test_a_time_limit_must_be_positive() -> None:
    result = run_cli("run", "missions/square.yaml", "--max-time", "-5")
    assert result.returncode == 2
    assert "a time limit must be more than 0 s (got -5)" in result.stderr


def test_a_time_limit_may_be_written_with_seconds_as_a_mission_writes_it() -> None:
    result = run_cli("run", "missions/square.yaml", "--max-time", "2s", "--json")
    assert result.returncode == 1  # the square takes longer than 2 s
    assert "did not finish within 2 s" in result.stdout
    result = run_cli("run", "missions/square.yaml", "--max-time", "2 min")
    assert result.returncode == 2
    assert "'2 min' is not a number of seconds (write it in seconds" in result.stderr


@pytest.mark.parametrize(
    ("args", "answer"),
    [
        (
            ("run", "missions/square.yaml", "--seed", "abc"),
            (
                "roboscript run: error: argument --seed: 'abc' is not a whole number"
                " (write it in digits, e.g. --seed 7)"
            ),
        ),
        (
            ("run", "missions/square.yaml", "--view", "--view-port", "web"),
            (
                "roboscript run: error: argument --view-port: 'web' is not a whole number"
                " (write it in digits, e.g. --view-port 8765)"
            ),
        ),
        (
            ("run", "missions/square.yaml", "--view", "--view-port", "99999"),
            (
                "roboscript run: error: argument --view-port: 99999 is out of range: give 0 to"
                " 65535 (e.g. --view-port 8765)"
            ),
        ),
        (
            ("run", "missions/square.yaml", "--view-port", "8765"),
            "error: --view-port is the live view's port: add --view to watch the run",
        ),
        (
            ("grade", "missions/teacher", "--mission", "missions", "--jobs", "two"),
            (
                "roboscript grade: error: argument --jobs: 'two' is not a whole number"
                " (write it in digits, e.g. --jobs 2)"
            ),
        ),
        (
            ("grade", "missions/teacher", "--mission", "missions", "--hang-after", "soon"),
            (
                "roboscript grade: error: argument --hang-after: 'soon' is not a number of seconds"
                " (write it in seconds, e.g. --hang-after 2)"
            ),
        ),
        (
            ("sim", "--pty", "--seed", "1.5"),
            (
                "roboscript sim: error: argument --seed: '1.5' is not a whole number"
                " (write it in digits, e.g. --seed 7)"
            ),
        ),
        (
            ("sim", "--pty", "--handshake-wait", "a while"),
            (
                "roboscript sim: error: argument --handshake-wait: 'a while' is not a number of"
                " seconds (write it in seconds, e.g. --handshake-wait 5)"
            ),
        ),
    ],
)
def test_a_number_option_given_no_number_is_answered_with_an_example(
    args: tuple[str, ...], answer: str
) -> None:
    result = run_cli(*args)
    assert result.returncode == 2
    assert result.stderr.splitlines()[-1] == answer
    assert "invalid" not in result.stderr  # not argparse's "invalid int value: 'abc'"


def test_debug_is_accepted_after_the_command_too(tmp_path: Path) -> None:
    missing = str(tmp_path / "nope.yaml")
    plain = run_cli("run", missing)
    assert plain.returncode == 2
    assert "Traceback" not in plain.stderr
    for args in (("--debug", "run", missing), ("run", missing, "--debug")):
        shown = run_cli(*args)
        assert "Traceback" in shown.stderr, args  # --debug shows where it came from
        assert "cannot read the file" in shown.stderr


PRINTING_MISSION = '''\
"""A mission whose condition prints, as students' debugging code does."""

from roboscript import Mission, Wait, state


class Chatty(Mission):
    """Print while waiting."""

    waiting = state(Wait(duration_s=0.1), initial=True, on_done="done", when=[("chat", "done")])
    done = state(final="success")

    def chat(self) -> bool:
        """Print, and never fire."""
        print("hello from the student")
        return False
'''


def test_with_json_what_the_mission_prints_goes_to_stderr(tmp_path: Path) -> None:
    mission = tmp_path / "chatty.py"
    mission.write_text(PRINTING_MISSION, encoding="utf-8")
    result = run_cli("run", str(mission), "--json")
    assert result.returncode == 0, result.stderr
    assert json.loads(result.stdout)["outcome"] == "success"  # stdout is one JSON document
    assert "hello from the student" in result.stderr


def test_quiet_prints_only_the_result() -> None:
    # a one-pitch buzzer and no encoders: the StackMod driver has notices to give
    loud = run_cli("run", "missions/square.yaml", "--robot", "stackmod-rover")
    assert "no wheel encoders" in loud.stderr
    quiet = run_cli("run", "missions/square.yaml", "--robot", "stackmod-rover", "--quiet")
    assert quiet.returncode == 0
    lines = quiet.stderr.strip().splitlines()
    assert len(lines) == 1, lines
    assert lines[0].startswith("success: square ended in 'finished' after ")


def test_a_closed_pipe_ends_quietly() -> None:
    # `roboscript robots | head -c 1` with the reader already gone
    read_end, write_end = os.pipe()
    os.close(read_end)
    done = subprocess.run(
        [sys.executable, "-m", "roboscript", "run", "missions/square.yaml", "--json"],
        cwd=ROOT,
        stdout=write_end,
        stderr=subprocess.PIPE,
        text=True,
        check=False,
    )
    os.close(write_end)
    assert done.returncode == 141  # 128 + SIGPIPE, as the shell reports for a C tool
    assert done.stderr == ""


def test_a_recording_named_run_json_is_replayed_and_drawn_as_the_interfaces_write_it(
    tmp_path: Path,
) -> None:
    # roboscript run MISSION --record RUN.json; view RUN.json --output FILE.html;
    # graph MISSION --run RUN.json: any name, the format is the recording's
    mission = str(ROOT / "missions" / "square.yaml")
    done = run_cli("run", mission, "--record", "RUN.json", "--quiet", cwd=tmp_path)
    assert done.returncode == 0, done.stderr
    done = run_cli("view", "RUN.json", "--output", "FILE.html", cwd=tmp_path)
    assert (done.returncode, done.stderr) == (0, "replay: FILE.html\n")
    assert "<html" in (tmp_path / "FILE.html").read_text(encoding="utf-8").lower()
    done = run_cli("graph", mission, "--format", "svg", "--run", "RUN.json", cwd=tmp_path)
    assert done.returncode == 0, done.stderr
    assert "<title>square: success in 'finished'</title>" in done.stdout


@pytest.mark.parametrize("fmt", ["mermaid", "svg"])
def test_graph_refuses_a_folder_given_as_its_output_as_invalid_input(
    tmp_path: Path, fmt: str
) -> None:
    mission = str(ROOT / "missions" / "square.yaml")
    done = run_cli("graph", mission, "--format", fmt, "-o", str(tmp_path))
    assert (done.returncode, done.stderr) == (
        2,
        f"error: cannot write {tmp_path}: it is a folder\n",
    )
    under_a_file = tmp_path / "notes.txt"
    under_a_file.write_text("mine", encoding="utf-8")
    done = run_cli("graph", mission, "-o", str(under_a_file / "g.svg"))
    assert (done.returncode, done.stderr) == (
        2,
        f"error: cannot write {under_a_file / 'g.svg'}: {under_a_file} is a file, not a folder\n",
    )


def test_check_of_a_folder_skips_hidden_folders_and_python_environments(tmp_path: Path) -> None:
    broken = "mission: x\ninitial: nowhere\nstates:\n  a: {final: success}\n"
    (tmp_path / "missions").mkdir()
    (tmp_path / "missions" / "mine.yaml").write_text(
        "mission: mine\ninitial: a\nstates:\n  a: {final: success}\n", encoding="utf-8"
    )
    for inside in (".venv/lib/site-packages/pkg", ".git/info", "env/share"):
        (tmp_path / inside).mkdir(parents=True)
        (tmp_path / inside / "examples.yaml").write_text(broken, encoding="utf-8")
    (tmp_path / "env" / "pyvenv.cfg").write_text("home = /usr/bin\n", encoding="utf-8")
    done = run_cli("check", ".", cwd=tmp_path)
    assert (done.returncode, done.stderr) == (0, "checked 1 file: 0 with errors\n")
    # named itself, a hidden folder is checked as any other
    done = run_cli("check", ".git", cwd=tmp_path)
    assert done.returncode == 2
    assert "checked 1 file: 1 with errors" in done.stderr


def test_view_writes_into_a_pipe_named_as_its_page_and_never_replaces_it(tmp_path: Path) -> None:
    recorded = run_cli("run", str(ROOT / "missions" / "square.yaml"), "--record", "run.jsonl",
                       cwd=tmp_path)  # fmt: skip
    assert recorded.returncode == 0, recorded.stderr
    pipe = tmp_path / "page.html"
    os.mkfifo(pipe)
    kept = tmp_path / "kept-pipe"
    os.link(pipe, kept)  # the same pipe by a second name, should the first be taken from it
    read: list[bytes] = []

    def reader() -> None:
        with pipe.open("rb") as stream:  # waits for a writer to open the pipe
            read.append(stream.read())

    thread = threading.Thread(target=reader, daemon=True)
    thread.start()
    done = run_cli("view", "run.jsonl", "-o", "page.html", cwd=tmp_path)
    if thread.is_alive():  # nothing opened the pipe: let the reader go
        os.close(os.open(kept, os.O_WRONLY | os.O_NONBLOCK))
    thread.join()
    assert done.returncode == 0, done.stderr
    assert pipe.is_fifo()  # still the pipe, not a file put in its place
    assert read[0].startswith(b"<!DOCTYPE html>")


def test_check_with_a_robot_that_does_not_exist_says_so_once_and_checks_nothing() -> None:
    done = run_cli("check", str(ROOT / "missions"), "--robot", "mirot")
    assert done.returncode == 2
    assert done.stderr.count("no robot called 'mirot'") == 1, done.stderr
    assert "checked" not in done.stderr  # no file is blamed for the option's mistake
