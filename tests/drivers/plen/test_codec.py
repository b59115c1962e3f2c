"""PLEN2 codec: wire formats of firmware 1.4.2, the seed's examples, faults, both roles."""

from __future__ import annotations

import json

import pytest

from roboscript.codec import Role, drain
from roboscript.drivers.plen.codec import PlenCodec
from roboscript.drivers.plen.commands import encode_command
from roboscript.drivers.plen.messages import (
    JOINT_COUNT,
    Command,
    GetJointSettings,
    GetMotion,
    GetVersion,
    HomePosition,
    JointSettingsReply,
    JumpCode,
    LoopCode,
    MotionFrame,
    MotionHeader,
    MotionReply,
    MotionReplyFrame,
    PlayMotion,
    PlenMessage,
    PopMotion,
    PushMotion,
    ResetInterpreter,
    ResetJointSettings,
    SetAngle,
    SetAngleDiff,
    SetHome,
    SetMax,
    SetMin,
    StopMotion,
    VersionReply,
    factory_joint_settings,
)
from roboscript.drivers.plen.motionfile import motion_from_json, motion_to_json
from roboscript.drivers.plen.replies import encode_reply, reply_from_json
from roboscript.errors import FAULT_SAMPLE_BYTES, LocalProtocolError, RemoteProtocolError

ZEROS = (0,) * JOINT_COUNT

Outcome = list[PlenMessage | tuple[str, bytes]]


def feed(codec: PlenCodec, *chunks: bytes) -> Outcome:
    """Feed chunks one by one, draining after each; faults become (kind, data)."""
    out: Outcome = []
    for chunk in chunks:
        codec.receive_data(chunk)
        while True:
            try:
                message = codec.next_message()
            except RemoteProtocolError as fault:
                out.append((fault.kind, fault.data))
                continue
            if message is None:
                break
            out.append(message)
    return out


def device(*chunks: bytes) -> Outcome:
    return feed(PlenCodec(Role.DEVICE), *chunks)


def host(*chunks: bytes) -> Outcome:
    return feed(PlenCodec(Role.HOST), *chunks)


def split(data: bytes, size: int) -> list[bytes]:
    return [data[i : i + size] for i in range(0, len(data), size)]


# ------------------------------------------------------------------------- the seed's examples

SEED_EXAMPLES: list[tuple[bytes, Command]] = [
    (b"$an0a3e8", SetAngle(10, 900)),  # 1000, clamped like the firmware does
    (b"$ad04f9c", SetAngleDiff(4, -100)),
    (b"$pm04", PlayMotion(4)),
    (b"$sm", StopMotion()),
    (b"$hp", HomePosition()),
    (b"#pu0a03", PushMotion(10, 3)),
    (b"#po", PopMotion()),
    (b"#ri", ResetInterpreter()),
    (b">js", ResetJointSettings()),
    (b">ho00064", SetHome(0, 100)),
    (b">ma00064", SetMax(0, 100)),
    (b">mi0afff", SetMin(10, -1)),
    (b"<js", GetJointSettings()),
    (b"<mo00", GetMotion(0)),
    (b"<vi", GetVersion()),
]


@pytest.mark.parametrize(("wire", "command"), SEED_EXAMPLES)
def test_seed_examples_decode(wire: bytes, command: Command) -> None:
    assert device(wire) == [command]


def test_seed_examples_back_to_back_in_one_stream() -> None:
    stream = b"".join(wire for wire, _ in SEED_EXAMPLES)
    codec = PlenCodec(Role.DEVICE)
    assert feed(codec, stream) == [command for _, command in SEED_EXAMPLES]
    assert codec.stats.messages == len(SEED_EXAMPLES)
    assert not codec.stats.faults
    assert codec.pending_bytes() == 0


def test_seed_install_command_is_not_in_firmware_142() -> None:
    seed_install = b">in00Test                000000020064" + b"0000ffff" * 12
    out = device(seed_install + b"$hp")
    assert out[0] == ("bad_command", b">in")
    assert out[-1] == HomePosition()
    assert all(isinstance(item, tuple) for item in out[:-1])


# ------------------------------------------------------------------------------ encoding


