"""Stand-in for the SPIKE App 3 ``hub`` module (only what roboscript's agent uses).

``config["module_tunnel"]`` is the tunnel stand-in, as the public programs that drive a real
hub's tunnel find it; a test takes the key out to model a firmware without it. Every key the
agent looks up is recorded (``hub.config[]``), so a test can prove which form it tried first.
"""

from __future__ import annotations

from typing import Any

import tunnel as _tunnel
from standin_log import record


class _Config(dict[str, Any]):
    def __getitem__(self, key: str) -> Any:
        record("hub.config[]", key)
        return super().__getitem__(key)


config = _Config(module_tunnel=_tunnel)
