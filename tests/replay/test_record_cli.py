"""``roboscript run --record`` and ``roboscript view`` as a user types them."""

from __future__ import annotations

import contextlib
import json
import os
import re
import resource
import subprocess
import sys
import time
from collections.abc import Callable
from pathlib import Path

import pytest
from helpers import HANG_BOUND_S, MISSIONS, OUT_TURN_BEEP, ROOT, run_cli, served_simulator

from roboscript.replay import load_recording
from roboscript.transport.wirelog import read_wire_log


def test_run_record_then_view_writes_a_self_contained_page(tmp_path: Path) -> None:
    run = tmp_path / "run.jsonl"
    done = run_cli("run", str(MISSIONS / "square.yaml"), "--record", str(run), "--quiet")
    assert done.returncode == 0, done.stderr
    recording = load_recording(run)
    assert recording.result is not None and recording.result["outcome"] == "success"
    assert recording.header["mission"]["name"] == "square"

    view = run_cli("view", str(run))
    assert view.returncode == 0, view.stderr
    page = tmp_path / "run.html"
    assert view.stderr.strip() == f"replay: {page}"
    html = page.read_text(encoding="utf-8")
    assert "<script src" not in html and "<link" not in html and "http" not in html
    data = re.search(r'<script type="application/json" class="rs-data">(.*?)</script>', html)
    assert data is not None
    embedded = json.loads(data.group(1))
    assert len(embedded["frames"]) == len(recording.frames)
    assert embedded["header"]["format"] == "roboscript-run"

    other = tmp_path / "other.html"
    assert run_cli("view", str(run), "-o", str(other)).returncode == 0
    assert other.read_text(encoding="utf-8") == html


@pytest.mark.parametrize(
    ("option", "where"),
    [
        ("--record", "a folder"),
        ("--record", "under a file"),
        ("--wire-log", "under a file"),
        ("--plot", "a folder"),
        ("--wire-log", "the recording"),
        ("--record", "the mission"),
        ("--plot", "the mission"),
    ],
)
def test_an_output_path_that_cannot_be_written_is_refused_before_the_robot_moves(
    tmp_path: Path, option: str, where: str
) -> None:
    a_file = tmp_path / "notes.txt"
    a_file.write_text("mine\n", encoding="utf-8")
    mission = tmp_path / "square.yaml"
    mission.write_bytes((MISSIONS / "square.yaml").read_bytes())
    record = tmp_path / "run.jsonl"
    target = {
        "a folder": tmp_path,
        "under a file": a_file / "run.out",
        "the recording": record,
        "the mission": mission,
    }[where]
    outputs = ["--record", str(target)]
    if option != "--record":  # beside a recording that could be written
        outputs = ["--record", str(record), option, str(target)]
    done = run_cli("run", str(mission), *outputs, "--json")
    assert done.returncode == 2, done.stderr
    assert done.stdout == ""  # no run: the robot never moved
    assert done.stderr.count("\n") == 1 and done.stderr.startswith("error: ")
    assert str(target) in done.stderr or option in done.stderr
    assert a_file.read_text(encoding="utf-8") == "mine\n"  # nothing of the user's is lost
    assert mission.read_bytes() == (MISSIONS / "square.yaml").read_bytes()
    assert not record.exists() or where == "the recording"


def test_run_outputs_in_folders_not_made_yet_are_written_there(tmp_path: Path) -> None:
    record = tmp_path / "new" / "runs" / "run.jsonl"
    wire = tmp_path / "logs" / "run.wire"
    done = run_cli(
        "run",
        str(MISSIONS / "square.yaml"),
        "--record",
        str(record),
        "--wire-log",
        str(wire),
        "--quiet",
    )
    assert done.returncode == 0, done.stderr
    assert load_recording(record).result is not None
    assert read_wire_log(wire)


@pytest.mark.parametrize(
    "outputs", [("-o", "run.jsonl"), ("--csv", "run.jsonl"), ("-o", "x.csv", "--csv", "x.csv")]
)
def test_view_never_writes_its_page_over_the_recording(
    tmp_path: Path, outputs: tuple[str, ...]
) -> None:
    run = tmp_path / "run.jsonl"
    done = run_cli("run", str(MISSIONS / "square.yaml"), "--record", str(run), "--quiet")
    assert done.returncode == 0, done.stderr
    kept = run.read_bytes()
    view = run_cli("view", "run.jsonl", *outputs, cwd=tmp_path)
    assert view.returncode == 2
    assert view.stderr.startswith("error: ") and view.stderr.count("\n") == 1
    assert run.read_bytes() == kept
    assert sorted(p.name for p in tmp_path.iterdir()) == ["run.jsonl"]


