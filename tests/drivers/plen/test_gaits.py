"""roboscript's gait motions: valid PLEN2 motions in free slots, one step per loop pass."""

from __future__ import annotations

import json
from importlib import resources

import pytest

from roboscript.codec import Role
from roboscript.drivers.plen.codec import PlenCodec
from roboscript.drivers.plen.commands import encode_command
from roboscript.drivers.plen.gaits import GAIT_KEYS, load_gait, load_gaits
from roboscript.drivers.plen.messages import JOINT_NAMES, MotionHeader


def test_the_four_gaits_live_in_slots_80_to_83() -> None:
    gaits = load_gaits()
    assert [gaits[key].slot for key in GAIT_KEYS] == [80, 81, 82, 83]
    assert [gaits[key].header.name for key in GAIT_KEYS] == [
        "RS Walk Forward",
        "RS Walk Backward",
        "RS Turn Right",
        "RS Turn Left",
    ]


def test_walk_forward_header_bytes() -> None:
    # slot 50, name padded to 20, loop on from frame 00 to 05 255 times, no jump, no extra, 6 frames
    assert encode_command(load_gait("walk_forward").header) == (
        b">MH50RS Walk Forward     10005ff000006"
    )


@pytest.mark.parametrize("key", GAIT_KEYS)
def test_each_gait_is_one_step_from_home_stance_to_home_stance(key: str) -> None:
    gait = load_gait(key)
    header = gait.header
    assert (header.use_loop, header.loop_begin, header.loop_end, header.loop_count) == (
        True,
        0,
        header.frame_length - 1,
        255,
    )
    assert not header.use_jump
    assert set(gait.frames[-1].offsets_ddeg) == {0}
    assert all(frame.transition_time_ms % 32 == 0 for frame in gait.frames)
    assert gait.schedule(1).duration_s() == pytest.approx(0.992)
    assert gait.schedule(4).duration_s() == pytest.approx(4 * 0.992)


@pytest.mark.parametrize("key", GAIT_KEYS)
def test_each_gait_installs_as_paced_setter_commands_the_firmware_reads(key: str) -> None:
    gait = load_gait(key)
    data = gait.install_bytes()
    assert len(data) == 3 + 35 + len(gait.frames) * (3 + 104)
    device = PlenCodec(Role.DEVICE)
    device.receive_data(data)
    decoded = []
    while (message := device.next_message()) is not None:
        decoded.append(message)
    assert decoded == [gait.header, *gait.frames]
    assert isinstance(decoded[0], MotionHeader)


@pytest.mark.parametrize("key", GAIT_KEYS)
def test_motion_files_name_every_joint_in_every_frame(key: str) -> None:
    source = resources.files("roboscript.drivers.plen") / "motions" / f"{key}.json"
    data = json.loads(source.read_text(encoding="utf-8"))
    for frame in data["frames"]:
        assert [output["device"] for output in frame["outputs"]] == list(JOINT_NAMES.values())


def test_steps_and_turns_carry_their_signs() -> None:
    gaits = load_gaits()
    assert gaits["walk_forward"].stride_mm == 40.0
    assert gaits["walk_backward"].stride_mm == -40.0
    assert gaits["turn_right"].turn_step_deg == 15.0
    assert gaits["turn_left"].turn_step_deg == -15.0
    with pytest.raises(KeyError):
        load_gait("moonwalk")