@pytest.mark.parametrize(
    ("command", "wire"),
    [
        (SetAngle(10, 900), b"$AN0a384"),
        (SetAngle(0, -1), b"$AN00fff"),
        (SetAngle(23, -900), b"$AN17c7c"),
        (SetAngleDiff(4, -100), b"$AD04f9c"),
        (SetAngleDiff(4, -1800), b"$AD048f8"),
        (PlayMotion(4), b"$PM04"),
        (StopMotion(), b"$SM"),
        (HomePosition(), b"$HP"),
        (PushMotion(10, 3), b"#PU0a03"),
        (PushMotion(89, 0), b"#PU5900"),
        (PopMotion(), b"#PO"),
        (ResetInterpreter(), b"#RI"),
        (SetHome(0, 100), b">HO00064"),
        (SetMax(0, 100), b">MA00064"),
        (SetMin(10, -1), b">MI0afff"),
        (ResetJointSettings(), b">JS"),
        (GetJointSettings(), b"<JS"),
        (GetMotion(89), b"<MO59"),
        (GetVersion(), b"<VI"),
    ],
)
def test_encode(command: Command, wire: bytes) -> None:
    assert PlenCodec(Role.HOST).send(command) == wire
    assert device(wire) == [command]
    assert device(wire.lower()) == [command]


def test_motion_header_is_35_characters() -> None:
    header = MotionHeader(0, "Test", 2)
    wire = b">MH00Test                0000000000002"
    assert encode_command(header) == wire
    assert len(wire) == 3 + 35
    looped = MotionHeader(
        5,
        "Walk",
        4,
        use_loop=True,
        loop_begin=1,
        loop_end=3,
        loop_count=255,
        use_jump=True,
        jump_slot=6,
    )
    #        slot name(20)              L  b  e  c J  s X  n
    wire2 = b">MH05Walk                " + b"10103ff106004"
    assert encode_command(looped) == wire2
    assert device(wire, wire2) == [header, looped]


def test_motion_header_name_is_free_text() -> None:
    # The firmware skips the hex check for >MH: a '$' in the name is just a name character.
    header = MotionHeader(1, "A$B #<x>", 1)
    wire = encode_command(header)
    assert wire == b">MH01A$B #<x>            0000000000001"
    assert device(wire + b"$sm") == [header, StopMotion()]


def test_motion_header_flags_read_like_the_firmware() -> None:
    # Anything but '0' sets a flag.
    wire = b">MH00Test                2000000a00001"
    (header,) = device(wire)
    assert isinstance(header, MotionHeader)
    assert header.use_loop is True
    assert header.use_jump is True
    assert header.jump_slot == 0
    assert header.use_extra is False


def test_motion_frame_is_104_characters() -> None:
    # The seed's frame: 100 ms, even joints 0, odd joints -1.
    frame = MotionFrame(0, 0, 100, (0, -1) * 12)
    wire = b">MF00000064" + b"0000ffff" * 12
    assert encode_command(frame) == wire
    assert len(wire) == 3 + 104
    assert device(wire) == [frame]
    extremes = MotionFrame(89, 19, 65535, (-32768, 32767) * 12)
    wire2 = b">MF5913ffff" + b"80007fff" * 12
    assert encode_command(extremes) == wire2
    assert device(wire2.upper()) == [extremes]


def test_twelve_bit_twos_complement() -> None:
    assert device(b"$ad00f9c$ad00fff$ad00001$ad007ff$ad00800") == [
        SetAngleDiff(0, -100),
        SetAngleDiff(0, -1),
        SetAngleDiff(0, 1),
        SetAngleDiff(0, 1800),  # 2047, clamped
        SetAngleDiff(0, -1800),  # -2048, clamped
    ]
    assert device(b"$an00c7c$an00384") == [SetAngle(0, -900), SetAngle(0, 900)]


def test_every_command_round_trips() -> None:
    commands: list[Command] = [command for _, command in SEED_EXAMPLES] + [
        MotionHeader(12, "Bow", 3, use_loop=True, loop_end=2, loop_count=255),
        MotionFrame(12, 2, 1000, tuple(range(-12, 12))),
        PushMotion(0, 0),
        SetAngleDiff(23, 1800),
    ]
    host_codec = PlenCodec(Role.HOST)
    stream = b"".join(host_codec.send(command) for command in commands)
    assert device(stream) == commands
    assert device(*split(stream, 1)) == commands
    assert device(*split(stream, 13)) == commands