def test_view_names_a_bad_recording_in_one_line(tmp_path: Path) -> None:
    bad = tmp_path / "bad.jsonl"
    bad.write_text('{"format": "roboscript-run", "version": 9}\n', encoding="utf-8")
    done = run_cli("view", str(bad))
    assert done.returncode == 2
    assert done.stderr.strip() == (
        f"{bad}:1: error: this recording is version 9; this roboscript reads up to version 1"
        " (upgrade roboscript)"
    )
    assert not (tmp_path / "bad.html").exists()


def test_a_run_on_a_port_records_the_odometry_pose(
    write_mission: Callable[..., Path], tmp_path: Path
) -> None:
    mission = write_mission(OUT_TURN_BEEP)
    run = tmp_path / "run.jsonl"
    with served_simulator("mirto") as port:
        url = f"socket://127.0.0.1:{port}"
        done = run_cli("run", str(mission), "--port", url, "--record", str(run), "--quiet")
    assert done.returncode == 0, done.stderr
    recording = load_recording(run)
    assert recording.header["pose_source"] == "odometry"
    assert recording.header["world"] is None and recording.header["seed"] is None
    assert recording.header["port"] == url
    x, y, heading = recording.frames[-1]["pose"]
    # 20 cm north, then a quarter turn right on the spot
    assert x == pytest.approx(0.0, abs=15.0)
    assert y == pytest.approx(200.0, abs=15.0)
    assert heading == pytest.approx(90.0, abs=6.0)
    assert [f["tone"] for f in recording.frames if "tone" in f] == [[660.0, 0.2]]
    # One frame per tick of the wall-clock loop: never faster than its period on average, nor
    # closer than a catch-up tick (half a period). How much later a busy machine makes them
    # is the machine's business, not the recording's.
    ticks = [b["t"] - a["t"] for a, b in zip(recording.frames, recording.frames[1:], strict=False)]
    assert sum(ticks) / len(ticks) >= 0.02 - 0.002
    assert min(ticks) >= 0.01 - 0.001


def _line_end_mission(folder: Path) -> Path:
    mission = folder / "ends.yaml"
    mission.write_text(
        'mission: "ends\\u2028here"\n'
        "initial: show\n"
        "states:\n"
        '  show: {do: {display: {text: "a\\u2028b\\u2029c\\x85d"}}, on: {done: wait}}\n'
        "  wait: {do: {wait: {duration: 0.2 s}}, on: {done: finished}}\n"
        "  finished: {final: success}\n",
        encoding="utf-8",
    )
    return mission


def test_a_run_showing_line_separators_records_a_file_view_and_graph_read(
    tmp_path: Path,
) -> None:
    mission = _line_end_mission(tmp_path)
    run = tmp_path / "run.jsonl"
    done = run_cli("run", str(mission), "--record", str(run), "--quiet")
    assert done.returncode == 0, done.stderr
    assert load_recording(run).frames[-1]["display"] == "a\u2028b\u2029c\x85d"
    view = run_cli("view", str(run))
    assert view.returncode == 0, view.stderr
    graph = run_cli("graph", str(mission), "--run", str(run), "-o", str(tmp_path / "g.svg"))
    assert graph.returncode == 0, graph.stderr


def _limited_run(
    limit_bytes: int, *args: str, stdout: Path | None = None
) -> subprocess.CompletedProcess[str]:
    """``roboscript ARGS`` with files limited to ``limit_bytes`` (a full disk, for one
    process): writes past it fail with EFBIG, as Python ignores SIGXFSZ. ``stdout``: a file
    the output goes to, under the same limit."""

    def limit() -> None:
        resource.setrlimit(resource.RLIMIT_FSIZE, (limit_bytes, limit_bytes))

    env = {**os.environ, "PYTHONPATH": str(ROOT), "PYTHONDONTWRITEBYTECODE": "1"}
    with contextlib.ExitStack() as stack:
        out = stack.enter_context(stdout.open("w")) if stdout else subprocess.PIPE
        return subprocess.run(
            [sys.executable, "-m", "roboscript", *args],
            stdout=out,
            stderr=subprocess.PIPE,
            text=True,
            timeout=HANG_BOUND_S,
            env=env,
            preexec_fn=limit,
            check=False,
        )


@pytest.mark.parametrize(
    ("option", "what"), [("--record", "the recording"), ("--wire-log", "the wire log")]
)
def test_a_full_disk_is_one_sentence_after_the_robot_stops(
    tmp_path: Path, option: str, what: str
) -> None:
    out = tmp_path / "out.txt"
    done = _limited_run(20_000, "run", str(MISSIONS / "square.yaml"), option, str(out), "--json")
    assert "Traceback" not in done.stderr, done.stderr
    assert done.returncode == 1, done.stderr
    assert json.loads(done.stdout)["outcome"] == "success"  # the run went on to its end
    assert done.stderr.strip().splitlines()[-1] == (
        f"error: cannot write {what} {out}: File too large"
    )
    assert 0 < out.stat().st_size <= 20_000


