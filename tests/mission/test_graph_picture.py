"""``roboscript graph --format svg|png``: the state diagram as a picture, a run highlighted."""

from __future__ import annotations

import itertools
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

import pytest
from helpers import MISSIONS, TWICE_PY, run_cli

from roboscript.mission import load_mission
from roboscript.mission.graph import _edges
from roboscript.mission.graph_layout import Diagram, Rect, layout
from roboscript.mission.graph_picture import (
    PictureUnavailableError,
    RunMarks,
    diagram_for,
    to_svg,
    write_png,
)
from roboscript.mission.spec import MissionSpec

SVG = "{http://www.w3.org/2000/svg}"


LOOPS = """
mission: loops
initial: a
states:
  a:
    do: {drive: {distance: 10 cm}}
    on: {done: a, failed: b}
    when:
      - {if: "range.distance_cm < 20", goto: a}
  b:
    do: {wait: {duration: 1 s}}
    on: {done: a, timeout: c}
    timeout: 5 s
  c:
    final: failure
"""


def _mission_files() -> list[Path]:
    return sorted(MISSIONS.glob("*.yaml")) + sorted(MISSIONS.glob("*.py"))


@pytest.fixture
def nested(tmp_path: Path) -> MissionSpec:
    path = tmp_path / "twice.py"
    path.write_text(TWICE_PY, encoding="utf-8")
    return load_mission(path)[0]


@pytest.fixture
def loops(tmp_path: Path) -> MissionSpec:
    path = tmp_path / "loops.yaml"
    path.write_text(LOOPS, encoding="utf-8")
    return load_mission(path)[0]


def _all_edges(spec: MissionSpec, prefix: str = "") -> list[tuple[str, str, str]]:
    """Every transition of the real machine, nested ones included, by full state name."""
    found = [(prefix + a, prefix + b, label) for a, b, label in _edges(spec)]
    for name, state in spec.states.items():
        if state.action is not None and state.action.inner is not None:
            found += _all_edges(state.action.inner, f"{prefix}{name}.")
    return found


def _all_states(spec: MissionSpec, prefix: str = "") -> list[str]:
    found = []
    for name, state in spec.states.items():
        found.append(prefix + name)
        if state.action is not None and state.action.inner is not None:
            found += _all_states(state.action.inner, f"{prefix}{name}.")
    return found


def _parse(svg: str) -> ET.Element:
    return ET.fromstring(svg.encode("utf-8"))


def _groups(root: ET.Element, kind: str) -> list[ET.Element]:
    return [g for g in root.iter(f"{SVG}g") if kind in g.get("class", "").split()]


def _texts(group: ET.Element) -> list[str]:
    return [t.text or "" for t in group.iter(f"{SVG}text")]


# ------------------------------------------------------------------------------- contents


@pytest.mark.parametrize("path", _mission_files(), ids=lambda p: p.name)
def test_svg_parses_and_shows_every_state_and_transition(path: Path) -> None:
    spec, _ = load_mission(path)
    root = _parse(to_svg(spec))
    assert root.tag == f"{SVG}svg"
    states = {g.get("data-state"): _texts(g) for g in _groups(root, "state")}
    assert sorted(states) == sorted(_all_states(spec))
    for name, texts in states.items():
        assert texts[0] == name.rpartition(".")[2]  # the name is drawn, in the box
    edges = [
        (g.get("data-source"), g.get("data-dest"), g.get("data-label"), _texts(g))
        for g in _groups(root, "edge")
        if g.get("data-source") is not None
    ]
    assert sorted(e[:3] for e in edges) == sorted(_all_edges(spec))
    for _, _, label, texts in edges:
        assert texts == [label]  # the label is drawn on its arrow
    starts = [c.get("data-dest") for c in root.iter(f"{SVG}circle")]
    assert starts == [spec.initial]