def test_roles_refuse_the_other_sides_messages() -> None:
    with pytest.raises(LocalProtocolError, match="does not send replies"):
        PlenCodec(Role.HOST).send(VersionReply())
    with pytest.raises(LocalProtocolError, match="not a PLEN2 reply"):
        PlenCodec(Role.DEVICE).send(GetVersion())
    with pytest.raises(LocalProtocolError, match="not a PLEN2 command"):
        PlenCodec(Role.HOST).send("$HP")
    with pytest.raises(ValueError, match="max_reply_bytes"):
        PlenCodec(Role.HOST, max_reply_bytes=1)


# --------------------------------------------------------------------- device-side parsing


def test_case_insensitive_commands_but_exact_headers() -> None:
    assert device(b"$An0A3E8$aN0a3e8$MP05$ms#Pu0A03") == [
        SetAngle(10, 900),
        SetAngle(10, 900),
        PlayMotion(5),
        StopMotion(),
        PushMotion(10, 3),
    ]
    # '%' is not a header: the whole run up to the next header is one garbage fault.
    assert device(b"%an0a3e8$hp") == [("garbage", b"%an0a3e8"), HomePosition()]


def test_crlf_between_commands_is_dropped_silently() -> None:
    codec = PlenCodec(Role.DEVICE)
    assert feed(codec, b"$hp\r\n$sm\n\r\n<vi\r\n") == [HomePosition(), StopMotion(), GetVersion()]
    assert not codec.stats.faults
    assert codec.stats.dropped_bytes == 0


def test_bad_byte_mid_command_resets_the_parser() -> None:
    codec = PlenCodec(Role.DEVICE)
    # Like the firmware, all 5 argument characters are read before they are checked.
    assert feed(codec, b"$an0aXe8$hp") == [("bad_argument", b"$an0aXe8"), HomePosition()]
    assert codec.stats.faults == {"bad_argument": 1}
    assert codec.stats.dropped_bytes == 8
    assert codec.stats.messages == 1


def test_crlf_inside_a_command_corrupts_it() -> None:
    assert device(b"$an0a\r\n3e8$hp") == [
        ("bad_argument", b"$an0a\r\n3"),
        ("garbage", b"e8"),
        HomePosition(),
    ]


def test_truncated_command_swallows_the_next_like_the_firmware() -> None:
    # "$an0" then "$hp": the argument field takes "0$hp" + the next byte.
    assert device(b"$an0$hp$sm$vi") == [
        ("bad_argument", b"$an0$hp$"),
        ("garbage", b"sm"),
        ("bad_command", b"$vi"),
    ]


def test_unknown_commands() -> None:
    assert device(b"$xx$js>vi<hp$hp") == [
        ("bad_command", b"$xx"),
        ("bad_command", b"$js"),
        ("bad_command", b">vi"),
        ("bad_command", b"<hp"),
        HomePosition(),
    ]


def test_out_of_range_values_are_faults() -> None:
    codec = PlenCodec(Role.DEVICE)
    out = feed(
        codec,
        b"$an183e8"  # joint 24
        b"$pm5a"  # slot 90
        b">ho0a3e8"  # home 1000: the firmware ignores it
        b">MH00Test                0000000000000"  # 0 frames
        b">MF00000010" + b"0000" * 24 + b"$hp",  # 16 ms transition
    )
    assert [item[0] for item in out[:-1]] == ["out_of_range"] * 5  # type: ignore[index]
    assert out[-1] == HomePosition()
    assert codec.stats.faults == {"out_of_range": 5}


def test_motion_header_numbers_are_read_as_the_firmware_reads_any_byte() -> None:
    # the firmware checks nothing in >MH: hexbytes2uint16 reads 'g' as 103 - 87 = 16
    header = device(b">MH0gTest                0000000000001")[0]
    assert isinstance(header, MotionHeader)
    assert (header.slot, header.name, header.frame_length) == (16, "Test", 1)
    out = device(b'>MH00Te"t                0000000000001')
    assert out[0][0] == "bad_argument"  # type: ignore[index]


