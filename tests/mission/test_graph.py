# ruff: noqa: E501  (golden diagrams are pinned verbatim; graphviz lines run long)
"""The text of ``roboscript graph --format dot|mermaid``: whole diagrams, pinned."""

from __future__ import annotations

from pathlib import Path

import pytest
from helpers import TWICE_PY

from roboscript.mission import load_mission
from roboscript.mission.graph import to_dot, to_mermaid
from roboscript.mission.spec import MissionSpec

ODD_NAMES_YAML = """\
mission: "odd names"
initial: go-out
states:
  go-out:
    do: {drive: {distance: 10 cm}}
    during: [{play_tone: {frequency: 440 Hz, duration: 1 s}}]
    on: {done: "turn 1", failed: bad, timeout: bad}
    when:
      - {if: 'range.distance_cm < 20', goto: bad}
      - {if: 'color.red and range.distance_cm > 5', goto: ok}
    timeout: 2.5 s
  turn 1:
    do: {rotate: {angle: 90 deg}}
    on: {done: ok}
  ok:
    final: success
  bad:
    final: failure
"""


CHOOSE_PY = """\
from roboscript import Drive, Mission, PlayTone, Wait, state


class Choose(Mission):
    go = state(
        Drive(distance_mm=500),
        initial=True,
        during=[PlayTone(frequency_hz=440, duration_s=1)],
        on_done=[("close", "near"), (lambda m: m.elapsed > 1, "slow"), "far"],
        on_failed="lost",
        when=[("state_time >= 1 s", "lost")],
    )
    near = state(Wait(duration_s=0.5), timeout_s=2, on_done="home", on_timeout="lost")
    slow = state(final="failure")
    far = state(final=True)
    home = state(final="success")
    lost = state(final="failure")

    def close(self) -> bool:
        return self.range.distance_cm < 20
"""

ODD_NAMES_DOT = """\
digraph "odd names" {
  rankdir=LR;
  node [fontname="Helvetica"];
  __start [shape=point, label=""];
  go_out [label="go-out\\ndrive + play_tone (timeout 2.5 s)", shape=box, style=rounded];
  turn_1 [label="turn 1\\nrotate", shape=box, style=rounded];
  ok [label="ok", shape=box, style="rounded,filled", fillcolor="#c8f0c8", peripheries=2];
  bad [label="bad", shape=box, style="rounded,filled", fillcolor="#f6c6c6", peripheries=2];
  __start -> go_out;
  go_out -> turn_1 [label="done"];
  turn_1 -> ok [label="done"];
  go_out -> bad [label="failed"];
  go_out -> bad [label="timeout"];
  go_out -> bad [label="when [range.distance_cm < 20]"];
  go_out -> ok [label="when [color.red and range.distance_cm > 5]"];
}
"""

ODD_NAMES_MERMAID = """\
---
title: odd names
---
stateDiagram-v2
  classDef success fill:#c8f0c8,stroke:#2a7a2a
  classDef failure fill:#f6c6c6,stroke:#a02020
  state "go-out" as go_out
  go_out : drive + play_tone (timeout 2.5 s)
  state "turn 1" as turn_1
  turn_1 : rotate
  state "ok" as ok
  state "bad" as bad
  [*] --> go_out
  go_out --> turn_1 : done
  turn_1 --> ok : done
  go_out --> bad : failed
  go_out --> bad : timeout
  go_out --> bad : when [range.distance_cm < 20]
  go_out --> ok : when [color.red and range.distance_cm > 5]
  ok --> [*] : success
  class ok success
  bad --> [*] : failure
  class bad failure
"""

