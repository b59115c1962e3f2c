"""Byte transports: the only package that imports pyserial.

:func:`open_port` opens anything pyserial opens (``/dev/ttyUSB0``, ``COM3``,
``socket://host:port``, ``rfc2217://``, ``loop://``, ``hwgrep://``) plus roboscript's own
``sim://ROBOT?world=W&seed=N`` (an in-process simulated robot). Ports are opened with
``timeout=0``: reads never block and return what has arrived.
"""

from __future__ import annotations

from roboscript.transport.link import Link, PortLike
from roboscript.transport.ports import open_port

__all__ = ["Link", "PortLike", "open_port"]
