"""A recording's header: the mission, the robot's geometry and the world, as plain JSON.

Positions are millimetres in the world frame (x east, y north); headings and bearings are
degrees clockwise from north (the simulator's and the world files' convention). A sensor's
``forward_mm``/``right_mm`` place it on the robot, its ``bearing_deg`` is clockwise from the
robot's heading.
"""

from __future__ import annotations

from typing import Any

from roboscript import capabilities as cap
from roboscript.mission.spec import MissionSpec
from roboscript.profiles import RobotProfile
from roboscript.sim.body import BodySpec
from roboscript.sim.simulation import body_spec_for
from roboscript.sim.world import World
from roboscript.transport.ports import WEB_SCHEMES

__all__ = [
    "PRINTED_BEFORE_START",
    "mission_header",
    "port_header",
    "robot_header",
    "run_header",
    "world_header",
]

PRINTED_BEFORE_START = "printed_before_start"
"""The header key of the lines the mission printed before it started (while it loaded: a
Python mission's ``print`` at the top of its file or in its class body), in order."""


def port_header(url: str) -> str:
    """The header's ``port``: the robot's URL (``sim://mirto?...``, ``/dev/ttyUSB0``), or for
    a port chosen in the browser app the page's own words for it (``the robot on the serial
    port you chose``), since its URL (``webserial://1``) names nothing the student saw."""
    if url.partition("://")[0].lower() not in WEB_SCHEMES:
        return url
    # the browser's ports load only for their URLs (a run on one has loaded them already)
    from roboscript.transport.webport import chosen_robot

    return chosen_robot(url) or url


def run_header(
    mission: dict[str, Any],
    profile: RobotProfile,
    *,
    world: World | None,
    seed: int | None,
    pose_source: str,
    tick_s: float,
    body: BodySpec | None = None,
) -> dict[str, Any]:
    """Everything a viewer needs before the first frame (``format``/``version`` come later).

    Args:
        mission: The mission's part (:func:`mission_header`).
        profile: The robot.
        world: The simulated world, or ``None`` on a real robot.
        seed: The simulator seed, or ``None`` on a real robot.
        pose_source: ``"simulator"`` (the true pose), ``"odometry"`` (estimated from the
            wheels) or ``"none"``.
        tick_s: The scheduler's period, seconds.
        body: The simulated body (default: the profile's).
    """
    return {
        "mission": mission,
        "robot": robot_header(profile, body or body_spec_for(profile)),
        "world": world_header(world) if world is not None else None,
        "seed": seed,
        "pose_source": pose_source,
        "tick_s": tick_s,
    }


def mission_header(spec: MissionSpec) -> dict[str, Any]:
    """The mission's name, file, first state, and each state's action and kind."""
    return {
        "name": spec.name,
        "path": spec.path,
        "initial": spec.initial,
        "states": [
            {
                "name": state.name,
                "action": state.action_name,
                "final": state.final,
            }
            for state in spec.states.values()
        ],
    }


def robot_header(profile: RobotProfile, body: BodySpec) -> dict[str, Any]:
    """The robot's name, size and sensors as the simulator places them."""
    sensors: list[dict[str, Any]] = []
    has = profile.capabilities
    ray = {
        "cone_deg": body.range_cone_deg,
        "rays": body.range_rays,
        "max_range_mm": body.range_max_mm,
    }
    if cap.RANGE in has:
        sensors.append(
            {
                "name": "range_mm",
                "kind": "range",
                "forward_mm": body.range_offset_mm,
                "right_mm": 0.0,
                "bearing_deg": 0.0,
                **ray,
            }
        )
    if cap.SIDE_RANGE in has:
        sensors.append(
            {
                "name": "side_range_mm",
                "kind": "range",
                "forward_mm": 0.0,
                "right_mm": body.side_range_offset_mm,
                "bearing_deg": 90.0,
                **ray,
            }
        )
    if cap.LINE in has:
        sensors.append(
            {
                "name": "line",
                "kind": "line",
                "spots_mm": [list(spot) for spot in body.line_sensor_offsets_mm],
                "spot_diameter_mm": body.line_spot_mm,
            }
        )
    if cap.BUMPER in has:
        sensors.append({"name": "bumper", "kind": "bumper", "names": list(body.bumper_names)})
    if cap.HEADING in has:
        sensors.append({"name": "heading_deg", "kind": "heading"})
    return {
        "name": profile.name,
        "protocol": profile.protocol,
        "body_radius_mm": body.body_radius_mm,
        "track_mm": body.track_mm,
        "wheel_diameter_mm": body.wheel_diameter_mm,
        "max_speed_mm_s": profile.max_speed_mm_s,
        "sensors": sensors,
    }


def world_header(world: World) -> dict[str, Any]:
    """Walls and tape as segments ``[x1, y1, x2, y2]``, regions, start pose."""
    regions: list[dict[str, Any]] = []
    for region in world.regions.values():
        item: dict[str, Any] = {"name": region.name, "center": list(region.center)}
        if region.radius_mm is not None:
            item["radius_mm"] = region.radius_mm
        else:
            item["points"] = [list(point) for point in region.points]
        regions.append(item)
    return {
        "name": world.name,
        "walls": [_segment(seg) for seg in world.walls],
        "lines": [
            {"segments": [_segment(seg) for seg in line.segments], "width_mm": line.width_mm}
            for line in world.lines
        ],
        "regions": regions,
        "start": [world.start.x_mm, world.start.y_mm, world.start.heading_deg],
    }


def _segment(seg: Any) -> list[float]:
    return [round(seg.x0, 1), round(seg.y0, 1), round(seg.x1, 1), round(seg.y1, 1)]
