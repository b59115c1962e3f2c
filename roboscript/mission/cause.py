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
from typing import Any, Literal, cast, get_args

__all__ = ["CLAIM_TEXT_CHARS", "CauseKind", "TransitionCause"]

CauseKind = Literal["start", "done", "failed", "timeout", "when"]
"""What moved the mission on: ``start`` (the first state), an action's outcome (``done``,
``failed``, ``timeout``: the action's own or the state's ``timeout``), or a ``when``
condition that held."""

_MAX_VALUES = 8  # a condition reads a handful of names; a huge Python one is cut here

_WHOLE_LIMIT = 2**53  # the largest whole number a float (and a page's script) holds exactly

CLAIM_TEXT_CHARS = 200
"""Longest text (an action, a reason, a condition, a value's name) a claimed cause keeps."""


def _claimed_text(value: object) -> str | None:
    """Untrusted text as a claim keeps it: printable, at most :data:`CLAIM_TEXT_CHARS`."""
    if not isinstance(value, str):
        return None
    clean = "".join(c if c.isprintable() else " " for c in value[: CLAIM_TEXT_CHARS + 1])
    return clean[:CLAIM_TEXT_CHARS] + "…" if len(clean) > CLAIM_TEXT_CHARS else clean


def _claimed_number(value: object) -> float | None:
    """A finite number as it was (a whole number stays whole, as it is shown), else None."""
    if isinstance(value, bool):
        return None
    if isinstance(value, int):  # JSON's whole numbers have no bound: a float's are kept
        return value if abs(value) <= _WHOLE_LIMIT else None
    if isinstance(value, float):
        return value if math.isfinite(value) else None
    return None


def _claimed_values(value: object) -> dict[str, float | bool]:
    if not isinstance(value, Mapping):
        return {}
    kept: dict[str, float | bool] = {}
    for name, read in list(value.items())[:_MAX_VALUES]:
        key = _claimed_text(name)
        if not key:
            continue
        if isinstance(read, bool):
            kept[key] = read
        elif read is None:  # how to_json writes a range sensor that saw nothing
            kept[key] = math.inf
        else:
            number = _claimed_number(read)
            if number is not None:
                kept[key] = number if isinstance(number, int) else round(number, 3)
    return kept


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

    @classmethod
    def from_claim(cls, data: object, *, source: str | None) -> TransitionCause | None:
        """A cause another process says happened (a graded mission's), made safe to show.

        The inverse of :meth:`to_json` for a writer that is not trusted: an unknown ``kind``
        gives ``None``; text is made printable and cut at :data:`CLAIM_TEXT_CHARS`; at most
        a few values are kept, each ``true``/``false`` or a finite number (``null``: nothing
        seen); a ``text`` in ``data`` is ignored, as :meth:`text` is rebuilt from the rest.
        The result is for display only: nothing judges a run on it.

        Args:
            data: The claimed cause (``to_json``'s shape).
            source: The state left, as the caller itself recorded it (never the claim's).
        """
        if not isinstance(data, Mapping):
            return None
        kind = data.get("kind")
        if not isinstance(kind, str) or kind not in get_args(CauseKind):
            return None
        timeout_s = _claimed_number(data.get("timeout_s"))
        return cls(
            cast("CauseKind", kind),
            None if kind == "start" else source,
            action=_claimed_text(data.get("action")),
            reason=_claimed_text(data.get("reason")),
            condition=_claimed_text(data.get("condition")),
            values=_claimed_values(data.get("values")),
            timeout_s=None if timeout_s is None or timeout_s < 0 else timeout_s,
        )

    @staticmethod
    def kept_values(reads: Mapping[str, float | bool]) -> dict[str, float | bool]:
        """The first few values a condition read, rounded as shown (a record stays small)."""
        kept: dict[str, float | bool] = {}
        for name, value in list(reads.items())[:_MAX_VALUES]:
            is_number = isinstance(value, float) and not math.isinf(value)
            kept[name] = round(value, 3) if is_number else value
        return kept
