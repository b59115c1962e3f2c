"""roboscript: behaviour scripting for educational robots.

Missions (state machines in YAML or Python) run on a single-threaded scheduler and talk to
robots through capabilities; protocol drivers speak ASIP, the LEGO SPIKE Prime hub protocol,
StackMod and PLEN2; a byte-exact simulator stands in for every robot.

Importing the package is cheap: heavy parts load when first used.
"""

from __future__ import annotations

import logging

__version__ = "0.1.0"
__all__ = ["__version__"]

logging.getLogger(__name__).addHandler(logging.NullHandler())
