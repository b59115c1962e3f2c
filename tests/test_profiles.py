"""Robot profiles named on the command line: a built-in's name, or a profile file."""

from __future__ import annotations

from pathlib import Path

import pytest
from helpers import MISSIONS, run_cli

from roboscript.errors import ProfileError
from roboscript.profiles import get_profile


def test_a_missing_profile_file_named_like_a_built_in_robot_suggests_the_built_in(
    tmp_path: Path,
) -> None:
    # `--robot mirto.yaml` for the built-in mirto: the file is missing, the robot is not.
    done = run_cli("run", str(MISSIONS / "square.yaml"), "--robot", "mirto.yaml", cwd=tmp_path)
    assert done.returncode == 2, done.stderr
    assert done.stderr == (
        "error: there is no robot profile file mirto.yaml (did you mean the built-in robot"
        " 'mirto', named without '.yaml'?)\n"
    )


@pytest.mark.parametrize(
    ("name", "hint"),
    [
        ("plen2.yml", "did you mean the built-in robot 'plen2', named without '.yml'?"),
        ("mirtoo.yaml", "did you mean 'mirto'?"),
        ("zzzzqqq.yaml", None),
    ],
)
def test_a_missing_profile_file_says_it_is_missing_with_the_near_built_in(
    name: str, hint: str | None, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.chdir(tmp_path)
    with pytest.raises(ProfileError) as info:
        get_profile(name)
    assert info.value.message == f"there is no robot profile file {name}"
    assert info.value.hint == hint