def test_json_output_to_a_full_disk_is_one_sentence(tmp_path: Path) -> None:
    out = tmp_path / "summary.json"
    done = _limited_run(1_000, "run", str(MISSIONS / "square.yaml"), "--json", stdout=out)
    assert done.returncode == 1
    assert done.stderr == "error: cannot write the output: File too large\n"


def test_a_killed_run_leaves_a_recording_and_wire_log_view_opens(tmp_path: Path) -> None:
    run, wire = tmp_path / "run.jsonl", tmp_path / "run.wire"
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    child = subprocess.Popen(
        [
            *(sys.executable, "-m", "roboscript", "run", str(MISSIONS / "square.yaml")),
            *("--realtime", "--record", str(run), "--wire-log", str(wire), "--quiet"),
        ],
        env=env,
        stderr=subprocess.DEVNULL,
    )
    try:
        # wait for the frames of the first second to reach the disk, then kill outright
        for _ in range(1200):
            if run.exists() and run.read_text(encoding="utf-8").count("\n") > 3:
                break
            if child.poll() is not None:
                break
            time.sleep(0.1)
        assert child.poll() is None, "the run ended before it could be killed"
        child.kill()
    finally:
        child.kill()
        child.wait()
    recording = load_recording(run)
    assert recording.frames and recording.result is None  # a prefix, cut short
    assert any(direction == ">" for _, direction, _ in read_wire_log(wire))
    view = run_cli("view", str(run))
    assert view.returncode == 0, view.stderr


HEADER_LINE = '{"format":"roboscript-run","version":1,"mission":{"name":"m","states":[]}}\n'


@pytest.mark.parametrize(
    ("body", "problem"),
    [
        ('{"t":NaN}\n', "2: error: this line is not JSON (NaN is not a number JSON allows)"),
        ('{"t":0,"pose":[0,0,-Infinity]}\n', "2: error: this line is not JSON"),
        ("[" * 5000 + "]" * 5000 + "\n", "2: error: this line is nested too deeply"),
        ('{"t":0,"sensors":"loud"}\n', "2: error: 'sensors' must be an object"),
        ('{"t":0}\n{"result":"fine"}\n', "3: error: 'result' must be an object"),
        ('{"t":0,"pose":"here"}\n', "2: error: 'pose' must be a list of 3 values"),
        ('{"t":0}\n\x85\u2028{oops\n', "3: error: this line is not JSON"),
    ],
)
def test_view_refuses_a_hostile_recording_at_its_line(
    tmp_path: Path, body: str, problem: str
) -> None:
    bad = tmp_path / "bad.jsonl"
    bad.write_text(HEADER_LINE + body, encoding="utf-8")
    done = run_cli("view", str(bad))
    assert done.returncode == 2
    assert done.stderr.startswith(f"{bad}:{problem}"), done.stderr
    assert len(done.stderr.strip().splitlines()) == 1  # one sentence, no traceback
    assert not list(tmp_path.glob("bad.html*"))  # no page, not even half of one


def _view_peak_kib(recording: Path) -> int:
    """``roboscript view RECORDING``'s peak resident memory, KiB, as the kernel counted it."""
    child = subprocess.Popen(
        [sys.executable, "-m", "roboscript", "view", str(recording)],
        env={**os.environ, "PYTHONPATH": str(ROOT)},
        stderr=subprocess.DEVNULL,
    )
    _, status, usage = os.wait4(child.pid, 0)
    child.returncode = os.waitstatus_to_exitcode(status)
    assert child.returncode == 0
    return int(usage.ru_maxrss)


def test_view_memory_does_not_grow_with_the_recording(tmp_path: Path) -> None:
    frame = '{"t":%d.02,"pose":[%d.5,-3.25,90.0],"sensors":{"range_mm":%d.5,"line":[1,2,3]}}\n'
    small, large = tmp_path / "small.jsonl", tmp_path / "large.jsonl"
    small.write_text(HEADER_LINE + "".join(frame % (i, i, i) for i in range(1_000)))
    large.write_text(HEADER_LINE + "".join(frame % (i, i, i) for i in range(150_000)))
    grown_kib = _view_peak_kib(large) - _view_peak_kib(small)
    more_kib = (large.stat().st_size - small.stat().st_size) // 1024
    # the whole file in memory would cost several times its size (it once cost 23 times)
    assert grown_kib < more_kib / 4, (grown_kib, more_kib)
    assert (tmp_path / "large.html").stat().st_size > large.stat().st_size
