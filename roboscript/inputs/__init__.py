"""The input layer: every YAML file roboscript accepts is read here.

Missions, simulator worlds, robot profiles and teacher test specs share:

* :mod:`roboscript.inputs.source`: safe YAML with a position on every value (the package's
  only user of ``yaml``), and :class:`~roboscript.inputs.source.Location`, the one location
  type;
* :mod:`roboscript.inputs.limits`: what a hostile file is refused for (size, nesting, aliases
  expanded, digits, name length), each limit one named constant;
* :mod:`roboscript.inputs.quantities`: quantities with units (``50 cm``, ``200 ms``), and the
  warning for a bare number;
* :mod:`roboscript.inputs.fields`: one field reader, with one "did you mean", so a mistake
  reads ``file:line:col: error: ...`` the same in every kind of file.

This package imports nothing else of roboscript but :mod:`roboscript.errors`, so worlds and
profiles can read their files without importing missions.
"""