def test_a_nul_ends_the_firmwares_hex_check_of_arguments() -> None:
    # HexStringParser stops at a NUL; the handler then reads the NUL as 0
    assert device(b"$AN0\x00384") == [SetAngle(0, 900)]
    assert device(b"$AN\x000384")[0][0] == "bad_argument"  # type: ignore[index]


def test_partial_command_waits_and_reset_abandons_it() -> None:
    codec = PlenCodec(Role.DEVICE)
    assert feed(codec, b">MF0000") == []
    assert codec.in_progress
    assert codec.pending_bytes() == 7
    assert codec.reset() == 7
    assert codec.stats.faults == {"abandoned": 1}
    assert not codec.in_progress
    assert feed(codec, b"$hp") == [HomePosition()]


def test_garbage_run_is_reported_when_it_ends() -> None:
    codec = PlenCodec(Role.DEVICE)
    assert feed(codec, b"abc", b"def") == []
    assert not codec.in_progress
    assert feed(codec, b"\r\n") == [("garbage", b"abcdef")]
    assert feed(codec, b"xyz") == []
    assert codec.reset() == 3
    assert codec.stats.faults == {"garbage": 2}
    assert codec.stats.dropped_bytes == 9


# ------------------------------------------------------------------------ replies (host)

VERSION_WIRE = (
    b'{\r\n\t"device": "PLEN2",\r\n\t"codename": "Cytisus",\r\n\t"version": "1.4.2"\r\n}\r\n'
)


def joint_settings_wire() -> bytes:
    """A <JS dump written out by hand in the firmware's format."""
    homes = [-200, 50, 375, 250, -470, -220, 500, 200, 220, 0, 0, 0]
    homes += [-value for value in homes[:9]] + [0, 0, 0]
    entries = [
        f'\t{{\r\n\t\t"@device": {joint},\r\n\t\t"max": 900,\r\n\t\t"min": -900,\r\n'
        f'\t\t"home": {home}\r\n\t}}'
        for joint, home in enumerate(homes)
    ]
    return ("[\r\n" + ",\r\n".join(entries) + "\r\n]\r\n").encode()


def motion_wire(*, with_codes: bool) -> bytes:
    """A 2-frame <MO dump written out by hand in the firmware's format."""
    codes = (
        '\t\t{\r\n\t\t\t"method": "loop",\r\n\t\t\t"arguments": [0, 1, 255]\r\n\t\t},\r\n'
        '\t\t{\r\n\t\t\t"method": "jump",\r\n\t\t\t"arguments": [4]\r\n\t\t}\r\n'
        if with_codes
        else ""
    )
    frames = []
    for index, (time_ms, value) in enumerate([(100, 5), (200, -5)]):
        outputs = ",\r\n".join(
            f'\t\t\t\t{{\r\n\t\t\t\t\t"device": {joint},\r\n'
            f'\t\t\t\t\t"value": {value}\r\n\t\t\t\t}}'
            for joint in range(24)
        )
        frames.append(
            f'\t\t{{\r\n\t\t\t"@index": {index},\r\n\t\t\t"transition_time_ms": {time_ms},\r\n'
            f'\t\t\t"outputs": [\r\n{outputs}\r\n\t\t\t]\r\n\t\t}}'
        )
    text = (
        '{\r\n\t"slot": 3,\r\n\t"name": "Bow                 ",\r\n\t"@frame_length": 2,\r\n'
        f'\t"codes": [\r\n{codes}\t],\r\n'
        '\t"frames": [\r\n' + ",\r\n".join(frames) + "\r\n\t]\r\n}\r\n"
    )
    return text.encode()


MOTION = MotionReply(
    slot=3,
    name="Bow",
    frames=(MotionReplyFrame(0, 100, (5,) * 24), MotionReplyFrame(1, 200, (-5,) * 24)),
    loop=LoopCode(0, 1, 255),
    jump=JumpCode(4),
)


def test_device_encodes_replies_like_the_firmware() -> None:
    codec = PlenCodec(Role.DEVICE)
    assert codec.send(VersionReply()) == VERSION_WIRE
    assert codec.send(factory_joint_settings()) == joint_settings_wire()
    assert codec.send(MOTION) == motion_wire(with_codes=True)
    assert b"\t" in codec.send(MOTION) and b"\r\n" in codec.send(MOTION)
    assert encode_reply(MotionReply(3, "Bow", MOTION.frames)) == motion_wire(with_codes=False)


