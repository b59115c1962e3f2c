"""A protocol is one unit: the descriptor each ``drivers/<protocol>/__init__.py`` exports.

A :class:`ProtocolUnit` holds everything roboscript has for one protocol: its title, its
codec, its host driver, its simulated device, the built-in profiles that speak it, what
recognises its bytes on a port, and the profiles the driver contract tests run. The units are
found by looking in the ``drivers`` folder (:func:`roboscript.drivers.discover_units`); the
built-in profiles (:mod:`roboscript.profiles`), the driver registry
(:func:`roboscript.drivers.driver_class`), the simulator's device table
(:func:`roboscript.sim.simulation.build_device`), the protocol a port speaks
(:mod:`roboscript.drivers.recognise`) and the contract tests' parameters are all derived from
them, so adding a protocol is one folder.

The code is named by *reference* (``"module:attribute"`` strings), imported only when asked
for: importing a unit imports nothing of its protocol, so a codec never pulls in pyserial, and
the simulator, which asks a unit only for its device, never imports a host driver. This module
uses the standard library only.
"""

from __future__ import annotations

import importlib
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from roboscript.robot_profile import RobotProfile

__all__ = ["ContractCases", "ProtocolUnit", "resolve"]


def resolve(reference: str) -> Any:
    """Import and return the object a ``"package.module:attribute"`` reference names.

    Raises:
        ValueError: The reference has no ``:``.
        ImportError: The module cannot be imported.
        AttributeError: The module has no such attribute.
    """
    module_name, sep, attribute = reference.partition(":")
    if not sep or not module_name or not attribute:
        raise ValueError(f"a reference is 'package.module:attribute', not {reference!r}")
    return getattr(importlib.import_module(module_name), attribute)


@dataclass(frozen=True)
class ContractCases:
    """The profiles ``tests/drivers/test_contract.py`` runs its contracts on.

    Attributes:
        wheeled: Profiles with a ``drive_base``: hold a speed and stop, turn clockwise, beep,
            stop on exit, drive the square mission.
        walking: Profiles with a ``walker``: walk and turn by steps, stop on exit.
        open_loop: Profiles with a ``drive_base`` whose robot answers nothing (the StackMod
            author's firmware): hold a speed and stop, turn clockwise. Nothing can notice
            such a robot falling silent, so the silence and loss contracts do not apply.
    """

    wheeled: tuple[str, ...] = ()
    walking: tuple[str, ...] = ()
    open_loop: tuple[str, ...] = ()


@dataclass(frozen=True)
class ProtocolUnit:
    """One protocol: codec, host driver, simulated device, profiles and contract cases.

    Attributes:
        name: The protocol's name, as in :attr:`RobotProfile.protocol
            <roboscript.robot_profile.RobotProfile.protocol>` (``"asip"``).
        title: How the protocol is named to a user (``"SPIKE hub"``).
        speakers: Who speaks it, for a user told what a port speaks (``"a LEGO SPIKE Prime
            hub"``).
        codec: Reference to the codec factory ``(role, profile) -> codec``: the protocol's
            sans-IO codec (:class:`roboscript.codec.Codec`) in either role, set up from the
            profile's options.
        driver: Reference to the host driver class (a :class:`roboscript.drivers.base.Driver`).
        device: Reference to the simulated device factory ``(profile) -> (body) -> device``:
            it checks the profile's options at once (before any body exists, so a bad option
            fails like a bad profile), then builds a :class:`roboscript.sim.device.SimDevice`
            on a body.
        profiles: The built-in profiles that speak this protocol, the first the one a user
            is told to name (``--robot mirto``).
        contract: The profiles the driver contract tests run.
        proves_nothing: Names of message types any bytes read as (ASIP's free-text
            ``DebugLine``): reading them does not show that a port speaks this protocol.
        listed: Where the unit's robots come in lists (lower first), so that ``roboscript
            robots`` reads the same whatever the folders are called.
        usb: The USB-serial boards its robots are reached through, each ``(vendor id,
            product id or None for any of the vendor's, what the board is)``, so that
            ``roboscript ports`` can say which robot a port may be.
    """

    name: str
    title: str
    speakers: str
    codec: str
    driver: str
    device: str
    profiles: tuple[RobotProfile, ...]
    contract: ContractCases = ContractCases()
    proves_nothing: frozenset[str] = frozenset()
    listed: int = 100
    usb: tuple[tuple[int, int | None, str], ...] = ()

    def __post_init__(self) -> None:
        for field_name in ("codec", "driver", "device"):
            reference = getattr(self, field_name)
            module_name, sep, attribute = reference.partition(":")
            if not sep or not module_name or not attribute:
                raise ValueError(
                    f"protocol {self.name}: {field_name} must be 'package.module:attribute', "
                    f"not {reference!r}"
                )
        listed = set(self.profile_names)
        strays = [p.name for p in self.profiles if p.protocol != self.name]
        if strays or not self.profiles:
            raise ValueError(
                f"protocol {self.name}: its profiles must speak it, and there must be one "
                f"(not: {strays})"
            )
        contract = self.contract
        cases = (*contract.wheeled, *contract.walking, *contract.open_loop)
        stray = [p for p in cases if p not in listed]
        if stray:
            raise ValueError(
                f"protocol {self.name}: contract profiles {stray} are not among its profiles"
            )

    @property
    def profile_names(self) -> tuple[str, ...]:
        """The names of :attr:`profiles`, in order (``("mirto", "asip-basic")``)."""
        return tuple(profile.name for profile in self.profiles)

    def driver_class(self) -> Any:
        """Import and return the host driver class."""
        return resolve(self.driver)

    def device_factory(self) -> Any:
        """Import and return the simulated device factory ``(profile) -> (body) -> device``."""
        return resolve(self.device)

    def codec_factory(self) -> Any:
        """Import and return the codec factory ``(role, profile) -> codec``."""
        return resolve(self.codec)

    def make_codec(self, role: Any, profile: Any) -> Any:
        """This protocol's codec in ``role``, set up for ``profile``."""
        return self.codec_factory()(role, profile)
