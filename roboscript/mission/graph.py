"""Diagrams of a mission, drawn from the machine the runner really builds.

``roboscript graph MISSION`` prints mermaid (``stateDiagram-v2``, rendered by GitHub,
GitLab and most Markdown tools, no graphviz needed) or dot. Transitions are read from the
runner's ``transitions`` machine, so the diagram shows exactly what runs: each edge is labelled
with its trigger (``done``, ``failed``, ``timeout``, or ``when`` for a condition checked every
tick) and its condition; nested states are drawn inside their state; final states lead to the
end marker, coloured by outcome.
"""

from __future__ import annotations

import json
import re
from collections.abc import Iterator

from roboscript.mission.runner import MissionRunner
from roboscript.mission.spec import MissionSpec

__all__ = ["to_dot", "to_mermaid"]

_TRIGGER_LABEL = {"check": "when"}


def _edges(spec: MissionSpec) -> Iterator[tuple[str, str, str]]:
    """(source, destination, label) for every transition of the real machine, in order."""
    machine = MissionRunner(spec, {})._machine
    for trigger, event in machine.events.items():
        for source, transitions in event.transitions.items():
            for transition in transitions:
                label = _TRIGGER_LABEL.get(trigger, trigger)
                conditions = [
                    getattr(c.func, "__name__", str(c.func)) for c in transition.conditions
                ]
                if conditions:
                    label += f" [{' and '.join(conditions)}]"
                yield source, str(transition.dest), label


class _Idents:
    """One identifier per state of a diagram, each used once.

    A state's identifier is its name (after its outer state's identifier and ``__``) with
    every character that is not a letter, a digit or ``_`` made ``_``. Two states whose names
    differ only there (``go-out`` and ``go out``), or a state named like the start node, would
    otherwise be drawn as one: a later one gets ``_2``, ``_3``, ...
    """

    def __init__(self) -> None:
        self._by_key: dict[tuple[str, str], str] = {}
        self._used: set[str] = set()

    def __call__(self, prefix: str, name: str) -> str:
        """The identifier of state ``name`` of the machine whose identifiers start ``prefix``."""
        return self._claim((prefix, name), f"{prefix}{name}")

    def start(self, prefix: str) -> str:
        """The identifier of the start node of the machine whose identifiers start ``prefix``."""
        return self._claim((prefix, ""), f"{prefix}__start")  # no state is named ""

    def _claim(self, key: tuple[str, str], text: str) -> str:
        ident = self._by_key.get(key)
        if ident is None:
            base = re.sub(r"\W", "_", text)
            if base[:1].isdigit():  # an identifier that starts with a digit is a number
                base = f"_{base}"
            ident, n = base, 1
            while ident in self._used:
                n += 1
                ident = f"{base}_{n}"
            self._by_key[key] = ident
            self._used.add(ident)
        return ident


def _dot_text(text: str) -> str:
    """``text`` inside a dot double-quoted string, shown as written."""
    return text.replace("\\", "\\\\").replace('"', '\\"').replace("\n", "\\n")


def _mermaid_text(text: str) -> str:
    """``text`` inside a mermaid double-quoted name, shown as written."""
    return text.replace('"', "#quot;").replace("\n", " ")


def _mermaid_title(name: str) -> str:
    """A mission's name as the YAML value of the diagram's ``title``."""
    if re.fullmatch(r"\w[\w .-]*", name) and not name.endswith(" "):
        return name
    return json.dumps(name, ensure_ascii=False)


def _describe(spec: MissionSpec, name: str) -> str:
    state = spec.states[name]
    if state.action is None or state.action.inner is not None:
        return ""
    parts = [state.action.name]
    for extra in state.during:
        parts.append(f"+ {extra.name}")
    if state.timeout_s is not None:
        parts.append(f"(timeout {state.timeout_s:g} s)")
    return " ".join(parts)