@pytest.mark.parametrize("size", [1, 2, 3, 7, 64, 1000, 100_000])
def test_host_decodes_the_three_replies_in_any_chunks(size: int) -> None:
    stream = VERSION_WIRE + joint_settings_wire() + motion_wire(with_codes=True)
    codec = PlenCodec(Role.HOST)
    assert feed(codec, *split(stream, size)) == [VersionReply(), factory_joint_settings(), MOTION]
    assert codec.pending_bytes() == 0
    assert not codec.in_progress
    assert not codec.stats.faults


def test_motion_without_codes() -> None:
    assert host(motion_wire(with_codes=False)) == [MotionReply(3, "Bow", MOTION.frames)]


def test_seed_reply_forms_are_accepted() -> None:
    # The seed's <JS has no "@device" and uses spaces; entries are in joint order.
    entry = '    {\n        "max": 900,\n        "min": -900,\n        "home": 0\n    }'
    seed_js = ("[\n" + ",\n".join([entry] * 24) + "\n]").encode()
    (reply,) = host(seed_js)
    assert isinstance(reply, JointSettingsReply)
    assert [item.joint for item in reply.joints] == list(range(24))
    # Older firmware's code keys, and device names in outputs.
    older = {
        "slot": 1,
        "name": "x",
        "codes": [{"func": "jump", "args": [2]}],
        "frames": [
            {
                "transition_time_ms": 64,
                "outputs": [{"device": "left_knee_pitch", "value": 30}],
            }
        ],
    }
    offsets = [0] * 24
    offsets[6] = 30
    assert reply_from_json(older) == MotionReply(
        1, "x", (MotionReplyFrame(0, 64, tuple(offsets)),), jump=JumpCode(2)
    )


def test_strings_with_brackets_and_escapes() -> None:
    wire = b'{"device": "PL}EN]2", "codename": "x{[\\"", "version": "1\\\\"}'
    assert host(*split(wire, 1)) == [VersionReply("PL}EN]2", 'x{["', "1\\")]


def test_garbage_between_replies() -> None:
    codec = PlenCodec(Role.HOST)
    out = feed(codec, b"\r\nboot!" + VERSION_WIRE + b"}]x" + VERSION_WIRE)
    assert out == [("garbage", b"boot!"), VersionReply(), ("garbage", b"}]x"), VersionReply()]
    assert codec.stats.faults == {"garbage": 2}
    assert codec.stats.dropped_bytes == 8


def test_bad_json_and_bad_replies() -> None:
    codec = PlenCodec(Role.HOST)
    out = feed(
        codec,
        b'{"device": }'
        b'{"nothing": 1}'
        b"[1, 2]"
        b'{"device": "PLEN2", "codename": "C", "version": NaN}'
        b'{"slot": 95, "frames": []}' + VERSION_WIRE,
    )
    kinds = [item[0] for item in out[:-1]]  # type: ignore[index]
    assert kinds == ["bad_json", "bad_reply", "bad_reply", "bad_json", "bad_reply"]
    assert out[-1] == VersionReply()


def test_overlong_reply_is_dropped_whole() -> None:
    js = joint_settings_wire()
    for chunks in ([js + VERSION_WIRE], split(js + VERSION_WIRE, 5)):
        codec = PlenCodec(Role.HOST, max_reply_bytes=200)
        out = feed(codec, *chunks)
        assert out[0] == ("overlong", js[:FAULT_SAMPLE_BYTES])  # the error keeps the start
        assert out[1:] == [VersionReply()]
        assert codec.stats.faults == {"overlong": 1}
        assert codec.stats.dropped_bytes == len(js.rstrip())


def test_deep_nesting_is_refused() -> None:
    codec = PlenCodec(Role.HOST)
    out = feed(codec, b"[" * 40 + b"]" * 40 + VERSION_WIRE)
    assert out[0] == ("bad_json", b"[" * 17)
    assert out[1:] == [VersionReply()]
    assert codec.stats.dropped_bytes == 80


