"""Protocol drivers, one folder per protocol (``asip``, ``spike``, ``stackmod``, ``plen``).

Each folder holds ``codec.py`` (sans-IO, both roles, standard library only), ``driver.py`` (the
host side) and ``device.py`` (the simulated robot's side). Drivers are imported lazily, by
protocol name, so importing a codec never pulls in pyserial.
"""

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from roboscript.drivers.base import Driver

__all__ = ["DRIVERS", "driver_class"]

DRIVERS: dict[str, tuple[str, str]] = {
    "asip": ("roboscript.drivers.asip.driver", "AsipDriver"),
    "stackmod": ("roboscript.drivers.stackmod.driver", "StackModDriver"),
    "spike": ("roboscript.drivers.spike.driver", "SpikeDriver"),
    "plen": ("roboscript.drivers.plen.driver", "PlenDriver"),
}
"""Protocol name -> (module, class) of its host driver."""


def driver_class(protocol: str) -> type[Driver]:
    """Import and return the host driver class of ``protocol``.

    Raises:
        NotImplementedError: roboscript has no driver for that protocol yet.
    """
    try:
        module_name, class_name = DRIVERS[protocol]
    except KeyError:
        raise NotImplementedError(f"roboscript has no driver for {protocol} yet") from None
    cls: type[Driver] = getattr(importlib.import_module(module_name), class_name)
    return cls