def test_nested_states_are_drawn_inside_their_state(nested: MissionSpec) -> None:
    root = _parse(to_svg(nested))
    names = {g.get("data-state") for g in _groups(root, "state")}
    assert {"first.out", "first.turn", "second.home", "second.oops"} <= names
    assert {g.get("data-state") for g in _groups(root, "nested")} == {"first", "second"}
    starts = sorted(c.get("data-dest") or "" for c in root.iter(f"{SVG}circle"))
    assert starts == ["first", "first.out", "second.out"]


def test_final_states_are_coloured_by_outcome() -> None:
    spec, _ = load_mission(MISSIONS / "square.yaml")
    root = _parse(to_svg(spec))
    fills = {
        g.get("data-state"): next(g.iter(f"{SVG}rect")).get("fill") for g in _groups(root, "state")
    }
    assert fills["finished"] != fills["stuck"]
    assert fills["finished"] != fills["side"] and fills["stuck"] != fills["side"]
    classes = {g.get("data-state"): g.get("class", "").split() for g in _groups(root, "state")}
    assert "final-success" in classes["finished"]
    assert "final-failure" in classes["stuck"]
    assert not any(c.startswith("final") for c in classes["side"])


def test_student_text_is_escaped(loops: MissionSpec) -> None:
    svg = to_svg(loops)
    root = _parse(svg)  # a '<' in a condition would break the XML if written raw
    labels = [g.get("data-label") for g in _groups(root, "edge")]
    assert "when [range.distance_cm < 20]" in labels
    assert "&lt; 20" in svg


# --------------------------------------------------------------------------------- layout


def _overlap(a: Rect, b: Rect) -> bool:
    return a[0] < b[0] + b[2] and b[0] < a[0] + a[2] and a[1] < b[1] + b[3] and b[1] < a[1] + a[3]


def _inside(inner: Rect, outer: Rect) -> bool:
    return (
        outer[0] <= inner[0]
        and inner[0] + inner[2] <= outer[0] + outer[2]
        and outer[1] <= inner[1]
        and inner[1] + inner[3] <= outer[1] + outer[3]
    )


def _check_layout(diagram: Diagram) -> None:
    canvas = (0.0, 0.0, diagram.width_px, diagram.height_px)
    by_name = {box.name: box for box in diagram.states}
    # Boxes and labels of one level never overlap one another (labels included: they are
    # what a student reads); a nested state's content stays inside it.
    levels: dict[str | None, list[tuple[str, Rect]]] = {}
    for box in diagram.states:
        levels.setdefault(box.parent, []).append((f"state {box.name}", box.rect))
        assert _inside(box.rect, canvas), box.name
        if box.parent is not None:
            assert _inside(box.rect, by_name[box.parent].rect), box.name
    for edge in diagram.edges:
        if edge.label_rect is not None:
            levels.setdefault(edge.parent, []).append((f"label {edge.label}", edge.label_rect))
            assert _inside(edge.label_rect, canvas), edge.label
    for mark in diagram.starts:
        r = mark.radius_px
        dot = (mark.center[0] - r, mark.center[1] - r, 2 * r, 2 * r)
        levels.setdefault(mark.parent, []).append(("start", dot))
    for items in levels.values():
        for (name_a, a), (name_b, b) in itertools.combinations(items, 2):
            assert not _overlap(a, b), f"{name_a} overlaps {name_b}"


@pytest.mark.parametrize("path", _mission_files(), ids=lambda p: p.name)
def test_layout_has_no_overlapping_boxes_or_labels(path: Path) -> None:
    _check_layout(layout(load_mission(path)[0]))


def test_nested_and_looping_layouts_have_no_overlaps(
    nested: MissionSpec, loops: MissionSpec
) -> None:
    _check_layout(layout(nested))
    _check_layout(layout(loops))
    notes = {"first.out": "visited 2 times, first at 0.00 s, a long note indeed"}
    _check_layout(layout(nested, notes))


