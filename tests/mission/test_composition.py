"""Nested states, parallel, repeat and during, run on the simulated MIRTO."""

from __future__ import annotations

import json
from collections.abc import Callable
from pathlib import Path

from helpers import run_cli

NESTED = """
mission: nested
states:
  patrol:
    do:
      initial: out
      states:
        out:
          do: {drive: {distance: 30 cm}}
          on: {done: back, failed: oops}
        back:
          do: {repeat: {times: 2, do: {rotate: {angle: 90 deg}}}}
          on: {done: home, failed: oops}
        home: {final: success}
        oops: {final: failure}
    during:
      - {play_tone: {frequency: 440 Hz, duration: 1 s}}
    on: {done: tune, failed: sad}
  tune:
    do:
      parallel:
        all:
          - {drive: {distance: 20 cm}}
          - {play_tone: {frequency: 660 Hz, duration: 500 ms}}
    on: {done: happy, failed: sad}
  happy: {final: success}
  sad: {final: failure}
"""


def _run(path: Path) -> dict[str, object]:
    result = run_cli("run", str(path), "--json")
    assert result.returncode in (0, 1), result.stderr
    summary: dict[str, object] = json.loads(result.stdout)
    return summary


def test_nested_states_appear_in_the_timeline_and_compose(
    write_mission: Callable[..., Path],
) -> None:
    summary = _run(write_mission(NESTED))
    assert summary["outcome"] == "success"
    names = [name for _, name in summary["states"]]  # type: ignore[attr-defined]
    assert names == ["patrol", "patrol.out", "patrol.back", "patrol.home", "tune", "happy"]
    sim = summary["sim"]
    assert [t["frequency_hz"] for t in sim["tones"]] == [440.0, 660.0]  # type: ignore[index]
    pose = sim["final_pose"]  # type: ignore[index]
    assert abs(pose["heading_deg"] - 180.0) < 3.0  # two right-angle turns
    assert abs(pose["y_mm"] - 100.0) < 15.0  # 30 cm out, turned round, 20 cm back


def test_inner_failure_reason_reaches_the_outer_mission(
    write_mission: Callable[..., Path],
) -> None:
    # 3 m in a 2 m room: the inner drive stalls against the wall.
    text = NESTED.replace("do: {drive: {distance: 30 cm}}", "do: {drive: {distance: 3 m}}")
    result = run_cli("run", str(write_mission(text)), "--json", "--world", "square-room")
    data = json.loads(result.stdout)
    assert data["outcome"] == "failure"
    assert data["reason"] == (
        "ended in the failure state 'sad' after states failed in state 'patrol': "
        "ended in the failure state 'oops' after drive failed in state 'out': stalled"
    )


def test_parallel_any_ends_with_the_first(write_mission: Callable[..., Path]) -> None:
    path = write_mission(
        "states:\n  both:\n    do:\n      parallel:\n        any:\n"
        "          - {wait: {duration: 1 s}}\n          - {wait: {duration: 5 s}}\n"
        "    on: {done: end}\n  end: {final: success}\n"
    )
    summary = _run(path)
    assert summary["outcome"] == "success"
    assert abs(float(summary["duration_s"]) - 1.0) < 0.05  # type: ignore[arg-type]


def test_mission_file_as_a_state(write_mission: Callable[..., Path]) -> None:
    write_mission(
        "states:\n  hop:\n    do: {drive: {distance: 10 cm}}\n    on: {done: ok, failed: no}\n"
        "  ok: {final: success}\n  no: {final: failure}\n",
        name="hop.yaml",
    )
    outer = write_mission(
        "states:\n  twice:\n    do: {repeat: {times: 2, do: {wait: {duration: 0.1 s}}}}\n"
        "    on: {done: jump}\n  jump:\n    do: {mission: hop.yaml}\n"
        "    on: {done: end, failed: end}\n  end: {final: success}\n",
        name="outer.yaml",
    )
    summary = _run(outer)
    assert [n for _, n in summary["states"]] == ["twice", "jump", "jump.hop", "jump.ok", "end"]  # type: ignore[attr-defined]


