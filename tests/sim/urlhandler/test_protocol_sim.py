"""``sim://`` URLs open an in-process simulated robot through pyserial's URL lookup."""

from __future__ import annotations

import pytest

from roboscript.errors import InputError, LinkError
from roboscript.sim.urlhandler.protocol_sim import Serial, parse_sim_url
from roboscript.sim.world import Pose
from roboscript.transport.ports import open_port


def test_sim_url_carries_world_seed_and_start() -> None:
    assert parse_sim_url("sim://mirto?world=corridor&seed=4&x=10&y=-5&heading=90") == (
        "mirto",
        "corridor",
        4,
        Pose(10.0, -5.0, 90.0),
        {},
    )
    assert parse_sim_url("sim://") == ("mirto", "empty", 1, None, {})
    with pytest.raises(ValueError, match=r"^seed must be a whole number \(got 'four'\)$"):
        parse_sim_url("sim://mirto?seed=four")
    with pytest.raises(ValueError, match=r"^heading must be a finite number \(got 'nan'\)$"):
        parse_sim_url("sim://mirto?heading=nan")


def test_open_port_finds_the_simulators_handler_and_powers_the_device_on() -> None:
    port = open_port("sim://spike-prime?world=corridor&seed=3&x=5&y=0&heading=0")
    assert isinstance(port, Serial)
    assert port.is_open
    assert port.simulation is not None
    assert port.simulation.world.name == "corridor"
    assert port.simulation.body.pose.x_mm == pytest.approx(5.0)
    port.close()


def test_a_bad_number_is_a_link_error_naming_the_url_and_a_bad_robot_or_world_is_input() -> None:
    with pytest.raises(LinkError, match="seed=four"):
        open_port("sim://mirto?seed=four")
    with pytest.raises(InputError, match="no robot called 'no-such-robot'"):
        open_port("sim://no-such-robot")
    with pytest.raises(InputError, match="no-such-world"):
        open_port("sim://mirto?world=no-such-world")


def test_sim_url_reset_makes_a_board_that_resets_when_its_port_opens() -> None:
    assert parse_sim_url("sim://mirto?reset=1")[4] == {"reset_on_connect": True}
    assert parse_sim_url("sim://mirto?reset=0")[4] == {"reset_on_connect": False}
    with pytest.raises(ValueError, match=r"^reset must be 0 or 1 \(got 'yes'\)$"):
        parse_sim_url("sim://mirto?reset=yes")
    port = open_port("sim://mirto?reset=1")
    assert port.simulation is not None
    assert port.simulation.profile.options["reset_on_connect"] is True
    assert port.simulation.in_waiting == 0  # booting: no greeting yet
    port.close()


def test_sim_url_reset_on_a_robot_without_that_option_names_the_robot() -> None:
    with pytest.raises(InputError, match="unknown StackMod option 'reset_on_connect'"):
        open_port("sim://stackmod-rover?reset=1")
