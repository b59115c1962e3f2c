"""Missions run from Python: ``roboscript.run(...)`` and ``python my_mission.py``."""

from __future__ import annotations

import json
import os
import re
import signal
import subprocess
import sys
import threading
from html.parser import HTMLParser
from pathlib import Path
from typing import Any

import pytest
from helpers import (
    HANG_BOUND_S,
    MISSIONS,
    ROOT,
    RUN_FROM_PYTHON,
    SLEEPER,
    replayed_power,
    run_cli,
    signalled_once,
)

import roboscript
from roboscript import Drive, Mission, api, state
from roboscript.errors import InputError
from roboscript.interrupts import Interrupted
from roboscript.mission import load_mission
from roboscript.mission.student_code import import_student_file
from roboscript.replay.recording import load_recording

HOP = '''
from roboscript import Drive, Mission, state


class Hop(Mission):
    """Drive 10 cm."""

    go = state(Drive(distance_mm=100), initial=True, on_done="ok", on_failed="bad")
    ok = state(final="success")
    bad = state(final="failure")
'''


class Forever(Mission):
    """Drives until the time limit or a signal ends it."""

    go = state(Drive(duration_s=60), initial=True, on_done="done")
    done = state(final="success")


class ShortHop(Mission):
    """Drives 10 cm."""

    go = state(Drive(distance_mm=100), initial=True, on_done="done", on_failed="done")
    done = state(final="success")


class PressesCtrlC(Mission):
    """Ctrl-C arrives half a second into the drive, as if typed."""

    go = state(Drive(duration_s=60), initial=True, when=[("interrupted", "done")])
    done = state(final="success")

    def interrupted(self) -> bool:
        if self.elapsed > 0.5:
            raise KeyboardInterrupt
        return False


def _python(*args: str, cwd: Path) -> subprocess.CompletedProcess[str]:
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    return subprocess.run(
        [sys.executable, *args],
        capture_output=True,
        text=True,
        cwd=cwd,
        env=env,
        timeout=HANG_BOUND_S,
        check=False,
    )


@pytest.fixture
def sessions(monkeypatch: pytest.MonkeyPatch) -> list[Any]:
    """Every session roboscript.run runs, to look at its robot afterwards."""
    seen: list[Any] = []
    real = api.run_session

    def spy(*args: Any, **kwargs: Any) -> Any:
        seen.append(real(*args, **kwargs))
        return seen[-1]

    monkeypatch.setattr(api, "run_session", spy)
    return seen


# --------------------------------------------------------------------------- roboscript.run


def test_run_returns_what_roboscript_run_json_prints() -> None:
    result = roboscript.run(MISSIONS / "square.yaml", seed=7)
    cli = json.loads(run_cli("run", "missions/square.yaml", "--json", "--seed", "7").stdout)
    assert result.summary == cli
    assert (result.outcome, result.final_state, result.reason) == ("success", "finished", None)
    assert result.succeeded
    assert result.duration_s == cli["duration_s"]
    assert [list(entry) for entry in result.states] == cli["states"]
    assert result.states_visited == ["side", "corner", "beep", "finished"]
    pose = cli["sim"]["final_pose"]
    assert result.final_pose == (pose["x_mm"], pose["y_mm"], pose["heading_deg"])
    assert [list(sample) for sample in result.path] == cli["sim"]["path"]
    assert [t[1] for t in result.tones] == [880.0] * 4
    assert (result.world, result.seed, result.robot) == ("empty", 7, "mirto")
    assert str(result) == "square on mirto: success in 'finished' after 23.66 s"
    assert repr(result) == f"<RunResult {result}>"


def test_run_takes_a_class_a_spec_or_a_path_and_they_agree() -> None:
    square = import_student_file(MISSIONS / "square.py").Square
    by_class = roboscript.run(square)
    by_spec = roboscript.run(load_mission(MISSIONS / "square.yaml")[0])
    by_path = roboscript.run(str(MISSIONS / "square.py"))
    assert by_class.states == by_spec.states == by_path.states
    assert by_class.final_pose == by_spec.final_pose == by_path.final_pose


def test_robot_world_and_seed_are_those_asked_for() -> None:
    one = roboscript.run(MISSIONS / "square.yaml", seed=1)
    two = roboscript.run(MISSIONS / "square.yaml", seed=2)
    assert one.path != two.path  # the seed is the simulator's
    other = roboscript.run(MISSIONS / "square.yaml", robot="asip-basic", world="square-room")
    assert (other.robot, other.world) == ("asip-basic", "square-room")
    assert other.recording is not None
    assert other.recording.header["robot"]["name"] == "asip-basic"


