"""Protocol drivers, one folder per protocol (``asip``, ``spike``, ``stackmod``, ``plen``).

Each folder holds ``codec.py`` (sans-IO, both roles, standard library only), ``driver.py`` (the
host side), ``device.py`` (the simulated robot's side) and ``profiles.py`` (its built-in
robots), and its ``__init__.py`` exports one :class:`~roboscript.drivers.unit.ProtocolUnit`,
``PROTOCOL``, that names them. The units are found by looking in this folder
(:func:`discover_units`), so a new protocol is a new folder and nothing else; the built-in
profiles, the driver registry here, the simulator's device table, the protocol recogniser and
the driver contract tests are derived from them. Nothing of a protocol's code is imported
until it is asked for, so importing a codec never pulls in pyserial and the simulator never
imports a host driver.
"""

from __future__ import annotations

import importlib
import pkgutil
from collections.abc import Iterator, Mapping, Sequence
from typing import TYPE_CHECKING

from roboscript.drivers.unit import ContractCases, ProtocolUnit

if TYPE_CHECKING:
    from roboscript.drivers.base import Driver

__all__ = [
    "DRIVERS",
    "UNITS",
    "contract_cases",
    "discover_units",
    "driver_class",
    "protocol_unit",
    "register_unit",
    "units",
    "unregister_unit",
    "usb_hints",
]


def discover_units(folders: Sequence[str] | None = None) -> tuple[ProtocolUnit, ...]:
    """Every protocol unit in a folder of this package: each subpackage's ``PROTOCOL``.

    Args:
        folders: Where to look (default: this package's own ``__path__``, the folders
            ``roboscript.drivers.<name>`` is imported from).

    Returns:
        The units, in :attr:`~roboscript.drivers.unit.ProtocolUnit.listed` order.
    """
    found = []
    for info in pkgutil.iter_modules(list(__path__ if folders is None else folders)):
        if not info.ispkg:
            continue
        # found by name, like any plug-in: the folder is the whole of a protocol
        unit = getattr(importlib.import_module(f"{__name__}.{info.name}"), "PROTOCOL", None)
        if isinstance(unit, ProtocolUnit):
            found.append(unit)
    return tuple(sorted(found, key=lambda unit: (unit.listed, unit.name)))


UNITS: tuple[ProtocolUnit, ...] = discover_units()
"""The built-in protocols: one folder each in this package."""

_REGISTERED: dict[str, ProtocolUnit] = {unit.name: unit for unit in UNITS}


def units() -> tuple[ProtocolUnit, ...]:
    """Every protocol unit known in this process, built-in ones first."""
    return tuple(_REGISTERED.values())


def protocol_unit(protocol: str) -> ProtocolUnit:
    """The unit of ``protocol``.

    Raises:
        NotImplementedError: roboscript has no such protocol.
    """
    try:
        return _REGISTERED[protocol]
    except KeyError:
        raise NotImplementedError(f"roboscript has no driver for {protocol} yet") from None


def register_unit(unit: ProtocolUnit) -> None:
    """Make a protocol known in this process (a plug-in, or a test's fake protocol).

    Raises:
        ValueError: Another unit already has that name.
    """
    known = _REGISTERED.get(unit.name)
    if known is not None and known != unit:
        raise ValueError(f"a protocol called {unit.name} is registered already")
    _REGISTERED[unit.name] = unit


def unregister_unit(name: str) -> None:
    """Forget a protocol registered with :func:`register_unit` (built-in ones stay).

    Raises:
        ValueError: ``name`` is a built-in protocol.
    """
    if any(unit.name == name for unit in UNITS):
        raise ValueError(f"{name} is a built-in protocol")
    _REGISTERED.pop(name, None)


def contract_cases() -> ContractCases:
    """The profiles the driver contract tests run, from every unit, in unit order."""
    known = units()
    return ContractCases(
        wheeled=tuple(profile for unit in known for profile in unit.contract.wheeled),
        walking=tuple(profile for unit in known for profile in unit.contract.walking),
        open_loop=tuple(profile for unit in known for profile in unit.contract.open_loop),
    )


def usb_hints() -> dict[tuple[int, int | None], str]:
    """What a USB-serial port probably is, from every unit's boards: ``(vendor id, product id
    or None for any of the vendor's) -> "Arduino Uno: a MIRTO or another ASIP board (--robot
    mirto)"``; a board several protocols use names each of them."""
    boards: dict[tuple[int, int | None], str] = {}
    robots: dict[tuple[int, int | None], list[str]] = {}
    for unit in units():
        for vendor, product, board in unit.usb:
            boards.setdefault((vendor, product), board)
            robots.setdefault((vendor, product), []).append(
                f"{unit.speakers} (--robot {unit.profile_names[0]})"
            )
    return {key: f"{boards[key]}: {' or '.join(robots[key])}" for key in boards}


class _DriverTable(Mapping[str, tuple[str, str]]):
    """Protocol name -> (module, class) of its host driver, read from the units."""

    def __getitem__(self, protocol: str) -> tuple[str, str]:
        module_name, _, class_name = _REGISTERED[protocol].driver.partition(":")
        return module_name, class_name

    def __iter__(self) -> Iterator[str]:
        return iter(list(_REGISTERED))

    def __len__(self) -> int:
        return len(_REGISTERED)


DRIVERS: Mapping[str, tuple[str, str]] = _DriverTable()
"""Protocol name -> (module, class) of its host driver (derived from the units)."""


def driver_class(protocol: str) -> type[Driver]:
    """Import and return the host driver class of ``protocol``.

    Raises:
        NotImplementedError: roboscript has no driver for that protocol yet.
    """
    cls: type[Driver] = protocol_unit(protocol).driver_class()
    return cls
