"""Why a mission moved from one state to the next: the cause of each transition.

The runner makes one :class:`TransitionCause` each time it enters a state; the terminal
timeline, ``run --json``, the recording (and so the replay page and the notebook viewer) all
show it through :meth:`TransitionCause.text` and :meth:`TransitionCause.to_json`, so they
cannot say different things.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any, Literal

__all__ = ["CauseKind", "TransitionCause"]

CauseKind = Literal["start", "done", "failed", "timeout", "when"]
"""What moved the mission on: ``start`` (the first state), an action's outcome (``done``,
``failed``, ``timeout``: the action's own or the state's ``timeout``), or a ``when``
condition that held."""

_MAX_VALUES = 8  # a condition reads a handful of names; a huge Python one is cut here


def _shown(value: float | bool) -> str:
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int):
        return str(value)
    if math.isinf(value):
        return "nothing seen" if value > 0 else "-inf"
    return f"{value:.1f}"


@dataclass(frozen=True)
class TransitionCause:
    """Why the mission entered a state.

    Attributes:
        kind: See :data:`CauseKind`.
        source: The state left (``None`` for the first state).
        action: The action whose outcome moved the mission on, or ``None``.
        reason: The action's reason (``stalled``, ...) for ``failed`` and an action's own
            ``timeout``, or ``None``.
        condition: The condition that held: a ``when`` condition, or the ``if`` of the
            ``on`` route that was taken; ``None`` when the route had none.
        values: What the condition read to decide, by name (``range.distance_cm``,
            ``visits.side``), in the units of those names; ``inf`` for a range sensor that
            saw nothing.
        timeout_s: The state's timeout, s, when the state timed out.
    """

    kind: CauseKind
    source: str | None = None
    action: str | None = None
    reason: str | None = None
    condition: str | None = None
    values: Mapping[str, float | bool] = field(default_factory=dict)
    timeout_s: float | None = None

    def sentence(self) -> str:
        """The cause on its own, in a student's words: ``drive failed: stalled``."""
        if self.kind == "start":
            return "the mission started"
        if self.kind == "when":
            return f"'{self.condition}' held"
        if self.kind == "timeout" and self.timeout_s is not None:
            return f"the state timed out after {self.timeout_s:g} s"
        text = f"{self.action or 'the action'} {self.kind}"
        if self.reason and self.reason != self.kind:
            text += f": {self.reason}"
        if self.condition:
            text += f", and '{self.condition}' held"
        return text

    def in_state(self) -> str:
        """The cause with the state it happened in, as failure reasons say it:
        ``drive failed in state 'side': stalled``, ``state 'wait' timed out after 5 s``."""
        if self.kind == "when":
            return f"'{self.condition}' held in state '{self.source}'"
        if self.kind == "timeout" and self.timeout_s is not None:
            return f"state '{self.source}' timed out after {self.timeout_s:g} s"
        action = self.action or "the action"
        return f"{action} {self.kind} in state '{self.source}': {self.reason or self.kind}"

    def values_text(self) -> str:
        """What the condition read, ``range.distance_cm = 18.2, bumper.left = true``."""
        return ", ".join(f"{name} = {_shown(value)}" for name, value in self.values.items())

    def text(self) -> str:
        """:meth:`sentence` and the values that decided it: what every view shows."""
        values = self.values_text()
        return f"{self.sentence()} ({values})" if values else self.sentence()

    def to_json(self) -> dict[str, Any]:
        """The cause as the recording and ``run --json`` write it (units as named)."""
        return {
            "kind": self.kind,
            "from": self.source,
            "action": self.action,
            "reason": self.reason,
            "condition": self.condition,
            "values": {
                name: (None if isinstance(v, float) and math.isinf(v) else v)
                for name, v in self.values.items()
            },
            "timeout_s": self.timeout_s,
            "text": self.text(),
        }

    @staticmethod
    def kept_values(reads: Mapping[str, float | bool]) -> dict[str, float | bool]:
        """The first few values a condition read, rounded as shown (a record stays small)."""
        kept: dict[str, float | bool] = {}
        for name, value in list(reads.items())[:_MAX_VALUES]:
            is_number = isinstance(value, float) and not math.isinf(value)
            kept[name] = round(value, 3) if is_number else value
        return kept