def test_reset_abandons_a_partial_reply() -> None:
    codec = PlenCodec(Role.HOST)
    partial = motion_wire(with_codes=True)[:500]
    assert feed(codec, partial) == []
    assert codec.in_progress
    assert codec.pending_bytes() == 500
    assert codec.reset() == 500
    assert codec.stats.faults == {"abandoned": 1}
    assert not codec.in_progress and codec.pending_bytes() == 0
    assert feed(codec, VERSION_WIRE) == [VersionReply()]


def test_reply_round_trips_device_to_host() -> None:
    replies = [VersionReply("PLEN2", 'odd "name"', "9"), factory_joint_settings(), MOTION]
    device_codec = PlenCodec(Role.DEVICE)
    stream = b"".join(device_codec.send(reply) for reply in replies)
    assert host(*split(stream, 11)) == replies


# ----------------------------------------------------------------------- motion files

BOW_FILE = {
    "slot": 44,
    "name": "Bow",
    "codes": [],
    "frames": [
        {
            "transition_time_ms": 300,
            "outputs": [
                {"device": "left_shoulder_pitch", "value": -200},
                {"device": "right_shoulder_pitch", "value": 200},
            ],
            "stop_flag": 0,
        },
        {
            "transition_time_ms": 500,
            "outputs": [{"device": "left_knee_pitch", "value": 100}],
        },
    ],
}


def test_motion_from_json_carries_values_over() -> None:
    header, frames = motion_from_json(BOW_FILE)
    assert header == MotionHeader(44, "Bow", 2)
    first = [0] * 24
    first[0], first[12] = -200, 200
    second = list(first)
    second[6] = 100
    assert frames == [MotionFrame(44, 0, 300, tuple(first)), MotionFrame(44, 1, 500, tuple(second))]
    stream = b"".join(encode_command(command) for command in (header, *frames))
    assert device(stream) == [header, *frames]


def test_motion_json_round_trip_with_codes() -> None:
    looped = {
        **BOW_FILE,
        "codes": [
            {"method": "loop", "arguments": [0, 1, 255]},
            {"method": "jump", "arguments": [45]},
        ],
    }
    header, frames = motion_from_json(looped)
    assert header.use_loop and header.loop_count == 255 and header.loop_end == 1
    assert header.use_jump and header.jump_slot == 45
    as_json = motion_to_json(header, frames)
    assert json.loads(json.dumps(as_json)) == as_json
    assert motion_from_json(as_json) == (header, frames)
    # An unused joint with a value is written by id, which reads back too.
    odd = MotionFrame(44, 0, 300, (0,) * 9 + (7,) + (0,) * 14)
    odd_json = motion_to_json(MotionHeader(44, "Odd", 1), [odd])
    assert motion_from_json(odd_json) == (MotionHeader(44, "Odd", 1), [odd])


def test_motion_from_json_errors() -> None:
    with pytest.raises(LocalProtocolError, match="unknown PLEN2 joint"):
        outputs = [{"device": "tail", "value": 1}]
        motion_from_json({**BOW_FILE, "frames": [{"transition_time_ms": 300, "outputs": outputs}]})
    with pytest.raises(LocalProtocolError, match="frame_length"):
        motion_from_json({**BOW_FILE, "frames": []})
    with pytest.raises(LocalProtocolError, match="transition_time_ms"):
        motion_from_json({**BOW_FILE, "frames": [{"outputs": []}]})
    with pytest.raises(LocalProtocolError, match="unknown method"):
        motion_from_json({**BOW_FILE, "codes": [{"method": "dance", "arguments": []}]})
    with pytest.raises(LocalProtocolError, match="slot"):
        motion_from_json({**BOW_FILE, "slot": 90})
    with pytest.raises(LocalProtocolError, match="2 frames"):
        motion_to_json(MotionHeader(0, "x", 2), [MotionFrame(0, 0, 100, ZEROS)])


def test_drain_yields_faults_and_keeps_going() -> None:
    codec = PlenCodec(Role.DEVICE)
    codec.receive_data(b"$xx$hp$an0aXe8<vi")
    items = list(drain(codec))
    assert [type(item) for item in items] == [
        RemoteProtocolError,
        HomePosition,
        RemoteProtocolError,
        GetVersion,
    ]
    assert [item.kind for item in items if isinstance(item, RemoteProtocolError)] == [
        "bad_command",
        "bad_argument",
    ]