TWICE_DOT = """\
digraph "twice" {
  rankdir=LR;
  node [fontname="Helvetica"];
  __start [shape=point, label=""];
  subgraph cluster_first {
    label="first";
    first____start [shape=point, label=""];
    first__out [label="out\\ndrive", shape=box, style=rounded];
    first__turn [label="turn\\nrotate", shape=box, style=rounded];
    first__home [label="home", shape=box, style="rounded,filled", fillcolor="#c8f0c8", peripheries=2];
    first__oops [label="oops", shape=box, style="rounded,filled", fillcolor="#f6c6c6", peripheries=2];
    first____start -> first__out;
    first__out -> first__turn [label="done"];
    first__turn -> first__home [label="done"];
    first__out -> first__oops [label="failed"];
    first__turn -> first__oops [label="failed"];
  }
  first [label="first", shape=box, style="rounded,dashed"];
  subgraph cluster_second {
    label="second";
    second____start [shape=point, label=""];
    second__out [label="out\\ndrive", shape=box, style=rounded];
    second__turn [label="turn\\nrotate", shape=box, style=rounded];
    second__home [label="home", shape=box, style="rounded,filled", fillcolor="#c8f0c8", peripheries=2];
    second__oops [label="oops", shape=box, style="rounded,filled", fillcolor="#f6c6c6", peripheries=2];
    second____start -> second__out;
    second__out -> second__turn [label="done"];
    second__turn -> second__home [label="done"];
    second__out -> second__oops [label="failed"];
    second__turn -> second__oops [label="failed"];
  }
  second [label="second", shape=box, style="rounded,dashed"];
  happy [label="happy", shape=box, style="rounded,filled", fillcolor="#c8f0c8", peripheries=2];
  sad [label="sad", shape=box, style="rounded,filled", fillcolor="#f6c6c6", peripheries=2];
  __start -> first;
  first -> second [label="done"];
  second -> happy [label="done"];
  first -> sad [label="failed"];
  second -> sad [label="failed"];
}
"""

TWICE_MERMAID = """\
---
title: twice
---
stateDiagram-v2
  classDef success fill:#c8f0c8,stroke:#2a7a2a
  classDef failure fill:#f6c6c6,stroke:#a02020
  state "first" as first {
    state "out" as first__out
    first__out : drive
    state "turn" as first__turn
    first__turn : rotate
    state "home" as first__home
    state "oops" as first__oops
    [*] --> first__out
    first__out --> first__turn : done
    first__turn --> first__home : done
    first__out --> first__oops : failed
    first__turn --> first__oops : failed
    first__home --> [*] : success
    class first__home success
    first__oops --> [*] : failure
    class first__oops failure
  }
  state "second" as second {
    state "out" as second__out
    second__out : drive
    state "turn" as second__turn
    second__turn : rotate
    state "home" as second__home
    state "oops" as second__oops
    [*] --> second__out
    second__out --> second__turn : done
    second__turn --> second__home : done
    second__out --> second__oops : failed
    second__turn --> second__oops : failed
    second__home --> [*] : success
    class second__home success
    second__oops --> [*] : failure
    class second__oops failure
  }
  state "happy" as happy
  state "sad" as sad
  [*] --> first
  first --> second : done
  second --> happy : done
  first --> sad : failed
  second --> sad : failed
  happy --> [*] : success
  class happy success
  sad --> [*] : failure
  class sad failure
"""

CHOOSE_DOT = """\
digraph "choose" {
  rankdir=LR;
  node [fontname="Helvetica"];
  __start [shape=point, label=""];
  go [label="go\\ndrive + play_tone", shape=box, style=rounded];
  near [label="near\\nwait (timeout 2 s)", shape=box, style=rounded];
  slow [label="slow", shape=box, style="rounded,filled", fillcolor="#f6c6c6", peripheries=2];
  far [label="far", shape=box, style="rounded,filled", fillcolor="#c8f0c8", peripheries=2];
  home [label="home", shape=box, style="rounded,filled", fillcolor="#c8f0c8", peripheries=2];
  lost [label="lost", shape=box, style="rounded,filled", fillcolor="#f6c6c6", peripheries=2];
  __start -> go;
  go -> near [label="done [close]"];
  go -> slow [label="done [lambda]"];
  go -> far [label="done"];
  near -> home [label="done"];
  go -> lost [label="failed"];
  go -> lost [label="when [state_time >= 1 s]"];
  near -> lost [label="timeout"];
}
"""

CHOOSE_MERMAID = """\
---
title: choose
---
stateDiagram-v2
  classDef success fill:#c8f0c8,stroke:#2a7a2a
  classDef failure fill:#f6c6c6,stroke:#a02020
  state "go" as go
  go : drive + play_tone
  state "near" as near
  near : wait (timeout 2 s)
  state "slow" as slow
  state "far" as far
  state "home" as home
  state "lost" as lost
  [*] --> go
  go --> near : done [close]
  go --> slow : done [lambda]
  go --> far : done
  near --> home : done
  go --> lost : failed
  go --> lost : when [state_time >= 1 s]
  near --> lost : timeout
  slow --> [*] : failure
  class slow failure
  far --> [*] : success
  class far success
  home --> [*] : success
  class home success
  lost --> [*] : failure
  class lost failure
"""

