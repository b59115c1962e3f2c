"""Keys a beginner writes for the ones a mission has, and what to write instead.

A spelling slip (``stats``) is caught by "did you mean"; these are words from other tools or
from roboscript's own Python form that look nothing like the key meant (``name`` for
``mission``, ``next`` or ``on_done`` for ``on``, ``action`` for ``do``), so the hint names the
key and shows the line to write, with the student's own value where it fits::

    square.yaml:6:5: error: unknown key 'next' in state 'go' (where a state goes next is
    written under 'on:', by outcome: write on: {done: end})

The Python form's ``state()`` gets the same help for its keywords (:func:`meant_in_state_call`).
"""

from __future__ import annotations

from typing import Any

from roboscript.inputs.source import YamlMap

__all__ = ["meant_at_top", "meant_in_state", "meant_in_state_call", "meant_outcome"]

_OUTCOMES = ("done", "failed", "timeout")


_OUTCOME_WORDS = {
    **dict.fromkeys(
        ("finished", "finish", "complete", "completed", "success", "succeeded", "ok", "arrived"),
        "done",
    ),
    **dict.fromkeys(("fail", "failure", "error", "stalled", "stuck", "bumped"), "failed"),
    **dict.fromkeys(("timed_out", "time_out", "timeout_s", "too_long", "time"), "timeout"),
}
"""Words a beginner writes for an action's outcome, and the outcome meant."""


def meant_outcome(word: str) -> str | None:
    """The outcome (``done``, ``failed``, ``timeout``) ``word`` stands for (``finished``:
    ``done``; ``on_success``: ``done``), or ``None`` if it is no known word for one."""
    return _OUTCOME_WORDS.get(word.lower().removeprefix("on_").replace("-", "_").strip())


def _target(value: Any, fallback: str = "NEXT") -> str:
    """The state a wrong key's value names, when it is one plain name."""
    return value.strip() if isinstance(value, str) and value.strip().isidentifier() else fallback


def _routes(value: Any) -> str:
    """``on:``'s value as the student meant it: their own ``{done: end}`` when they wrote one."""
    if isinstance(value, YamlMap) and value and all(key in _OUTCOMES for key in value):
        return "{" + ", ".join(f"{key}: {_target(value[key])}" for key in value) + "}"
    return f"{{done: {_target(value)}}}"


def _action(value: Any) -> str:
    """``do:``'s value as the student meant it: their action's name, when there is one."""
    if isinstance(value, YamlMap) and len(value) == 1:
        return f"{{{next(iter(value))}: {{...}}}}"
    if isinstance(value, str) and value.strip().isidentifier():
        return value.strip()
    return "{drive: {distance: 50 cm}}"


def meant_at_top(key: str, value: Any) -> str | None:
    """The hint for ``key`` written at the top of a mission, or ``None`` if it is no known
    mix-up (then "did you mean" or the list of keys is the hint)."""
    word = key.lower()
    if word in ("name", "title", "mission_name"):
        return f"a mission's name goes under 'mission:': write mission: {_target(value, 'square')}"
    if word in ("start", "first", "start_state", "initial_state", "first_state", "begin"):
        return f"the first state is named under 'initial:': write initial: {_target(value, 'go')}"
    if is_a_state(value):  # `go:` at the left edge, under an empty `states:`
        return f"'{key}' is a state: indent it two spaces, under 'states:'"
    return None


def is_a_state(value: Any) -> bool:
    """True if ``value`` reads as a state (a mapping with ``do:``, ``on:``, ``final:``...)."""
    return isinstance(value, YamlMap) and any(
        key in ("do", "on", "when", "final", "timeout") for key in value
    )


def meant_in_state(key: str, value: Any) -> str | None:
    """The hint for ``key`` written in a state, or ``None`` if it is no known mix-up."""
    word = key.lower()
    if word in ("action", "actions", "run", "command", "task", "does"):
        return f"a state's action goes under 'do:': write do: {_action(value)}"
    if word in _OUTCOMES:  # on: with its outcomes not indented under it
        return (
            f"'{key}' is an outcome: it goes under 'on:', indented two more spaces"
            f" (or write on: {{{word}: {_target(value)}}})"
        )
    outcome = word.removeprefix("on_")
    if word.startswith("on_") and outcome in (*_OUTCOMES, "fail", "failure", "timeout_s"):
        outcome = {"fail": "failed", "failure": "failed", "timeout_s": "timeout"}.get(
            outcome, outcome
        )
        return f"outcomes go under 'on:': write on: {{{outcome}: {_target(value)}}}"
    if word in ("next", "goto", "go_to", "then", "after", "transitions", "transition"):
        return (
            "where a state goes next is written under 'on:', by outcome: "
            f"write on: {_routes(value)}"
        )
    if word in ("if", "condition", "conditions", "until", "while", "check"):
        return (
            "a condition checked while in the state goes under 'when:': "
            'write when: [{if: "range.distance_cm < 20", goto: NEXT}]'
        )
    if word in ("timeout_s", "time_limit", "max_time", "time", "limit"):
        return "a state's time bound is 'timeout:': write timeout: 10 s"
    if word in ("end", "ends", "final_state", "is_final", "outcome", "result", "finish"):
        return "a state that ends the mission says so under 'final:': write final: success"
    return None


def meant_in_state_call(keyword: str) -> str | None:
    """The hint for a keyword ``state()`` does not take, or ``None`` if it is no known mix-up
    (then "did you mean" is the hint)."""
    word = keyword.lower()
    if word in ("do", "actions", "run", "command", "task"):
        return "the action is state()'s first argument: write state(Drive(distance_mm=500), ...)"
    if word in ("next", "goto", "go_to", "then", "after", "transitions", "transition", "on"):
        return 'where a state goes next is named by outcome: write on_done="NEXT"'
    outcome = meant_outcome(word) if word.startswith("on_") else None
    if outcome is not None:  # on_finished, on_success, on_fail, on_error, ...
        return f'write on_{outcome}="NEXT"'
    if word in ("if_", "condition", "conditions", "until", "while_", "check"):
        return 'a condition checked while in the state goes in when: write when=[("cond", "NEXT")]'
    if word in ("end", "ends", "final_state", "is_final", "outcome", "result", "finish"):
        return 'a state that ends the mission says so with final: write final="success"'
    return None