def _mermaid_body(spec: MissionSpec, prefix: str, indent: str, _ident: _Idents) -> list[str]:
    lines: list[str] = []
    for name in spec.states:
        _ident(prefix, name)  # every state of this machine before any nested one's
    for name, state in spec.states.items():
        ident = _ident(prefix, name)
        inner = state.action.inner if state.action is not None else None
        if inner is not None:
            lines.append(f'{indent}state "{_mermaid_text(name)}" as {ident} {{')
            lines.extend(_mermaid_body(inner, f"{ident}__", indent + "  ", _ident))
            lines.append(f"{indent}}}")
        else:
            lines.append(f'{indent}state "{_mermaid_text(name)}" as {ident}')
            description = _describe(spec, name)
            if description:
                lines.append(f"{indent}{ident} : {description}")
    lines.append(f"{indent}[*] --> {_ident(prefix, spec.initial)}")
    for source, dest, label in _edges(spec):
        lines.append(f"{indent}{_ident(prefix, source)} --> {_ident(prefix, dest)} : {label}")
    for name, state in spec.states.items():
        if state.final:
            lines.append(f"{indent}{_ident(prefix, name)} --> [*] : {state.final}")
            lines.append(f"{indent}class {_ident(prefix, name)} {state.final}")
    return lines


def to_mermaid(spec: MissionSpec) -> str:
    """The mission as a mermaid ``stateDiagram-v2``."""
    lines = [
        "---",
        f"title: {_mermaid_title(spec.name)}",
        "---",
        "stateDiagram-v2",
        "  classDef success fill:#c8f0c8,stroke:#2a7a2a",
        "  classDef failure fill:#f6c6c6,stroke:#a02020",
    ]
    lines.extend(_mermaid_body(spec, "", "  ", _Idents()))
    return "\n".join(lines) + "\n"


def _dot_body(spec: MissionSpec, prefix: str, indent: str, _ident: _Idents) -> list[str]:
    lines: list[str] = []
    start = _ident.start(prefix)
    lines.append(f'{indent}{start} [shape=point, label=""];')
    for name in spec.states:
        _ident(prefix, name)  # every state of this machine before any nested one's
    for name, state in spec.states.items():
        ident = _ident(prefix, name)
        inner = state.action.inner if state.action is not None else None
        if inner is not None:
            lines.append(f"{indent}subgraph cluster_{ident} {{")
            lines.append(f'{indent}  label="{_dot_text(name)}";')
            lines.extend(_dot_body(inner, f"{ident}__", indent + "  ", _ident))
            lines.append(f"{indent}}}")
            lines.append(
                f'{indent}{ident} [label="{_dot_text(name)}", shape=box, style="rounded,dashed"];'
            )
            continue
        description = _describe(spec, name)
        label = _dot_text(name) + (f"\\n{_dot_text(description)}" if description else "")
        style = ""
        if state.final == "success":
            style = ', style="rounded,filled", fillcolor="#c8f0c8", peripheries=2'
        elif state.final == "failure":
            style = ', style="rounded,filled", fillcolor="#f6c6c6", peripheries=2'
        lines.append(f'{indent}{ident} [label="{label}", shape=box{style or ", style=rounded"}];')
    lines.append(f"{indent}{start} -> {_ident(prefix, spec.initial)};")
    for source, dest, label in _edges(spec):
        text = _dot_text(label)
        lines.append(
            f'{indent}{_ident(prefix, source)} -> {_ident(prefix, dest)} [label="{text}"];'
        )
    return lines


def to_dot(spec: MissionSpec) -> str:
    """The mission as a graphviz ``digraph``."""
    lines = [
        f'digraph "{_dot_text(spec.name)}" {{',
        "  rankdir=LR;",
        '  node [fontname="Helvetica"];',
    ]
    lines.extend(_dot_body(spec, "", "  ", _Idents()))
    lines.append("}")
    return "\n".join(lines) + "\n"
