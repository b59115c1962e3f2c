"""A protocol is one unit: the descriptor each ``drivers/<protocol>/__init__.py`` exports.

A :class:`ProtocolUnit` names everything roboscript has for one protocol: its codec, its host
driver, its simulated device, the built-in profiles that speak it, and the profiles the
driver contract tests run. The driver registry (:func:`roboscript.drivers.driver_class`), the
simulator's device table (:func:`roboscript.sim.simulation.build_device`) and the contract
tests' parameters are all derived from the units, so adding a protocol is one folder and one
line in :data:`roboscript.drivers.UNITS`.

The code is named by *reference* (``"module:attribute"`` strings), imported only when asked
for: importing a unit imports nothing of its protocol, so a codec never pulls in pyserial, and
the simulator, which asks a unit only for its device, never imports a host driver. This module
uses the standard library only.
"""

from __future__ import annotations

import importlib
from dataclasses import dataclass
from typing import Any

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
            <roboscript.profiles.RobotProfile.protocol>` (``"asip"``).
        codec: Reference to the codec factory ``(role, profile) -> codec``: the protocol's
            sans-IO codec (:class:`roboscript.codec.Codec`) in either role, set up from the
            profile's options.
        driver: Reference to the host driver class (a :class:`roboscript.drivers.base.Driver`).
        device: Reference to the simulated device factory ``(profile) -> (body) -> device``:
            it checks the profile's options at once (before any body exists, so a bad option
            fails like a bad profile), then builds a :class:`roboscript.sim.device.SimDevice`
            on a body.
        profiles: The built-in profiles (:data:`roboscript.profiles.BUILTIN_PROFILES`) that
            speak this protocol.
        contract: The profiles the driver contract tests run.
    """

    name: str
    codec: str
    driver: str
    device: str
    profiles: tuple[str, ...]
    contract: ContractCases = ContractCases()

    def __post_init__(self) -> None:
        for field_name in ("codec", "driver", "device"):
            reference = getattr(self, field_name)
            module_name, sep, attribute = reference.partition(":")
            if not sep or not module_name or not attribute:
                raise ValueError(
                    f"protocol {self.name}: {field_name} must be 'package.module:attribute', "
                    f"not {reference!r}"
                )
        listed = set(self.profiles)
        contract = self.contract
        cases = (*contract.wheeled, *contract.walking, *contract.open_loop)
        stray = [p for p in cases if p not in listed]
        if stray:
            raise ValueError(
                f"protocol {self.name}: contract profiles {stray} are not among its profiles"
            )

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
