"""The simulator's pyserial URL handler (``sim://``), found by name when such a URL is opened.

It lives with the simulator, not in :mod:`roboscript.transport.urlhandler`, because it builds a
:class:`~roboscript.sim.simulation.Simulation`: the simulator sits above transport, and
transport names this package (:data:`roboscript.transport.ports.HANDLER_PACKAGES`) rather than
importing it.
"""