def test_layout_reads_left_to_right_from_the_start() -> None:
    diagram = layout(load_mission(MISSIONS / "square.yaml")[0])
    x = {box.name: box.rect[0] for box in diagram.states}
    assert diagram.starts[0].center[0] < x["side"] < x["corner"] < x["beep"] < x["finished"]
    arrows = {(e.source, e.dest): e for e in diagram.edges}
    # an arrow ends where its state is: at the left side going forward, the right going back
    forward = arrows[("side", "corner")].curves[-1][3]
    corner = next(b for b in diagram.states if b.name == "corner").rect
    assert forward[0] == pytest.approx(corner[0])
    assert corner[1] <= forward[1] <= corner[1] + corner[3]
    back = arrows[("beep", "side")].curves[-1][3]
    side = next(b for b in diagram.states if b.name == "side").rect
    assert back[0] == pytest.approx(side[0] + side[2])


def test_a_self_loop_is_an_arc_over_its_state(loops: MissionSpec) -> None:
    diagram = layout(loops)
    box = next(b for b in diagram.states if b.name == "a").rect
    loops_ = [e for e in diagram.edges if e.source == e.dest == "a"]
    assert sorted(e.label for e in loops_) == ["done", "when [range.distance_cm < 20]"]
    for edge in loops_:
        start, _, _, end = edge.curves[0]
        assert start[1] == end[1] == box[1]  # leaves and enters the box's top
        assert edge.label_rect is not None and edge.label_rect[1] + edge.label_rect[3] <= box[1]


# ------------------------------------------------------------------------------- the run


SQUARE_RUN = ((0.0, "side"), (3.8, "corner"), (5.7, "beep"), (6.0, "side"), (9.1, "stuck"))


def test_a_run_marks_the_states_it_visited_and_where_it_ended() -> None:
    spec, _ = load_mission(MISSIONS / "square.yaml")
    run = RunMarks(SQUARE_RUN, "failure", "stuck")
    root = _parse(to_svg(spec, run))
    classes = {g.get("data-state"): g.get("class", "").split() for g in _groups(root, "state")}
    visited = {name for name, c in classes.items() if "visited" in c}
    assert visited == {"side", "corner", "beep", "stuck"}
    assert "not-visited" in classes["finished"]
    assert [name for name, c in classes.items() if "ended" in c] == ["stuck"]
    side = next(g for g in _groups(root, "state") if g.get("data-state") == "side")
    assert "visited 2 times, first at 0.00 s" in _texts(side)
    taken = {(g.get("data-source"), g.get("data-dest")) for g in _groups(root, "taken")}
    assert taken == {
        (None, "side"),
        ("side", "corner"),
        ("corner", "beep"),
        ("beep", "side"),
        ("side", "stuck"),
    }
    assert "square: failure in 'stuck'" in (root.findtext(f"{SVG}title") or "")


def test_a_run_inside_nested_states_marks_the_outer_state_too(nested: MissionSpec) -> None:
    run = RunMarks(
        ((0.0, "first"), (0.0, "first.out"), (2.0, "first.oops"), (2.0, "sad")), "failure", "sad"
    )
    root = _parse(to_svg(nested, run))
    classes = {g.get("data-state"): g.get("class", "").split() for g in _groups(root, "state")}
    assert "visited" in classes["first"] and "visited" in classes["first.out"]
    assert "not-visited" in classes["second"] and "not-visited" in classes["first.turn"]
    taken = {(g.get("data-source"), g.get("data-dest")) for g in _groups(root, "taken")}
    assert ("first.out", "first.oops") in taken
    assert ("first", "sad") in taken
    assert ("first", "second") not in taken