def test_robot_world_and_seed_may_be_given_in_order_as_the_signature_shows_them() -> None:
    # run(mission, robot=None, world=None, seed=1, ...): a student who writes them in that
    # order, unnamed, gets the run they asked for
    square = MISSIONS / "square.yaml"
    by_position = roboscript.run(square, "asip-basic", "square-room", 2, record=False)
    by_name = roboscript.run(square, robot="asip-basic", world="square-room", seed=2, record=False)
    assert (by_position.robot, by_position.world, by_position.seed) == (
        "asip-basic",
        "square-room",
        2,
    )
    assert by_position.path == by_name.path


def test_the_recording_holds_every_tick_and_can_be_saved(tmp_path: Path) -> None:
    result = roboscript.run(MISSIONS / "square.yaml", max_time_s=6.0)
    assert result.outcome == "failure"
    assert result.reason == "the mission did not finish within 6 s"
    recording = result.recording
    assert recording is not None
    assert recording.frames[-1]["t"] == pytest.approx(6.0, abs=0.05)
    assert [f["state"] for f in recording.frames][:1] == ["side"]
    assert "corner" in {f["state"] for f in recording.frames}
    saved = load_recording(result.save(tmp_path / "run.jsonl"))
    assert saved.frames == recording.frames
    assert saved.result == recording.result
    assert roboscript.run(MISSIONS / "square.yaml", record=False).recording is None


