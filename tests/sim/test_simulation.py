"""The simulation's record of a run starts where the mission does."""

from __future__ import annotations

from roboscript.sim.simulation import make_simulation

TONE = b"T,P,880,100\n"  # an ASIP tone request: 880 Hz for 100 ms


def test_tones_before_the_mission_starts_are_forgotten() -> None:
    sim = make_simulation("mirto")
    sim.connect()
    for _ in range(3):
        sim.write(TONE)
    sim.tick(0.5, 0.02)
    assert len(sim.log.tones) == 3
    start_s = sim.time_s
    sim.start_mission()
    assert sim.log.tones == [] and sim.tones_since(start_s) == []
    sim.tick(1.0, 0.02)  # on to 1 s of simulated time
    sim.write(TONE)
    [(t_s, frequency_hz, duration_s)] = sim.tones_since(start_s)
    assert (frequency_hz, duration_s) == (880.0, 0.1)
    assert t_s == round(sim.time_s - start_s, 3) > 0.0
    assert sim.path_since(start_s)[0][0] == 0.0  # the path starts there too


def test_tones_since_leaves_out_those_before_the_time_given() -> None:
    sim = make_simulation("mirto")
    sim.connect()
    sim.write(TONE)
    sim.tick(1.0, 0.02)
    sim.write(TONE)
    assert [t for t, _, _ in sim.tones_since(0.5)] == [round(sim.time_s - 0.5, 3)]
