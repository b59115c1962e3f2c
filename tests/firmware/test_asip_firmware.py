"""roboscript's simulated MIRTO board against the real ASIP V1.1 firmware with the MIRTO sketch.

The firmware (ASIP V1.1 library, sketch ``mirtle2017``, ATmega328P build, 57600 baud UART)
runs on an emulated AVR; ``roboscript sim``'s board gets the same probes on the same schedule.
Every answer must be byte-identical, except the differences listed in ``KNOWN_DIFFERENCES``,
each with the firmware line that decides it (docs/robots/mirto.md lists them too). A listed
difference that goes away fails its test too, so the list stays true.
"""

from __future__ import annotations

import pytest
from firmware.asip_probes import PROBES, Probe
from firmware.transcripts import firmware_transcript, sim_transcript

KNOWN_DIFFERENCES: dict[str, str] = {
    "ir events": (
        "the IR values are the simulated floor's; the emulated board's ADC inputs read 0 V"
    ),
    "distance events": (
        "mirtle2017.ino: `NBR_DISTANCE_SENSORS = 1`; roboscript's mirto profile has a second, "
        "right-facing sensor (a sketch built with 2)"
    ),
    "distance measure": "the same second distance sensor",
    "an unknown strip's pixel count": (
        "asipPixels.cpp reads `stripPtr[stripIndex]` unchecked (`// todo - validate "
        "stripIndex range`), past its one strip: undefined; the simulated board answers "
        "~P,I,7{INVALID_DEVICE_NUMBER}"
    ),
}


@pytest.fixture(scope="module")
def transcripts() -> tuple[tuple[bytes, list[bytes]], tuple[bytes, list[bytes]]]:
    return firmware_transcript(PROBES), sim_transcript(PROBES)


def test_sim_greets_a_host_with_the_sketchs_start_up_lines(
    transcripts: tuple[tuple[bytes, list[bytes]], tuple[bytes, list[bytes]]],
) -> None:
    (firmware_greeting, _), (sim_greeting, _) = transcripts
    assert sim_greeting == firmware_greeting


@pytest.mark.parametrize("probe", PROBES, ids=[probe.name for probe in PROBES])
def test_sim_answers_each_probe_as_the_firmware_does(
    probe: Probe,
    transcripts: tuple[tuple[bytes, list[bytes]], tuple[bytes, list[bytes]]],
) -> None:
    (_, firmware_answers), (_, sim_answers) = transcripts
    index = PROBES.index(probe)
    firmware, sim = firmware_answers[index], sim_answers[index]
    if probe.name in KNOWN_DIFFERENCES:
        assert sim != firmware, f"no longer differs: drop {probe.name!r} from KNOWN_DIFFERENCES"
    else:
        assert sim == firmware, f"{probe.data!r}: firmware {firmware!r}, sim {sim!r}"
