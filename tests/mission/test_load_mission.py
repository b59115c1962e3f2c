"""``load_mission``: which loader a file goes to, and the message for a file of no known kind
(issue 16)."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import pytest

from roboscript.errors import MissionError
from roboscript.mission import fit_to_robot, load_mission
from roboscript.profiles import get_profile

YAML = """\
mission: short
initial: go
states:
  go:
    do: {play_tone: {frequency: 440 Hz, duration: 1 s}}
    on: {done: end}
  end:
    final: success
"""

PYTHON = """\
from roboscript import Mission, PlayTone, state


class Short(Mission):
    go = state(PlayTone(frequency_hz=440, duration_s=1), initial=True, on_done="end")
    end = state(final="success")
"""


@pytest.mark.parametrize("name", ["short.yaml", "short.yml", "SHORT.YML"])
def test_yaml_missions_load_under_either_suffix(tmp_path: Path, name: str) -> None:
    path = tmp_path / name
    path.write_text(YAML, encoding="utf-8")
    spec, warnings = load_mission(path)
    assert (spec.name, list(spec.states), warnings) == ("short", ["go", "end"], [])


def test_a_python_mission_is_checked_against_the_robot_given(tmp_path: Path) -> None:
    # a robot without a speaker cannot play the tone: the profile must reach the Python loader
    path = tmp_path / "short.py"
    path.write_text(PYTHON, encoding="utf-8")
    assert load_mission(path)[0].name == "short"
    quiet = replace(get_profile("mirto"), name="quiet", capabilities=frozenset({"drive_base"}))
    with pytest.raises(MissionError) as info:
        load_mission(path, quiet)
    assert info.value.format() == (
        f"{path}:5:16: error: 'play_tone' needs speaker (a tone generator),"
        " which quiet does not have"
    )


@pytest.mark.parametrize(
    ("name", "expected"),
    [
        (
            "mission.txt",
            (
                "{path}: error: a mission file ends in .yaml or .py (got '.txt') (save it as"
                " mission.yaml, or mission.py for a Python mission: the ending tells roboscript how"
                " to read it)"
            ),
        ),
        ("Makefile", "{path}: error: a mission file ends in .yaml or .py (got 'Makefile')"),
    ],
)
def test_a_file_of_another_kind_is_refused(tmp_path: Path, name: str, expected: str) -> None:
    path = tmp_path / name
    with pytest.raises(MissionError) as info:
        load_mission(path)
    assert info.value.format() == expected.format(path=path)


FIT = """\
mission: fit
initial: go
states:
  go:
    do: {play_tone: {frequency: 440 Hz, duration: 1 s}}
    on: {done: fast}
  fast:
    do: {drive: {distance: 50 cm, speed: 40 cm/s}}
    on: {done: end}
  end:
    final: success
"""

STALL = (
    "{path}:8:10: warning: if 'drive' fails (stalled) in state 'fast', the mission ends in"
    " failure (add 'on: {{failed: STATE}}' to handle it)"
)
TOO_FAST = (
    "{path}:8:42: warning: drive speed: 400 mm/s is faster than {robot} can drive, so it will"
    " drive at its top speed of 300 mm/s (write speed: 300 mm/s or less)"
)


def test_a_mission_that_fits_the_robot_comes_with_its_warnings_in_file_order(
    tmp_path: Path,
) -> None:
    path = tmp_path / "fit.yaml"
    path.write_text(FIT, encoding="utf-8")
    spec, warnings = load_mission(path)
    _spec, profile, found = fit_to_robot(spec, warnings, "mirto")
    assert profile.name == "mirto"
    assert [p.format() for p in found] == [
        STALL.format(path=path),
        TOO_FAST.format(path=path, robot="mirto"),
    ]


def test_a_mission_that_needs_what_the_robot_lacks_is_refused_with_every_problem_in_order(
    tmp_path: Path,
) -> None:
    # the error comes first (line 5); on line 8 the warnings go by column, not by who found them
    path = tmp_path / "fit.yaml"
    path.write_text(FIT, encoding="utf-8")
    spec, warnings = load_mission(path)
    with pytest.raises(MissionError) as info:
        fit_to_robot(spec, warnings, "stackmod-reference")
    assert [p.format() for p in info.value.problems] == [  # type: ignore[attr-defined]
        (
            f"{path}:5:10: error: 'play_tone' needs speaker (a tone generator), which"
            " stackmod-reference does not have"
        ),
        STALL.format(path=path),
        TOO_FAST.format(path=path, robot="stackmod-reference"),
    ]
