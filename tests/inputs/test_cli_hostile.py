"""``roboscript check`` on hostile files: exit 2, one located line, no traceback."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest
from helpers import HANG_BOUND_S

LAUGHS = """\
mission: laughs
initial: go
states:
  go: {final: success}
description:
  a: &a ["lol","lol","lol","lol","lol","lol","lol","lol","lol"]
  b: &b [*a,*a,*a,*a,*a,*a,*a,*a,*a]
  c: &c [*b,*b,*b,*b,*b,*b,*b,*b,*b]
  d: &d [*c,*c,*c,*c,*c,*c,*c,*c,*c]
  e: &e [*d,*d,*d,*d,*d,*d,*d,*d,*d]
  f: &f [*e,*e,*e,*e,*e,*e,*e,*e,*e]
  g: &g [*f,*f,*f,*f,*f,*f,*f,*f,*f]
  h: &h [*g,*g,*g,*g,*g,*g,*g,*g,*g]
  i: &i [*h,*h,*h,*h,*h,*h,*h,*h,*h]
"""


def check(path: Path) -> list[str]:
    done = subprocess.run(
        [sys.executable, "-m", "roboscript", "check", str(path)],
        capture_output=True,
        text=True,
        timeout=HANG_BOUND_S,  # a hang is a failure, not a stuck test run; never a pass threshold
        check=False,
    )
    assert done.returncode == 2
    assert done.stdout == ""
    assert "Traceback" not in done.stderr
    lines = done.stderr.splitlines()
    assert lines[-1] == "checked 1 file: 1 with errors"
    return lines[:-1]


def test_a_billion_laughs_mission_is_one_located_error(tmp_path: Path) -> None:
    # Before the value budget, this 600-byte file took a minute and 5.9 GB to "check" clean.
    path = tmp_path / "laughs.yaml"
    path.write_text(LAUGHS, encoding="utf-8")
    assert check(path) == [
        (
            f"{path}:11:10: error: the aliases (*name) here expand to more than 100000 values"
            " (a roboscript file holds at most 100000 values, aliases expanded)"
        )
    ]


@pytest.mark.skipif(not Path("/dev/zero").exists(), reason="needs /dev/zero")
def test_a_mission_that_is_dev_zero_is_refused_unread(tmp_path: Path) -> None:
    path = tmp_path / "mission.yaml"
    path.symlink_to("/dev/zero")  # reading it would never end
    assert check(path) == [
        f"{path}: error: this is a character device, not an ordinary file (give the path of a file)"
    ]


@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="needs named pipes")
def test_a_mission_that_is_a_named_pipe_is_refused_unopened(tmp_path: Path) -> None:
    path = tmp_path / "mission.yaml"
    os.mkfifo(path)  # opening it would wait for a writer forever
    assert check(path) == [
        f"{path}: error: this is a named pipe, not an ordinary file (give the path of a file)"
    ]


LONG_KEY = """\
mission: long
initial: go
states:
  go: {do: {drive: {distance: 20 cm}}, on: {done: fin}}
  {key}:
    final: success
  fin: {final: success}
"""


def test_a_state_name_longer_than_yaml_reads_as_a_key_is_named_too_long(tmp_path: Path) -> None:
    # Past 1024 characters YAML stops reading a key as one, and said "a ':' is not allowed".
    path = tmp_path / "long.yaml"
    path.write_text(LONG_KEY.replace("{key}", "s" * 5000), encoding="utf-8")
    assert check(path) == [
        (
            f"{path}:5:3: error: this key is 5000 characters long; names are at most 200"
            " ('ssssssssssssssssssss...')"
        )
    ]


BUILT_NAME = """\
from roboscript import Drive, Mission, state


class Long(Mission):
    {line}
    go = state(Drive(distance_mm=200), initial=True, on_done="fin")
    fin = state(final="success")
"""


@pytest.mark.parametrize(
    ("line", "kind", "where"),
    [
        ('locals()["s" * 10_000_000] = state(final="failure")', "state name", "5"),
        ('name = "s" * 10_000_000', "mission name", "4:1"),
        ('other = state(Drive(distance_mm=1), on_done="s" * 10_000_000)', "state name", "5:49"),
    ],
    ids=["a state", "the mission", "a transition's target"],
)
def test_a_ten_megabyte_name_in_a_python_mission_is_one_located_error(
    tmp_path: Path, line: str, kind: str, where: str
) -> None:
    path = tmp_path / "long.py"
    path.write_text(BUILT_NAME.replace("{line}", line), encoding="utf-8")
    assert check(path) == [
        (
            f"{path}:{where}: error: this {kind} is 10000000 characters long; names are at most 200"
            " ('ssssssssssssssssssss...')"
        )
    ]