def test_a_mission_that_includes_itself_is_refused(write_mission: Callable[..., Path]) -> None:
    path = write_mission(
        "states:\n  loop:\n    do: {mission: self.yaml}\n    on: {done: end}\n"
        "  end: {final: success}\n",
        name="self.yaml",
    )
    result = run_cli("check", str(path))
    assert result.returncode == 2
    assert "'self.yaml' includes itself" in result.stderr


def test_graph_prints_mermaid_from_the_real_machine() -> None:
    result = run_cli("graph", "missions/square.yaml")
    assert result.returncode == 0
    out = result.stdout
    assert out.startswith("---\ntitle: square\n---\nstateDiagram-v2\n")
    assert "  [*] --> side\n" in out
    assert "  beep --> finished : done [visits.side >= 4]\n" in out
    assert "  side --> stuck : when [bumper.any]\n" in out
    assert "  finished --> [*] : success\n" in out


def test_graph_prints_dot_with_nested_clusters(write_mission: Callable[..., Path]) -> None:
    result = run_cli("graph", str(write_mission(NESTED)), "--format", "dot")
    assert result.returncode == 0
    assert result.stdout.startswith('digraph "nested" {')
    assert "subgraph cluster_patrol {" in result.stdout
    assert 'patrol__out -> patrol__back [label="done"];' in result.stdout


def test_a_mission_file_used_by_two_states_is_warned_about_once(
    write_mission: Callable[..., Path],
) -> None:
    write_mission(
        "states:\n  hop:\n    do: {drive: {distance: 10 cm}}\n    on: {done: ok}\n"
        "  ok: {final: success}\n",
        name="hop.yaml",
    )
    outer = write_mission(
        "states:\n  one:\n    do: {mission: hop.yaml}\n    on: {done: two, failed: end}\n"
        "  two:\n    do: {mission: hop.yaml}\n    on: {done: end, failed: end}\n"
        "  end: {final: success}\n",
        name="outer.yaml",
    )
    result = run_cli("check", str(outer))
    assert result.returncode == 0, result.stderr
    warnings = [line for line in result.stderr.splitlines() if "warning:" in line]
    assert len(warnings) == 1 and "hop.yaml:3:10: warning" in warnings[0], result.stderr


REPEATED_INNER = """\
from roboscript import Drive, Mission, Parallel, PlayTone, Repeat, Rotate, state


class Side(Mission):
    go = state(Drive(distance_mm=200), initial=True, on_done="turn", on_failed="stuck")
    turn = state(Rotate(angle_deg=90), on_done="done", on_failed="stuck")
    done = state(final="success")
    stuck = state(final="failure")


class Square(Mission):
    sides = state(Repeat(Side, times=4), initial=True, on_done="tune", on_failed="oops")
    tune = state(
        Parallel([Side, PlayTone(frequency_hz=660, duration_s=0.5)]),
        on_done="home",
        on_failed="oops",
    )
    home = state(final="success")
    oops = state(final="failure")
"""


def test_a_python_repeat_or_parallel_of_an_inner_mission_runs_it_nested(
    write_mission: Callable[..., Path],
) -> None:
    path = write_mission(REPEATED_INNER, "square.py")
    checked = run_cli("check", str(path))
    assert checked.returncode == 0, checked.stdout + checked.stderr
    assert "checked 1 file: 0 with errors" in checked.stderr
    summary = _run(path)
    assert summary["outcome"] == "success"
    names = [name for _, name in summary["states"]]  # type: ignore[attr-defined]
    assert names == [
        "sides",
        *(["sides.go", "sides.turn", "sides.done"] * 4),
        "tune",
        "tune.go",
        "tune.turn",
        "tune.done",
        "home",
    ]
    pose = summary["sim"]["final_pose"]  # type: ignore[index]
    assert abs(pose["heading_deg"] - 90.0) < 5.0  # five right-angle turns


def test_a_mistake_in_a_repeated_inner_mission_is_found_where_it_is_written(
    write_mission: Callable[..., Path],
) -> None:
    path = write_mission(REPEATED_INNER.replace('on_done="done"', 'on_done="dne"'), "square.py")
    checked = run_cli("check", str(path))
    assert checked.returncode == 2
    assert f"{path}:6:48: error: there is no state 'dne' (did you mean 'done'?)" in checked.stderr
