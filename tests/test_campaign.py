"""The fuzz campaign's own parts (tools/fuzz_campaign.py, docs/development/fuzzing.md): its
inputs are reproducible from the seed, and its judge of "the robot was left moving" tells a
stopped robot from a driving one."""

from __future__ import annotations

import random
import sys

from helpers import ROOT

sys.path.insert(0, str(ROOT / "tools"))

import fuzz_campaign
import fuzz_shapes


def test_the_same_seed_makes_the_same_inputs_of_every_kind() -> None:
    first = [fuzz_shapes.make_input(random.Random(f"1:{i}")) for i in range(200)]
    again = [fuzz_shapes.make_input(random.Random(f"1:{i}")) for i in range(200)]
    assert first == again
    assert {kind for kind, _ in first} == set(fuzz_shapes.KINDS)
    other = [fuzz_shapes.make_input(random.Random(f"2:{i}")) for i in range(200)]
    assert other != first


def test_a_robot_told_to_drive_last_is_left_moving_and_one_told_to_stop_is_not() -> None:
    drive = [(0.0, b"E,1,50\n"), (0.2, b"M,M,200,200\n")]
    assert fuzz_campaign._moving_after("mirto", drive) == (True, True)
    stopped = [*drive, (1.0, b"M,S,0\n")]
    moved, moving = fuzz_campaign._moving_after("mirto", stopped)
    assert (moved, moving) == (True, False)
    assert fuzz_campaign._moving_after("mirto", []) == (False, False)