CLASHING_YAML = """\
mission: "clash: names"
initial: go-out
states:
  go-out:
    do: {drive: {distance: 10 cm}}
    on: {done: go out}
  go out:
    do: {drive: {distance: 10 cm}}
    on: {done: __start}
  __start:
    do: {rotate: {angle: 90 deg}}
    on: {done: say "hi"}
  say "hi":
    do: {rotate: {angle: 90 deg}}
    on: {done: 'back\\slash'}
  'back\\slash':
    do: {rotate: {angle: 90 deg}}
    on: {done: 1st}
  1st:
    final: success
"""

CLASHING_DOT = """\
digraph "clash: names" {
  rankdir=LR;
  node [fontname="Helvetica"];
  __start [shape=point, label=""];
  go_out [label="go-out\\ndrive", shape=box, style=rounded];
  go_out_2 [label="go out\\ndrive", shape=box, style=rounded];
  __start_2 [label="__start\\nrotate", shape=box, style=rounded];
  say__hi_ [label="say \\"hi\\"\\nrotate", shape=box, style=rounded];
  back_slash [label="back\\\\slash\\nrotate", shape=box, style=rounded];
  _1st [label="1st", shape=box, style="rounded,filled", fillcolor="#c8f0c8", peripheries=2];
  __start -> go_out;
  go_out -> go_out_2 [label="done"];
  go_out_2 -> __start_2 [label="done"];
  __start_2 -> say__hi_ [label="done"];
  say__hi_ -> back_slash [label="done"];
  back_slash -> _1st [label="done"];
}
"""

CLASHING_MERMAID = """\
---
title: "clash: names"
---
stateDiagram-v2
  classDef success fill:#c8f0c8,stroke:#2a7a2a
  classDef failure fill:#f6c6c6,stroke:#a02020
  state "go-out" as go_out
  go_out : drive
  state "go out" as go_out_2
  go_out_2 : drive
  state "__start" as __start
  __start : rotate
  state "say #quot;hi#quot;" as say__hi_
  say__hi_ : rotate
  state "back\\slash" as back_slash
  back_slash : rotate
  state "1st" as _1st
  [*] --> go_out
  go_out --> go_out_2 : done
  go_out_2 --> __start : done
  __start --> say__hi_ : done
  say__hi_ --> back_slash : done
  back_slash --> _1st : done
  _1st --> [*] : success
  class _1st success
"""


def _load(tmp_path: Path, name: str, text: str) -> MissionSpec:
    path = tmp_path / name
    path.write_text(text, encoding="utf-8")
    return load_mission(path)[0]


# Names with a space or a dash become identifiers with "_" but keep their text in the label;
# the state's action, its during actions and its timeout are described; every trigger
# (done, failed, timeout, when) labels its edge with its condition's source text.
CASES = [
    ("odd_names.yaml", ODD_NAMES_YAML, ODD_NAMES_DOT, ODD_NAMES_MERMAID),
    # nested machines: drawn inside their state, identifiers prefixed by the outer state
    ("twice.py", TWICE_PY, TWICE_DOT, TWICE_MERMAID),
    # choices tried in order (a method, a lambda, a fallback), final=True drawn as success
    ("choose.py", CHOOSE_PY, CHOOSE_DOT, CHOOSE_MERMAID),
    # names that clash once made identifiers (with each other, the start node, a number) get
    # identifiers of their own; quotes and backslashes show as written; a title with a colon
    # stays one YAML value
    ("clashing.yaml", CLASHING_YAML, CLASHING_DOT, CLASHING_MERMAID),
]


@pytest.mark.parametrize(("name", "source", "dot", "mermaid"), CASES, ids=[c[0] for c in CASES])
def test_the_dot_text_is_the_whole_diagram(
    tmp_path: Path, name: str, source: str, dot: str, mermaid: str
) -> None:
    assert to_dot(_load(tmp_path, name, source)) == dot


@pytest.mark.parametrize(("name", "source", "dot", "mermaid"), CASES, ids=[c[0] for c in CASES])
def test_the_mermaid_text_is_the_whole_diagram(
    tmp_path: Path, name: str, source: str, dot: str, mermaid: str
) -> None:
    assert to_mermaid(_load(tmp_path, name, source)) == mermaid
