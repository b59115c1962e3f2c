"""A simulated run of hours keeps a log of bounded size; a normal run's log is untouched."""

from __future__ import annotations

import itertools
from pathlib import Path

import pytest

from roboscript.mission import load_mission
from roboscript.profiles import get_profile
from roboscript.session import run_session, session_record
from roboscript.sim import body as body_module
from roboscript.sim import simulation as simulation_module
from roboscript.sim.body import FirstOf
from roboscript.sim.simulation import PATH_INTERVAL_S, make_simulation

FOREVER = """
mission: forever
description: Drive a square and beep at every corner, until the time limit.
initial: side
states:
  side:
    do: {drive: {distance: 30 cm, speed: 15 cm/s}}
    on: {done: corner, failed: side}
  corner:
    do: {rotate: {angle: 90 deg}}
    on: {done: beep, failed: side}
  beep:
    do: {play_tone: {frequency: 880 Hz, duration: 200 ms}}
    on: {done: side}
    when:
      - {if: "visits.side > 1000000", goto: finished}
  finished: {final: success}
"""


def _gaps(path: list[tuple[float, float, float, float]]) -> set[float]:
    return {round(b[0] - a[0], 3) for a, b in itertools.pairwise(path)}


def test_a_run_inside_the_horizon_keeps_every_sample() -> None:
    sim = make_simulation("mirto")
    sim.tick(60.0, 60.0)
    assert len(sim.log.path) == round(60.0 / PATH_INTERVAL_S) + 1
    assert _gaps(sim.log.path) == {PATH_INTERVAL_S}
    assert sim.path_interval_s == PATH_INTERVAL_S


def test_a_full_path_is_thinned_to_half_and_sampled_half_as_often(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    monkeypatch.setattr(simulation_module, "MAX_PATH_SAMPLES", 100)
    sim = make_simulation("mirto")
    sim.tick(1.05, 0.02)
    sim.sample_path()  # the mission starts here (an odd sample): it must survive thinning
    start = sim.log.path[-1]
    sim.tick(600.0, 0.02)
    path = sim.log.path
    assert 50 <= len(path) <= 100
    assert path[0][0] == 0.0
    assert start in path
    assert path[-1][0] >= 600.0 - sim.path_interval_s
    assert sim.path_interval_s == pytest.approx(PATH_INTERVAL_S * 2**6)  # 6000 samples, 100 kept
    assert [t for t, *_ in path] == sorted(t for t, *_ in path)
    assert sim.path_since(start[0])[0][0] == 0.0


def test_first_of_keeps_the_first_items_and_counts_the_rest() -> None:
    kept: FirstOf[int] = FirstOf(3)
    for item in range(10):
        kept.append(item)
    assert kept == [0, 1, 2]
    assert (kept.more, kept.total) == (7, 10)


def test_a_collision_after_the_log_is_full_still_ends_in_its_own_contact(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    monkeypatch.setattr(body_module, "MAX_CONTACTS", 1)
    sim = make_simulation("mirto", "square-room", start=None)
    body = sim.body
    for side in range(3):  # drive into the north wall, back off, again
        body.power = [0.6, 0.6]
        sim.tick(sim.time_s + 6.0, 6.0)
        body.power = [-0.6, -0.6]
        sim.tick(sim.time_s + 1.5, 1.5)
        del side
    contacts = sim.log.contacts
    assert len(contacts) == 1
    assert contacts.more >= 1
    assert contacts[0].end_s is not None
    assert contacts[0].end_s - contacts[0].start_s < 7.0  # not stretched by later contacts


def test_an_endless_mission_reports_a_bounded_summary(
    monkeypatch: pytest.MonkeyPatch, tmp_path: Path
) -> None:
    monkeypatch.setattr(simulation_module, "MAX_PATH_SAMPLES", 200)
    monkeypatch.setattr(body_module, "MAX_TONES", 4)
    mission = tmp_path / "forever.yaml"
    mission.write_text(FOREVER, encoding="utf-8")
    profile = get_profile("mirto")
    spec, _ = load_mission(mission, profile)
    session = run_session(spec, profile, max_time_s=180.0)
    summary = session_record(session).to_dict()["sim"]
    assert len(summary["path"]) <= 200
    assert summary["path"][0][0] == 0.0  # still from the mission's start
    assert len(summary["tones"]) == 4
    heard = session.simulation.log.tones.total
    assert heard > 4
    assert summary["tones_not_listed"] == heard - 4


def test_a_normal_summary_lists_every_tone_and_says_nothing_more() -> None:
    profile = get_profile("mirto")
    spec, _ = load_mission(Path(__file__).parents[2] / "missions" / "square.yaml", profile)
    summary = session_record(run_session(spec, profile)).to_dict()["sim"]
    assert len(summary["tones"]) == 4
    assert "tones_not_listed" not in summary
    path = [tuple(p) for p in summary["path"]]
    assert _gaps(path[1:]) == {PATH_INTERVAL_S}  # after the mission's start: every sample