def test_code_that_blocks_a_tick_is_warned_about_once_and_ended_as_run_and_grade_do(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    mission = tmp_path / "sleepy.py"
    mission.write_text(SLEEPER, encoding="utf-8")
    result = roboscript.run(mission)
    said = [line for line in capsys.readouterr().err.splitlines() if line.startswith("warning:")]
    # once, on standard error when it happened, naming the line and the time it took
    assert len(said) == 1
    assert re.match(
        rf"warning: the mission's code at {re.escape(str(mission))}:22 in tired took 0\.\d\d s in"
        r" one tick \(a tick is 0\.02 s;",
        said[0],
    ), said[0]
    # check's warning about the sleep, at load and at its line, then the run's, once
    assert result.warnings[0].startswith(f"{mission}:22:9: warning: time.sleep(0.05) in tired()")
    assert result.warnings[1:] == tuple(said)
    # ended early as too slow, at its line, as `roboscript run` ends it and `grade` judges it
    assert (result.outcome, result.code_stopped) == ("error", "too slow")
    assert result.reason is not None
    assert result.reason.startswith(f"the mission was too slow: its code at {mission}:22 in tired")
    assert result.duration_s < 5  # about a second of slow ticks, not the 13 s drive
    cli = run_cli("run", str(mission), "--json")
    summary = json.loads(cli.stdout)
    assert (summary["outcome"], summary["code_stopped"]) == ("error", "too slow")
    assert summary["reason"].split(" took ")[0] == result.reason.split(" took ")[0]
    assert [line for line in cli.stderr.splitlines() if line.startswith("warning:")] != []


def test_honest_code_is_never_stopped_nor_warned_about_at_a_line() -> None:
    result = roboscript.run(MISSIONS / "square.py")
    assert (result.outcome, result.code_stopped) == ("success", "")
    assert "code_stopped" not in result.summary
    # Own time leaves out waiting for a CPU, so a busy machine gives honest code no warning;
    # a lone slow tick that is not the code's (a page fault, say) is warned about without a
    # line, and the student's own code is never named.
    assert not any(" at " in warning.split(" took ")[0] for warning in result.warnings)


def test_the_robot_is_stopped_before_run_returns(sessions: list[Any]) -> None:
    result = roboscript.run(Forever, max_time_s=1.0)
    assert result.outcome == "failure"
    body = sessions[-1].simulation.body
    assert result.recording is not None
    assert max(abs(v) for v in result.recording.frames[-1]["motors"].values()) > 50
    assert body.power == [0.0, 0.0]  # it was driving; it was told to stop


def test_ctrl_c_stops_the_robot_then_raises(sessions: list[Any]) -> None:
    with pytest.raises(KeyboardInterrupt) as caught:
        roboscript.run(PressesCtrlC)
    assert getattr(caught.value, "exit_status", None) == 130
    assert sessions[-1].result.reason == "interrupted by Ctrl-C"
    assert sessions[-1].simulation.body.power == [0.0, 0.0]


# Drives for ten minutes, and says so once the wheels have turned.
DRIVES_AND_SAYS_SO = """\
from roboscript import Drive, Mission, state

SAID = []


class Far(Mission):
    go = state(Drive(duration_s=600), initial=True, when=[("moving", "end")], on_done="end")
    end = state(final="success")

    def moving(self):
        if not SAID and self.driven.total_cm > 1:
            SAID.append(True)
            print("moving")
        return False
"""


@pytest.mark.parametrize("name", ["SIGINT", "SIGTERM"])
def test_a_signal_during_run_in_a_script_stops_the_robot_and_raises_the_commands_sentence(
    tmp_path: Path, name: str
) -> None:
    signum = getattr(signal, name)
    (tmp_path / "far.py").write_text(DRIVES_AND_SAYS_SO, encoding="utf-8")
    log = tmp_path / "wire.log"

    def moving(proc: subprocess.Popen[str]) -> None:
        assert proc.stdout is not None
        for line in proc.stdout:  # the mission's prints, stamped, as it prints them
            if line.endswith("> moving\n"):
                return  # the wheels turn
        raise AssertionError("the script ended before its robot moved")

    status, stderr = signalled_once(
        [sys.executable, "-u", "-c", RUN_FROM_PYTHON, "far.py", str(log)],
        signum,
        moving,
        cwd=tmp_path,
    )
    assert status == 128 + signum, stderr
    assert stderr.splitlines()[-2:] == [
        f"Interrupted: {Interrupted(signum).reason}",  # as roboscript run's last line says it
        "handlers given back: True",
    ]
    most, end = replayed_power("mirto", log)
    assert most > 0.1, "the robot never drove: the test proves nothing"
    assert end == [0.0, 0.0], f"left driving at {end} after {name}"


def test_run_gives_the_program_its_own_signal_handlers_back() -> None:
    def own(signum: int, frame: object) -> None:
        pass

    previous = signal.signal(signal.SIGTERM, own)
    try:
        roboscript.run(ShortHop, max_time_s=5.0)
        assert signal.getsignal(signal.SIGTERM) is own
        assert signal.getsignal(signal.SIGINT) is signal.default_int_handler
    finally:
        signal.signal(signal.SIGTERM, previous)


def test_run_in_another_thread_runs_with_the_programs_handlers() -> None:
    # Python lets only the main thread set signal handlers: a run in a thread must not try
    results: list[Any] = []
    errors: list[BaseException] = []

    def run() -> None:
        try:
            results.append(roboscript.run(ShortHop, max_time_s=5.0))
        except BaseException as exc:  # noqa: BLE001 - reported by the test
            errors.append(exc)

    worker = threading.Thread(target=run)
    worker.start()
    worker.join(timeout=HANG_BOUND_S)
    assert errors == []
    assert [result.outcome for result in results] == ["success"]


def test_a_bad_mission_raises_with_its_location(tmp_path: Path) -> None:
    bad = tmp_path / "bad.yaml"
    bad.write_text("mission: bad\ninitial: go\nstates:\n  go:\n    do: {drvie: {}}\n")
    with pytest.raises(InputError) as caught:
        roboscript.run(bad)
    assert str(caught.value).startswith(f"{bad}:5:")
    assert "did you mean 'drive'" in str(caught.value)
    with pytest.raises(TypeError, match="a mission file's path, a Mission class"):
        roboscript.run(42)  # type: ignore[arg-type]
    with pytest.raises(ValueError, match="max_time_s"):
        roboscript.run(MISSIONS / "square.yaml", max_time_s=0)

    class Seed:  # a whole number of another type, as numpy's int64
        def __index__(self) -> int:
            return 2

    assert roboscript.run(MISSIONS / "square.yaml", seed=Seed()).seed == 2  # type: ignore[arg-type]
    for seed in (3.5, "3", True, None):
        with pytest.raises(TypeError, match=r"^seed must be a whole number, like seed=3"):
            roboscript.run(MISSIONS / "square.yaml", seed=seed)  # type: ignore[arg-type]


def test_a_class_typed_into_a_notebook_runs() -> None:
    namespace: dict[str, Any] = {"__name__": "__main__"}  # a notebook cell: no file
    exec(compile(HOP, "<cell>", "exec"), namespace)  # noqa: S102 - the test's own code
    result = roboscript.run(namespace["Hop"])
    assert (result.mission, result.outcome, result.final_state) == ("hop", "success", "ok")
    with pytest.raises(SystemExit) as exited:
        namespace["Hop"].main([])
    assert exited.value.code == 2


# ---------------------------------------------------------------------------- the notebook


class _Frames(HTMLParser):
    def __init__(self) -> None:
        super().__init__()
        self.frames: list[dict[str, str | None]] = []

    def handle_starttag(self, tag: str, attrs: list[tuple[str, str | None]]) -> None:
        if tag == "iframe":
            self.frames.append(dict(attrs))


def test_in_a_notebook_the_result_shows_the_replay_viewer() -> None:
    result = roboscript.run(MISSIONS / "square.yaml")
    parser = _Frames()
    parser.feed(result._repr_html_())
    [frame] = parser.frames
    assert frame["sandbox"] == "allow-scripts"
    page = frame["srcdoc"] or ""
    assert page.startswith("<!DOCTYPE html>")
    assert 'class="rs-viewer"' in page and "<script>" in page
    data = page.split('class="rs-data">', 1)[1].split("</script>", 1)[0]
    embedded = json.loads(data)
    assert embedded["header"]["mission"]["name"] == "square"
    assert embedded["result"]["final_state"] == "finished"
    # a notebook keeps 25 frames a second, every state change included
    assert result.recording is not None
    assert len(embedded["frames"]) < len(result.recording.frames) / 1.5
    shown = {frame["state"] for frame in embedded["frames"] if "state" in frame}
    assert shown == set(result.states_visited)
    unrecorded = roboscript.run(MISSIONS / "square.yaml", record=False)._repr_html_()
    assert "rs-viewer" not in unrecorded and "success" in unrecorded


def test_importing_roboscript_does_not_load_the_run_machinery(tmp_path: Path) -> None:
    probe = (
        "import sys, roboscript\n"
        "print(sorted(m for m in ('roboscript.api', 'roboscript.session', 'roboscript.replay')"
        " if m in sys.modules))\n"
        "print(roboscript.run.__module__, roboscript.RunResult.__name__)\n"
    )
    done = _python("-c", probe, cwd=tmp_path)
    assert done.stdout.splitlines() == ["[]", "roboscript.api RunResult"], done.stderr


# ------------------------------------------------------------------- python my_mission.py


def test_python_my_mission_runs_it_as_roboscript_run_does(tmp_path: Path) -> None:
    script = tmp_path / "hop.py"
    script.write_text(HOP + '\n\nif __name__ == "__main__":\n    Hop.main()\n')
    done = _python(str(script), cwd=tmp_path)
    assert done.returncode == 0, done.stderr
    assert "success: hop ended in 'ok'" in done.stderr
    as_json = _python(str(script), "--json", "--seed", "4", "--robot", "asip-basic", cwd=tmp_path)
    cli = run_cli("run", str(script), "--json", "--seed", "4", "--robot", "asip-basic")
    assert json.loads(as_json.stdout) == json.loads(cli.stdout)
    assert json.loads(as_json.stdout)["robot"] == "asip-basic"


def test_python_my_mission_exits_with_the_run_status(tmp_path: Path) -> None:
    script = tmp_path / "short.py"
    script.write_text(HOP + '\n\nif __name__ == "__main__":\n    Hop.main()\n')
    done = _python(str(script), "--max-time", "0.5", cwd=tmp_path)
    assert done.returncode == 1
    assert done.stderr.strip().splitlines()[-1] == (
        "failure: the mission did not finish within 0.5 s"
    )
    done = _python(str(script), "--robot", "no-such-robot", cwd=tmp_path)
    assert done.returncode == 2 and "Traceback" not in done.stderr


def test_a_mission_file_without_main_runs_its_mission_with_python(tmp_path: Path) -> None:
    script = tmp_path / "hop.py"
    script.write_text(HOP)
    done = _python(str(script), "--max-time", "0.5", cwd=tmp_path)
    assert done.returncode == 1, "the run's own status, as roboscript run hop.py gives"
    assert "hop.py defines the mission Hop: running it (roboscript run hop.py)" in done.stderr
    assert done.stderr.strip().splitlines()[-1] == (
        "failure: the mission did not finish within 0.5 s"
    )
    script.write_text(HOP + "\n\nimport roboscript\nprint(roboscript.run(Hop).outcome)\n")
    done = _python(str(script), cwd=tmp_path)
    assert (done.stdout, done.stderr) == ("success\n", "")


def test_run_records_what_the_mission_printed_while_it_loaded(tmp_path: Path) -> None:
    mission = tmp_path / "square.py"
    text = (MISSIONS / "square.py").read_text(encoding="utf-8")
    mission.write_text('print("loading my square")\n' + text, encoding="utf-8")
    result = roboscript.run(mission, seed=7, record=True)
    assert result.recording is not None
    assert result.recording.header["printed_before_start"] == ["loading my square"]
