"""The error tree's shared pieces: fault samples and "did you mean" hints."""

from __future__ import annotations

from pathlib import Path

from helpers import ROOT, run_cli

from roboscript.errors import (
    FAULT_SAMPLE_BYTES,
    MissionError,
    RemoteProtocolError,
    did_you_mean,
    grouped,
    nearby_file,
)


def test_a_fault_keeps_only_the_start_of_a_long_bad_frame() -> None:
    frame = bytearray(range(256)) * 40  # a 10 KiB frame of garbage
    fault = RemoteProtocolError("garbage", kind="garbage", data=frame)
    assert fault.data == bytes(frame[:FAULT_SAMPLE_BYTES])
    assert isinstance(fault.data, bytes)


def test_did_you_mean_names_the_closest_choice_or_nothing() -> None:
    assert did_you_mean("drvie", ["drive", "rotate"]) == "did you mean 'drive'?"
    assert did_you_mean("final_pose", ["final_pose_within", "final_state"]) == (
        "did you mean 'final_pose_within'?"
    )
    assert did_you_mean("xyzzy", ["drive", "rotate"]) is None


def test_did_you_mean_names_the_choice_written_in_another_case() -> None:
    assert did_you_mean("MIRTO", ["mirto", "asip-basic"]) == "did you mean 'mirto'?"
    assert did_you_mean("Go", ["go", "end"]) == "did you mean 'go'?"


def test_a_missing_file_suggests_the_file_of_a_like_name_beside_it(tmp_path: Path) -> None:
    (tmp_path / "square.yaml").write_text("", encoding="utf-8")
    assert nearby_file(tmp_path / "square.yml") == "did you mean 'square.yaml'?"
    assert nearby_file(tmp_path / "square") == "did you mean 'square.yaml'?"
    assert nearby_file(tmp_path / "Square.yaml") == "capitals count: did you mean 'square.yaml'?"
    assert nearby_file(tmp_path / "sqaure.yaml") == "did you mean 'square.yaml'?"
    assert nearby_file(tmp_path / "zigzag.yaml") is None
    assert nearby_file(tmp_path / "square.yaml") is None  # it is there: nothing to suggest
    assert nearby_file(tmp_path / "no-folder" / "square.yaml") == (
        f"there is no folder 'no-folder' in {tmp_path.resolve()}"
    )


def test_a_file_under_a_missing_folder_names_the_first_folder_missing(tmp_path: Path) -> None:
    (tmp_path / "class").mkdir()
    assert nearby_file(tmp_path / "class" / "alice" / "v2" / "square.yaml") == (
        f"there is no folder 'alice' in {(tmp_path / 'class').resolve()}"
    )


def test_the_guides_examples_named_from_another_folder_say_where_they_are(
    tmp_path: Path,
) -> None:
    # The guides run `roboscript run missions/square.yaml` in the roboscript folder; typed
    # anywhere else (a wheel install, another folder), the answer says how to get them here.
    where = (
        f"there is no folder 'missions' in {tmp_path.resolve()}: `roboscript examples` writes"
        " the example missions here"
    )
    done = run_cli("run", "missions/square.yaml", cwd=tmp_path)
    assert (done.returncode, done.stderr) == (
        2,
        f"missions/square.yaml: error: cannot read the file: No such file or directory ({where})\n",
    )
    done = run_cli("check", "missions/", cwd=tmp_path)
    assert done.returncode == 2
    assert done.stderr == (
        f"missions/: error: there is no such file or folder ({where})\n"
        "checked 1 file: 1 with errors\n"
    )
    # in the roboscript folder, a missing example is only missing
    done = run_cli("run", "missions/squar.yaml")
    assert done.stderr.rstrip().endswith("(did you mean 'square.yaml'?)"), done.stderr


def test_running_a_misspelt_mission_file_names_the_one_beside_it(tmp_path: Path) -> None:
    (tmp_path / "square.yaml").write_text(
        (ROOT / "missions" / "square.yaml").read_text(encoding="utf-8"), encoding="utf-8"
    )
    for written in ("square.yml", "square"):
        done = run_cli("run", written, cwd=tmp_path)
        assert done.returncode == 2
        assert done.stderr.rstrip().endswith("(did you mean 'square.yaml'?)"), done.stderr
    done = run_cli("run", "square.yaml", "--world", "squareroom", cwd=tmp_path)
    assert "(did you mean 'square-room'?)" in done.stderr


def _typo(line: int, state: str = "a", hint: str = "did you mean 'drive'?") -> MissionError:
    return MissionError(
        f"unknown action 'dirve' in state '{state}'", path="m.yaml", line=line, col=10, hint=hint
    )


def test_problems_that_read_alike_are_told_three_times_then_counted_with_their_lines() -> None:
    problems = [_typo(3 * i + 4, state=f"s{i}") for i in range(14)]
    lines = grouped(problems)
    assert lines[:3] == [p.format() for p in problems[:3]]  # the first ones, each at its place
    assert lines[3] == (
        "m.yaml:13:10: error: and 11 more like it at lines 13, 16, 19, 22, 25, 28, 31, 34, 37,"
        " ..., 43"
    )
    assert len(lines) == 4


def test_problems_with_another_fix_or_file_are_not_counted_together() -> None:
    other_fix = [_typo(line, hint="did you mean 'rotate'?") for line in (4, 5, 6, 7)]
    same_fix = [_typo(line) for line in (8, 9)]
    other_file = MissionError("unknown action 'dirve' in state 'a'", path="n.yaml", line=1)
    lines = grouped([*other_fix, *same_fix, other_file])
    assert lines[3] == "m.yaml:7:10: error: and 1 more like it at lines 7"
    assert lines[4:] == [p.format() for p in [*same_fix, other_file]]
