"""Every bound of ``value_ranges``, in both roles: at the bound a value goes through, one past it
the host counts the line as ``"out_of_range"`` and skips it, and the device refuses to send it.

Each row pairs a wire template with the message it decodes to, for one number field, so a
bound that moved on one side only fails here.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from roboscript.codec import Role, drain
from roboscript.drivers.asip import messages as m
from roboscript.drivers.asip import value_ranges as ranges
from roboscript.drivers.asip.codec import AsipCodec
from roboscript.errors import LocalProtocolError, RemoteProtocolError

SENTINEL = m.BumpEvent((1, 0))
SENTINEL_WIRE = b"@B,e,2,{1,0}\n"


@dataclass(frozen=True)
class Field:
    """One number field: its wire form and message for a value, and its bounds."""

    wire: Callable[[float], str]
    message: Callable[[float], object]
    bounds: tuple[float, float]
    device_sends: bool = True  # False for forms only the seed or older firmware write
    step: float = 1  # the smallest step the wire carries


def _i(value: float) -> int:
    return int(value)


FIELDS = {
    "encoder-delta": Field(
        lambda v: f"@M,e,1,{{{_i(v)}:0}}",
        lambda v: m.EncoderEvent(((_i(v), 0),)),
        ranges.ENCODER_COUNT,
    ),
    "encoder-total": Field(
        lambda v: f"@M,e,1,{{0:{_i(v)}}}",
        lambda v: m.EncoderEvent(((0, _i(v)),)),
        ranges.ENCODER_COUNT,
    ),
    "legacy-encoder-width": Field(
        lambda v: f"@E,e,1,{{{_i(v)}:0}}",
        lambda v: m.LegacyEncoderEvent(((_i(v), 0),)),
        ranges.ENCODER_COUNT,
    ),
    "legacy-encoder-count": Field(
        lambda v: f"@E,e,1,{{0:{_i(v)}}}",
        lambda v: m.LegacyEncoderEvent(((0, _i(v)),)),
        ranges.ENCODER_COUNT,
    ),
    "bump": Field(
        lambda v: f"@B,e,1,{{{_i(v)}}}", lambda v: m.BumpEvent((_i(v),)), ranges.BUMP_LEVEL
    ),
    "ir": Field(
        lambda v: f"@R,e,1,{{{_i(v)}}}", lambda v: m.IrEvent((_i(v),)), ranges.ANALOG_VALUE
    ),
    "analog-channel": Field(
        lambda v: f"@I,a,1,{{{_i(v)}:0}}", lambda v: m.AnalogEvent(((_i(v), 0),)), ranges.BYTE
    ),
    "analog-value": Field(
        lambda v: f"@I,a,1,{{0:{_i(v)}}}",
        lambda v: m.AnalogEvent(((0, _i(v)),)),
        ranges.ANALOG_VALUE,
    ),
    "distance": Field(
        lambda v: f"@D,e,1,{{{_i(v)}}}",
        lambda v: m.DistanceEvent((_i(v),)),
        ranges.DISTANCE_CM,
    ),
    "distance-seed-form": Field(
        lambda v: f"@D,M,{_i(v)}",
        lambda v: m.DistanceEvent((_i(v),)),
        ranges.DISTANCE_CM,
        device_sends=False,
    ),
    "accelerometer": Field(
        lambda v: f"@A,e,3,{{{_i(v)},0,0}}",
        lambda v: m.AccelerometerEvent(_i(v), 0, 0),
        ranges.IMU_AXIS,
    ),
    "gyro": Field(
        lambda v: f"@G,e,3,{{0,{_i(v)},0}}", lambda v: m.GyroEvent(0, _i(v), 0), ranges.IMU_AXIS
    ),
    "heading-axis": Field(
        lambda v: f"@H,e,4,{{0,0,{_i(v)},0}}",
        lambda v: m.HeadingEvent(0, 0, _i(v), 0),
        ranges.IMU_AXIS,
    ),
    "heading-degrees": Field(
        lambda v: f"@H,e,4,{{0,0,0,{_i(v)}}}",
        lambda v: m.HeadingEvent(0, 0, 0, _i(v)),
        ranges.HEADING_DEG,
    ),
    "pressure": Field(
        lambda v: f"@P,e,3,{{{v:.2f},0.00,0.00}}",
        lambda v: m.PressureEvent(v, 0.0, 0.0),
        ranges.PRESSURE_MBAR,
        step=0.01,
    ),
    "temperature": Field(
        lambda v: f"@P,e,3,{{0.00,{v:.2f},0.00}}",
        lambda v: m.PressureEvent(0.0, v, 0.0),
        ranges.TEMPERATURE_C,
        step=0.01,
    ),
    "altitude": Field(
        lambda v: f"@P,e,3,{{0.00,0.00,{v:.2f}}}",
        lambda v: m.PressureEvent(0.0, 0.0, v),
        ranges.ALTITUDE_M,
        step=0.01,
    ),
    "digital-port": Field(
        lambda v: f"@I,d,{_i(v)},0", lambda v: m.DigitalPortEvent(_i(v), 0), ranges.BYTE
    ),
    "digital-mask": Field(
        lambda v: f"@I,d,0,{_i(v):X}",
        lambda v: m.DigitalPortEvent(0, _i(v)),
        ranges.PORT_MASK,
    ),
    "port-map-port": Field(
        lambda v: f"@I,M,1,{{{_i(v)}:0}}", lambda v: m.PortMapReply(((_i(v), 0),)), ranges.BYTE
    ),
    "port-map-mask": Field(
        lambda v: f"@I,M,1,{{0:{_i(v):X}}}",
        lambda v: m.PortMapReply(((0, _i(v)),)),
        ranges.PORT_MASK,
    ),
    "analog-map-pin": Field(
        lambda v: f"@I,m,1,{{{_i(v)}:0}}", lambda v: m.AnalogMapReply(((_i(v), 0),)), ranges.BYTE
    ),
    "analog-map-channel": Field(
        lambda v: f"@I,m,1,{{0:{_i(v)}}}", lambda v: m.AnalogMapReply(((0, _i(v)),)), ranges.BYTE
    ),
    "pin-mode": Field(
        lambda v: f"@I,p,1,{{{_i(v)}}}", lambda v: m.PinModesReply((_i(v),)), ranges.BYTE
    ),
    "capabilities": Field(
        lambda v: f"@I,c,1,{{{_i(v)}}}", lambda v: m.CapabilitiesReply((_i(v),)), ranges.BYTE
    ),
    "version-major": Field(
        lambda v: f"@#,?,{_i(v)},1,chip,20,sketch",
        lambda v: m.VersionReply(_i(v), 1, "chip", 20, "sketch"),
        ranges.BYTE,
    ),
    "version-minor": Field(
        lambda v: f"@#,?,1,{_i(v)},chip,20,sketch",
        lambda v: m.VersionReply(1, _i(v), "chip", 20, "sketch"),
        ranges.BYTE,
    ),
    "version-pins": Field(
        lambda v: f"@#,?,1,1,chip,{_i(v)},sketch",
        lambda v: m.VersionReply(1, 1, "chip", _i(v), "sketch"),
        ranges.BYTE,
    ),
    "pixel-strip": Field(
        lambda v: f"@P,I,{_i(v)},16", lambda v: m.PixelsInfoReply(_i(v), 16), ranges.BYTE
    ),
    "pixel-count": Field(
        lambda v: f"@P,I,0,{_i(v)}", lambda v: m.PixelsInfoReply(0, _i(v)), ranges.PIXEL_COUNT
    ),
    "pixel-count-asip-04": Field(
        lambda v: f"@P,I,{_i(v)}",
        lambda v: m.PixelsInfoReply(0, _i(v)),
        ranges.PIXEL_COUNT,
        device_sends=False,
    ),
    "errno": Field(
        lambda v: f"~X,?,{_i(v)}{{TEXT}}",
        lambda v: m.ErrorReply("X", "?", _i(v), "TEXT"),
        ranges.ERRNO,
    ),
    "errno-seed-form": Field(
        lambda v: f"~X,?,{_i(v)},TEXT",
        lambda v: m.ErrorReply("X", "?", _i(v), "TEXT"),
        ranges.ERRNO,
        device_sends=False,
    ),
}


def _at_bounds(*, sent_only: bool = False) -> list[object]:
    return [
        pytest.param(field, value, id=f"{name}-{which}")
        for name, field in FIELDS.items()
        if field.device_sends or not sent_only
        for which, value in zip(("low", "high"), field.bounds, strict=True)
    ]


def _past_bounds(*, sent_only: bool = False) -> list[object]:
    return [
        pytest.param(field, value, id=f"{name}-{which}")
        for name, field in FIELDS.items()
        if field.device_sends or not sent_only
        for which, value in (
            ("below", field.bounds[0] - field.step),
            ("above", field.bounds[1] + field.step),
        )
    ]


def _decode(wire: bytes) -> tuple[list[object], AsipCodec]:
    host = AsipCodec(Role.HOST)
    host.receive_data(wire + b"\n" + SENTINEL_WIRE)
    return list(drain(host)), host


@pytest.mark.parametrize(("field", "value"), _at_bounds())
def test_host_decodes_a_value_at_its_bound(field: Field, value: float) -> None:
    got, host = _decode(field.wire(value).encode("ascii"))
    assert got == [field.message(value), SENTINEL]
    assert not host.stats.faults


@pytest.mark.parametrize(("field", "value"), _past_bounds())
def test_host_counts_and_skips_a_value_past_its_bound(field: Field, value: float) -> None:
    wire = field.wire(value).encode("ascii")
    got, host = _decode(wire)
    assert len(got) == 2
    assert isinstance(got[0], RemoteProtocolError)
    assert got[0].kind == "out_of_range"
    assert got[1] == SENTINEL
    assert host.stats.faults == {"out_of_range": 1}
    assert host.stats.dropped_bytes == len(wire) + 1
    assert host.stats.messages == 1


@pytest.mark.parametrize(("field", "value"), _at_bounds(sent_only=True))
def test_device_sends_a_value_at_its_bound_in_the_wire_form(field: Field, value: float) -> None:
    wire = AsipCodec(Role.DEVICE).send(field.message(value))
    assert wire == field.wire(value).encode("ascii") + b"\n"


@pytest.mark.parametrize(("field", "value"), _past_bounds(sent_only=True))
def test_device_refuses_to_send_a_value_past_its_bound(field: Field, value: float) -> None:
    with pytest.raises(LocalProtocolError, match="must be in"):
        AsipCodec(Role.DEVICE).send(field.message(value))


@settings(max_examples=300, deadline=None)
@given(
    st.sampled_from(sorted(FIELDS)), st.integers(-(10**300), 10**300) | st.integers(-(2**33), 2**33)
)
def test_the_device_refuses_a_value_exactly_when_the_host_would(name: str, number: int) -> None:
    field = FIELDS[name]
    value = number if field.step == 1 else round(number * field.step, 2)
    low, high = field.bounds
    inside = low <= value <= high
    wire = field.wire(value).encode("ascii")
    got, host = _decode(wire) if len(wire) < 512 else ([None], None)
    if host is not None:
        assert (got[0] == field.message(value)) is inside
        assert host.stats.faults == ({} if inside else {"out_of_range": 1})
    if field.device_sends:
        try:
            sent = AsipCodec(Role.DEVICE).send(field.message(value))
        except LocalProtocolError:
            assert not inside
        else:
            assert inside
            assert sent == wire + b"\n"


@pytest.mark.parametrize("value", [math.nan, math.inf, -math.inf])
def test_pressure_that_is_not_a_number_is_refused_both_ways(value: float) -> None:
    with pytest.raises(LocalProtocolError):
        AsipCodec(Role.DEVICE).send(m.PressureEvent(value, 20.0, 100.0))
    text = {math.inf: "inf", -math.inf: "-inf"}.get(value, "nan")
    got, _ = _decode(f"@P,e,3,{{{text},20.00,100.00}}".encode("ascii"))
    assert isinstance(got[0], RemoteProtocolError)
    assert got[0].kind == "out_of_range"
    assert got[1] == SENTINEL


def test_check_range_names_the_field_and_refuses_nan() -> None:
    ranges.check_range("distance_cm", (0, 5), ranges.DISTANCE_CM)  # no exception
    with pytest.raises(LocalProtocolError, match=r"distance_cm must be in -1\.\.16777, got 16778"):
        ranges.check_range("distance_cm", (0, 16778), ranges.DISTANCE_CM)
    with pytest.raises(LocalProtocolError, match="nan"):
        ranges.check_range("pressure_mbar", (math.nan,), ranges.PRESSURE_MBAR)