def test_run_marks_from_recorded_frames_and_from_the_result() -> None:
    frames = [
        {"t": 0.0, "state": "side"},
        {"t": 0.02, "state": "side"},
        {"t": 3.8, "state": "corner"},
        {"t": 5.0, "state": "side"},
    ]
    marks = RunMarks.from_frames(frames, {"outcome": "error"})
    assert marks.entered == ((0.0, "side"), (3.8, "corner"), (5.0, "side"))
    assert marks.visits == {"side": 2, "corner": 1}
    assert (marks.outcome, marks.final_state) == ("error", "side")
    listed = {"outcome": "success", "final_state": "b", "states": [[0.0, "a"], [0.0, "a"]]}
    marks = RunMarks.from_frames(frames, listed)  # the result's list wins: it misses nothing
    assert marks.visits == {"a": 2}
    assert marks.final_state == "b"


# ------------------------------------------------------------------------------------ PNG


def test_png_is_drawn_with_matplotlib(tmp_path: Path) -> None:
    pytest.importorskip("matplotlib")
    spec, _ = load_mission(MISSIONS / "square.yaml")
    target = tmp_path / "square.png"
    run = RunMarks(SQUARE_RUN, "failure", "stuck")
    write_png(spec, target, run)
    data = target.read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n"
    from matplotlib.image import imread

    pixels = imread(str(target))
    diagram = diagram_for(spec, run)
    # the picture is the layout at 2 pixels per layout pixel, and not blank
    assert abs(pixels.shape[1] - 2 * diagram.width_px) <= 2
    assert pixels[..., :3].min() < 0.3


def test_png_without_matplotlib_says_what_to_install(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setitem(sys.modules, "matplotlib", None)  # import matplotlib now fails
    spec, _ = load_mission(MISSIONS / "square.yaml")
    with pytest.raises(PictureUnavailableError, match=r"pip install 'roboscript\[plot\]'"):
        write_png(spec, tmp_path / "x.png")
    assert not (tmp_path / "x.png").exists()


# ------------------------------------------------------------------------------------ CLI


def test_cli_writes_svg_by_suffix_and_highlights_a_recorded_run(tmp_path: Path) -> None:
    from roboscript.replay.recording import Recorder

    recorder = Recorder({"mission": {"name": "square"}})
    for t, name in SQUARE_RUN:
        recorder.add({"t": t, "state": name})
    recorder.finish({"outcome": "failure", "final_state": "stuck"})
    run = tmp_path / "run.jsonl"
    recorder.write(run)
    out = tmp_path / "square.svg"
    result = run_cli("graph", "missions/square.yaml", "-o", str(out), "--run", str(run))
    assert result.returncode == 0, result.stderr
    root = _parse(out.read_text(encoding="utf-8"))
    classes = {g.get("data-state"): g.get("class", "").split() for g in _groups(root, "state")}
    assert "visited" in classes["corner"] and "not-visited" in classes["finished"]
    assert "ended" in classes["stuck"]
    assert result.stderr == ""


def test_cli_refuses_a_png_on_stdout_and_a_run_in_text_formats() -> None:
    result = run_cli("graph", "missions/square.yaml", "--format", "png")
    assert result.returncode == 2
    assert "-o FILE.png" in result.stderr and "Traceback" not in result.stderr
    result = run_cli("graph", "missions/square.yaml", "--run", "run.jsonl")
    assert result.returncode == 2
    assert "--format svg" in result.stderr
    result = run_cli("graph", "missions/square.yaml", "--format", "svg")
    assert result.returncode == 0
    assert _parse(result.stdout).tag == f"{SVG}svg"


def test_cli_writes_png_by_suffix_and_warns_of_another_missions_run(tmp_path: Path) -> None:
    pytest.importorskip("matplotlib")
    from roboscript.replay.recording import Recorder

    recorder = Recorder({"mission": {"name": "zigzag"}})
    recorder.add({"t": 0.0, "state": "side"})
    recorder.finish({"outcome": "success", "final_state": "side"})
    run = tmp_path / "other.jsonl"
    recorder.write(run)
    out = tmp_path / "square.png"
    result = run_cli("graph", "missions/square.yaml", "-o", str(out), "--run", str(run))
    assert result.returncode == 0, result.stderr
    assert out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert result.stderr == f"warning: {run} is a run of 'zigzag', not of 'square'\n"
