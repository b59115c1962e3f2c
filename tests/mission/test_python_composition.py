"""Python missions compose like YAML ones: Parallel, Repeat, and a Mission as a nested state."""

from __future__ import annotations

import json
from collections.abc import Callable
from pathlib import Path

from helpers import run_cli

NESTED = '''"""Out and back twice, with a tune while driving out."""
from roboscript import Drive, Mission, Parallel, PlayTone, Repeat, Rotate, state


class OutAndBack(Mission):
    out = state(
        Parallel([Drive(distance_mm=300), PlayTone(frequency_hz=523, duration_s=1)]),
        initial=True, on_done="turn", on_failed="oops",
    )
    turn = state(Repeat(Rotate(angle_deg=90), times=2), on_done="home", on_failed="oops")
    home = state(final="success")
    oops = state(final="failure")


class Twice(Mission):
    first = state(OutAndBack, initial=True, on_done="second", on_failed="sad")
    second = state(OutAndBack, on_done="happy", on_failed="sad")
    happy = state(final="success")
    sad = state(final="failure")
'''


def test_nested_python_missions_run_with_parallel_and_repeat(
    write_mission: Callable[..., Path],
) -> None:
    result = run_cli("run", str(write_mission(NESTED, name="twice.py")), "--json")
    assert result.returncode == 0, result.stderr
    summary = json.loads(result.stdout)
    assert [name for _, name in summary["states"]] == [
        "first",
        "first.out",
        "first.turn",
        "first.home",
        "second",
        "second.out",
        "second.turn",
        "second.home",
        "happy",
    ]
    assert [t["frequency_hz"] for t in summary["sim"]["tones"]] == [523.0, 523.0]
    pose = summary["sim"]["final_pose"]
    assert abs(pose["x_mm"]) < 20 and abs(pose["y_mm"]) < 20  # out, turn round, back, twice


def test_children_of_a_parallel_count_in_the_capability_check(
    write_mission: Callable[..., Path],
) -> None:
    result = run_cli("check", str(write_mission(NESTED, name="twice.py")), "--robot", "plen2")
    assert result.returncode == 2
    assert "needs drive_base" in result.stderr and "plen2 does not have" in result.stderr


def test_a_mission_class_nested_in_two_states_is_warned_about_once(
    write_mission: Callable[..., Path],
) -> None:
    text = """from roboscript import Drive, Mission, state


class Hop(Mission):
    hop = state(Drive(distance_mm=100), initial=True, on_done="ok")
    ok = state(final="success")


class Twice(Mission):
    one = state(Hop, initial=True, on_done="two", on_failed="end")
    two = state(Hop, on_done="end", on_failed="end")
    end = state(final="success")
"""
    result = run_cli("check", str(write_mission(text, name="twice.py")))
    assert result.returncode == 0, result.stderr
    warnings = [line for line in result.stderr.splitlines() if "warning:" in line]
    assert len(warnings) == 1 and "'drive' fails" in warnings[0], result.stderr
