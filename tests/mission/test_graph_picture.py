# ruff: noqa: E501  (the goldens hold whole SVG lines, which are long)
"""``roboscript graph --format svg|png``: the state diagram as a picture, a run highlighted."""

from __future__ import annotations

import itertools
import sys
import xml.etree.ElementTree as ET
from pathlib import Path
from typing import Any

import pytest
from helpers import MISSIONS, TWICE_PY, run_cli

from roboscript.mission import load_mission
from roboscript.mission.graph import _edges
from roboscript.mission.graph_layout import Diagram, Rect, layout, text_width_px
from roboscript.mission.graph_picture import (
    PictureUnavailableError,
    RunMarks,
    diagram_for,
    require_matplotlib,
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


def test_cli_never_draws_over_the_mission_or_the_run_it_reads(tmp_path: Path) -> None:
    mission = tmp_path / "square.yaml"
    mission.write_bytes((MISSIONS / "square.yaml").read_bytes())
    run = tmp_path / "run.jsonl"
    assert run_cli("run", str(mission), "--record", str(run), "--quiet").returncode == 0
    kept = {path: path.read_bytes() for path in (mission, run)}
    for args in (
        ("-o", "square.yaml"),
        ("--format", "svg", "--run", "run.jsonl", "-o", "run.jsonl"),
    ):
        result = run_cli("graph", "square.yaml", *args, cwd=tmp_path)
        assert result.returncode == 2
        assert (
            result.stderr.startswith("error: -o ")
            and "writing it would destroy it" in result.stderr
        )
    assert {path: path.read_bytes() for path in (mission, run)} == kept


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


# -------- Whole pictures: the SVG and the PNG's drawn artists
#
# Mutation-test pins of the state-diagram pictures: whole SVGs and the PNG's drawn artists.
#
# The goldens were checked by eye (boxes, labels, arrows, self-loops, marks) and are compared
# whole, so any change of a coordinate, colour, class or escaped text shows.


LOOPS_ESCAPED = LOOPS.replace("mission: loops", 'mission: "loops & <co>"')


# a three times (twice by its own loop), then b, then the final c; ends in c.
LOOPS_RUN = RunMarks(((0.0, "a"), (1.25, "a"), (2.5, "a"), (3.0, "b"), (8.0, "c")), "failure", "c")
# Into the first nested mission, out of it, into the second, never to a final state.
NESTED_RUN = RunMarks(
    ((0.0, "first"), (0.0, "first.out"), (2.0, "first.turn"), (3.0, "first.home"),
     (3.0, "second"), (3.0, "second.out")),
    "error", None,
)  # fmt: skip


def _load(tmp_path: Path, name: str, text: str) -> MissionSpec:
    path = tmp_path / name
    path.write_text(text, encoding="utf-8")
    return load_mission(path)[0]


def _case(tmp_path: Path, case: str) -> tuple[MissionSpec, RunMarks | None]:
    if case.startswith("loops"):
        spec = _load(tmp_path, "loops.yaml", LOOPS_ESCAPED)
        return spec, (LOOPS_RUN if case.endswith("run") else None)
    spec = _load(tmp_path, "twice.py", TWICE_PY)
    return spec, (NESTED_RUN if case.endswith("run") else None)


def _r(value: Any) -> Any:
    """Numbers to 0.01, recursively, so the dump is stable and readable."""
    if isinstance(value, float):
        return float(round(value, 2)) + 0.0
    if isinstance(value, list | tuple):
        return [_r(v) for v in value]
    return value


def _artists(figure: Any) -> list[str]:
    """Every patch and text the PNG draws, with what a viewer sees of it."""
    from matplotlib.colors import to_hex
    from matplotlib.patches import Circle, FancyBboxPatch, PathPatch, Polygon

    (axes,) = figure.axes
    out = [
        (
            f"figure {_r(list(figure.get_size_inches()))} dpi {figure.dpi}"
            f" xlim {_r(list(axes.get_xlim()))} ylim {_r(list(axes.get_ylim()))}"
            f" axis {axes.axison}"
        )
    ]
    for patch in axes.patches:
        common = (
            f"z={patch.get_zorder()} face={to_hex(patch.get_facecolor(), keep_alpha=True)}"
            f" edge={to_hex(patch.get_edgecolor(), keep_alpha=True)}"
            f" lw={_r(patch.get_linewidth())} ls={patch.get_linestyle()} fill={patch.get_fill()}"
        )
        if isinstance(patch, FancyBboxPatch):
            style = patch.get_boxstyle()
            shape = (
                f"box {_r([patch.get_x(), patch.get_y(), patch.get_width(), patch.get_height()])}"
                f" {type(style).__name__} pad={style.pad} r={style.rounding_size}"
            )
        elif isinstance(patch, Circle):
            shape = f"circle {_r(list(patch.center))} r={patch.radius}"
        elif isinstance(patch, Polygon):
            shape = f"polygon {_r(patch.get_xy().tolist())} closed={patch.get_closed()}"
        elif isinstance(patch, PathPatch):
            path = patch.get_path()
            shape = f"path {_r(path.vertices.tolist())} {path.codes.tolist()}"
        else:
            shape = type(patch).__name__
        out.append(f"{shape} {common}")
    for text in axes.texts:
        out.append(
            f"text {_r(list(text.get_position()))} {text.get_text()!r}"
            f" size={text.get_fontsize()} weight={text.get_fontweight()}"
            f" color={to_hex(text.get_color())} ha={text.get_horizontalalignment()}"
            f" va={text.get_verticalalignment()} z={text.get_zorder()}"
        )
    return out


def _png_artists(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, spec: MissionSpec, run: RunMarks | None
) -> tuple[list[str], Path]:
    from matplotlib.figure import Figure

    seen: list[list[str]] = []
    original = Figure.savefig

    def savefig(self: Figure, fname: Any, **kwargs: Any) -> None:
        seen.append([*_artists(self), f"savefig {sorted(kwargs.items())}"])
        original(self, fname, **kwargs)

    monkeypatch.setattr(Figure, "savefig", savefig)
    path = tmp_path / "out.png"
    write_png(spec, path, run)
    (artists,) = seen
    return artists, path


# ----------------------------------------------------------------------------- goldens

GOLDEN_SVG: dict[str, str] = {
    "loops": (
        '<?xml version="1.0" encoding="UTF-8"?>\n'
        '<svg xmlns="http://www.w3.org/2000/svg" width="650.3" height="153" viewBox="0 0 650.3 153" font-family="Helvetica, Arial, \'DejaVu Sans\', sans-serif" role="img" aria-label="state diagram of loops &amp; &lt;co&gt;">\n'
        "<title>loops &amp; &lt;co&gt;</title>\n"
        '<rect width="650.3" height="153" fill="#ffffff"/>\n'
        '<text class="caption" x="16" y="31" font-size="15" font-weight="bold" fill="#222222">loops &amp; &lt;co&gt;</text>\n'
        '<g class="edge" data-dest="a" data-label="">\n'
        '<path d="M30,115.5 C42.5,115.5 42.5,115.5 55,115.5 C103.5,115.5 103.5,115.5 152.1,115.5" fill="none" stroke="#555555" stroke-width="1.2"/>\n'
        '<polygon points="152.1,115.5 144.1,119.1 144.1,111.9" fill="#555555"/>\n'
        "</g>\n"
        '<g class="edge" data-source="a" data-dest="a" data-label="done">\n'
        '<path d="M191.9,94 C191.9,83.4 165.4,83.4 165.4,94" fill="none" stroke="#555555" stroke-width="1.2"/>\n'
        '<polygon points="165.4,94 161.8,86 169,86" fill="#555555"/>\n'
        '<rect x="159.5" y="46" width="38.2" height="16" rx="3" fill="#ffffff" fill-opacity="0.9"/>\n'
        '<text x="178.6" y="58" text-anchor="middle" font-size="11" fill="#222222">done</text>\n'
        "</g>\n"
        '<g class="edge" data-source="b" data-dest="a" data-label="done">\n'
        '<path d="M367.6,111.5 C354.5,111.5 354.5,103.5 341.5,103.5 C322.4,103.5 322.4,103.5 303.3,103.5 C254.2,103.5 254.2,111.5 205.1,111.5" fill="none" stroke="#555555" stroke-width="1.2"/>\n'
        '<polygon points="205.1,111.5 213.1,107.9 213.1,115.1" fill="#555555"/>\n'
        '<rect x="303.3" y="95.5" width="38.2" height="16" rx="3" fill="#ffffff" fill-opacity="0.9"/>\n'
        '<text x="322.4" y="107.5" text-anchor="middle" font-size="11" fill="#222222">done</text>\n'
        "</g>\n"
        '<g class="edge" data-source="a" data-dest="b" data-label="failed">\n'
        '<path d="M205.1,119.5 C253.2,119.5 253.2,127.5 301.2,127.5 C322.4,127.5 322.4,127.5 343.6,127.5 C355.6,127.5 355.6,119.5 367.6,119.5" fill="none" stroke="#555555" stroke-width="1.2"/>\n'
        '<polygon points="367.6,119.5 359.6,123.1 359.6,115.9" fill="#555555"/>\n'
        '<rect x="301.2" y="119.5" width="42.3" height="16" rx="3" fill="#ffffff" fill-opacity="0.9"/>\n'
        '<text x="322.4" y="131.5" text-anchor="middle" font-size="11" fill="#222222">failed</text>\n'
        "</g>\n"
        '<g class="edge" data-source="a" data-dest="a" data-label="when [range.distance_cm &lt; 20]">\n'
        '<path d="M191.9,94 C191.9,72.7 165.4,72.7 165.4,94" fill="none" stroke="#555555" stroke-width="1.2"/>\n'
        '<polygon points="165.4,94 161.8,86 169,86" fill="#555555"/>\n'
        '<rect x="80" y="62" width="197.2" height="16" rx="3" fill="#ffffff" fill-opacity="0.9"/>\n'
        '<text x="178.6" y="74" text-anchor="middle" font-size="11" fill="#222222">when [range.distance_cm &lt; 20]</text>\n'
        "</g>\n"
        '<g class="edge" data-source="b" data-dest="c" data-label="timeout">\n'
        '<path d="M498.9,115.5 C510.9,115.5 510.9,115.5 522.9,115.5 C550.1,115.5 550.1,115.5 577.4,115.5 C589.4,115.5 589.4,115.5 601.4,115.5" fill="none" stroke="#555555" stroke-width="1.2"/>\n'
        '<polygon points="601.4,115.5 593.4,119.1 593.4,111.9" fill="#555555"/>\n'
        '<rect x="522.9" y="107.5" width="54.4" height="16" rx="3" fill="#ffffff" fill-opacity="0.9"/>\n'
        '<text x="550.1" y="119.5" text-anchor="middle" font-size="11" fill="#222222">timeout</text>\n'
        "</g>\n"
        '<g class="state" data-state="a">\n'
        "<title>a</title>\n"
        '<rect x="152.1" y="94" width="53" height="43" rx="6" fill="#ffffff" stroke="#222222" stroke-width="1.5"/>\n'
        '<text x="178.6" text-anchor="middle" y="112" font-size="13" font-weight="bold" fill="#222222">a</text>\n'
        '<text x="178.6" text-anchor="middle" y="127" font-size="11" fill="#222222">drive</text>\n'
        "</g>\n"
        '<g class="state" data-state="b">\n'
        "<title>b</title>\n"
        '<rect x="367.6" y="94" width="131.4" height="43" rx="6" fill="#ffffff" stroke="#222222" stroke-width="1.5"/>\n'
        '<text x="433.2" text-anchor="middle" y="112" font-size="13" font-weight="bold" fill="#222222">b</text>\n'
        '<text x="433.2" text-anchor="middle" y="127" font-size="11" fill="#222222">wait (timeout 5 s)</text>\n'
        "</g>\n"
        '<g class="state final-failure" data-state="c">\n'
        "<title>c</title>\n"
        '<rect x="601.4" y="101.5" width="33" height="28" rx="6" fill="#f6c6c6" stroke="#a02020" stroke-width="1.5"/>\n'
        '<rect x="605.1" y="105.2" width="25.5" height="20.5" rx="4" fill="none" stroke="#a02020" stroke-width="1"/>\n'
        '<text x="617.9" text-anchor="middle" y="119.5" font-size="13" font-weight="bold" fill="#222222">c</text>\n'
        "</g>\n"
        '<circle class="start" cx="23" cy="115.5" r="7" fill="#222222" data-dest="a"/>\n'
        "</svg>\n"
    ),
    "loops_run": (
        '<?xml version="1.0" encoding="UTF-8"?>\n'
        '<svg xmlns="http://www.w3.org/2000/svg" width="860.8" height="168" viewBox="0 0 860.8 168" font-family="Helvetica, Arial, \'DejaVu Sans\', sans-serif" role="img" aria-label="state diagram of loops &amp; &lt;co&gt;">\n'
        "<title>loops &amp; &lt;co&gt;: failure in 'c'</title>\n"
        '<rect width="860.8" height="168" fill="#ffffff"/>\n'
        '<text class="caption" x="16" y="31" font-size="15" font-weight="bold" fill="#222222">loops &amp; &lt;co&gt;: failure in \'c\'</text>\n'
        '<g class="edge taken" data-dest="a" data-label="">\n'
        '<path d="M30,123 C42.5,123 42.5,123 55,123 C67.5,123 67.5,123 80,123" fill="none" stroke="#1f6fb4" stroke-width="2.2"/>\n'
        '<polygon points="80,123 72,126.6 72,119.4" fill="#1f6fb4"/>\n'
        "</g>\n"
        '<g class="edge taken" data-source="a" data-dest="a" data-label="done">\n'
        '<path d="M231.2,94 C231.2,83.4 130.4,83.4 130.4,94" fill="none" stroke="#1f6fb4" stroke-width="2.2"/>\n'
        '<polygon points="130.4,94 126.8,86 134,86" fill="#1f6fb4"/>\n'
        '<rect x="161.7" y="46" width="38.2" height="16" rx="3" fill="#ffffff" fill-opacity="0.9"/>\n'
        '<text x="180.8" y="58" text-anchor="middle" font-size="11" fill="#222222">done</text>\n'
        "</g>\n"
        '<g class="edge" data-source="b" data-dest="a" data-label="done">\n'
        '<path d="M371.9,119 C358.8,119 358.8,111 345.8,111 C326.7,111 326.7,111 307.6,111 C294.6,111 294.6,119 281.5,119" fill="none" stroke="#b0b0b0" stroke-width="1.2"/>\n'
        '<polygon points="281.5,119 289.5,115.4 289.5,122.6" fill="#b0b0b0"/>\n'
        '<rect x="307.6" y="103" width="38.2" height="16" rx="3" fill="#ffffff" fill-opacity="0.9"/>\n'
        '<text x="326.7" y="115" text-anchor="middle" font-size="11" fill="#808080">done</text>\n'
        "</g>\n"
        '<g class="edge taken" data-source="a" data-dest="b" data-label="failed">\n'
        '<path d="M281.5,127 C293.5,127 293.5,135 305.5,135 C326.7,135 326.7,135 347.9,135 C359.9,135 359.9,127 371.9,127" fill="none" stroke="#1f6fb4" stroke-width="2.2"/>\n'
        '<polygon points="371.9,127 363.9,130.6 363.9,123.4" fill="#1f6fb4"/>\n'
        '<rect x="305.5" y="127" width="42.3" height="16" rx="3" fill="#ffffff" fill-opacity="0.9"/>\n'
        '<text x="326.7" y="139" text-anchor="middle" font-size="11" fill="#222222">failed</text>\n'
        "</g>\n"
        '<g class="edge taken" data-source="a" data-dest="a" data-label="when [range.distance_cm &lt; 20]">\n'
        '<path d="M231.2,94 C231.2,72.7 130.4,72.7 130.4,94" fill="none" stroke="#1f6fb4" stroke-width="2.2"/>\n'
        '<polygon points="130.4,94 126.8,86 134,86" fill="#1f6fb4"/>\n'
        '<rect x="82.2" y="62" width="197.2" height="16" rx="3" fill="#ffffff" fill-opacity="0.9"/>\n'
        '<text x="180.8" y="74" text-anchor="middle" font-size="11" fill="#222222">when [range.distance_cm &lt; 20]</text>\n'
        "</g>\n"
        '<g class="edge taken" data-source="b" data-dest="c" data-label="timeout">\n'
        '<path d="M557.1,123 C569.1,123 569.1,123 581.1,123 C608.4,123 608.4,123 635.6,123 C647.6,123 647.6,123 659.6,123" fill="none" stroke="#1f6fb4" stroke-width="2.2"/>\n'
        '<polygon points="659.6,123 651.6,126.6 651.6,119.4" fill="#1f6fb4"/>\n'
        '<rect x="581.1" y="115" width="54.4" height="16" rx="3" fill="#ffffff" fill-opacity="0.9"/>\n'
        '<text x="608.4" y="127" text-anchor="middle" font-size="11" fill="#222222">timeout</text>\n'
        "</g>\n"
        '<g class="state visited" data-state="a">\n'
        "<title>a: visited 3 times, first at 0.00 s</title>\n"
        '<rect x="80" y="94" width="201.5" height="58" rx="6" fill="#e3effa" stroke="#1f6fb4" stroke-width="2.5"/>\n'
        '<text x="180.8" text-anchor="middle" y="112" font-size="13" font-weight="bold" fill="#222222">a</text>\n'
        '<text x="180.8" text-anchor="middle" y="127" font-size="11" fill="#222222">drive</text>\n'
        '<text x="180.8" text-anchor="middle" y="142" font-size="11" fill="#222222">visited 3 times, first at 0.00 s</text>\n'
        "</g>\n"
        '<g class="state visited" data-state="b">\n'
        "<title>b: visited once, first at 3.00 s</title>\n"
        '<rect x="371.9" y="94" width="185.3" height="58" rx="6" fill="#e3effa" stroke="#1f6fb4" stroke-width="2.5"/>\n'
        '<text x="464.5" text-anchor="middle" y="112" font-size="13" font-weight="bold" fill="#222222">b</text>\n'
        '<text x="464.5" text-anchor="middle" y="127" font-size="11" fill="#222222">wait (timeout 5 s)</text>\n'
        '<text x="464.5" text-anchor="middle" y="142" font-size="11" fill="#222222">visited once, first at 3.00 s</text>\n'
        "</g>\n"
        '<g class="state final-failure visited ended" data-state="c">\n'
        "<title>c: visited once, first at 8.00 s</title>\n"
        '<rect x="659.6" y="101.5" width="185.3" height="43" rx="6" fill="#f6c6c6" stroke="#1f6fb4" stroke-width="4"/>\n'
        '<rect x="664.6" y="106.5" width="175.3" height="33" rx="4" fill="none" stroke="#1f6fb4" stroke-width="1"/>\n'
        '<text x="752.2" text-anchor="middle" y="119.5" font-size="13" font-weight="bold" fill="#222222">c</text>\n'
        '<text x="752.2" text-anchor="middle" y="134.5" font-size="11" fill="#222222">visited once, first at 8.00 s</text>\n'
        "</g>\n"
        '<circle class="start" cx="23" cy="123" r="7" fill="#222222" data-dest="a"/>\n'
        "</svg>\n"
    ),
    "nested_run": (
        '<?xml version="1.0" encoding="UTF-8"?>\n'
        '<svg xmlns="http://www.w3.org/2000/svg" width="1747.7" height="225.8" viewBox="0 0 1747.7 225.8" font-family="Helvetica, Arial, \'DejaVu Sans\', sans-serif" role="img" aria-label="state diagram of twice">\n'
        "<title>twice: error</title>\n"
        '<rect width="1747.7" height="225.8" fill="#ffffff"/>\n'
        '<text class="caption" x="16" y="31" font-size="15" font-weight="bold" fill="#222222">twice: error</text>\n'
        '<g class="state nested visited" data-state="first">\n'
        "<title>first: visited once, first at 0.00 s</title>\n"
        '<rect x="80" y="78.8" width="824.5" height="131" rx="6" fill="none" stroke="#1f6fb4" stroke-width="2.5" stroke-dasharray="6 4"/>\n'
        '<text x="90" y="95.8" font-size="13" font-weight="bold" fill="#222222">first</text>\n'
        "</g>\n"
        '<g class="state nested visited" data-state="second">\n'
        "<title>second: visited once, first at 3.00 s</title>\n"
        '<rect x="994.8" y="46" width="577.6" height="116" rx="6" fill="none" stroke="#1f6fb4" stroke-width="2.5" stroke-dasharray="6 4"/>\n'
        '<text x="1004.8" y="63" font-size="13" font-weight="bold" fill="#222222">second</text>\n'
        "</g>\n"
        '<g class="edge taken" data-dest="first" data-label="">\n'
        '<path d="M30,145.7 C42.5,145.7 42.5,145.7 55,145.7 C67.5,145.7 67.5,144.3 80,144.3" fill="none" stroke="#1f6fb4" stroke-width="2.2"/>\n'
        '<polygon points="80,144.3 72,147.9 72,140.7" fill="#1f6fb4"/>\n'
        "</g>\n"
        '<g class="edge taken" data-source="first" data-dest="second" data-label="done">\n'
        '<path d="M904.5,140.3 C917.5,140.3 917.5,124.6 930.6,124.6 C949.6,124.6 949.6,124.6 968.7,124.6 C981.8,124.6 981.8,104 994.8,104" fill="none" stroke="#1f6fb4" stroke-width="2.2"/>\n'
        '<polygon points="994.8,104 986.8,107.6 986.8,100.4" fill="#1f6fb4"/>\n'
        '<rect x="930.6" y="116.6" width="38.2" height="16" rx="3" fill="#ffffff" fill-opacity="0.9"/>\n'
        '<text x="949.6" y="128.6" text-anchor="middle" font-size="11" fill="#222222">done</text>\n'
        "</g>\n"
        '<g class="edge" data-source="second" data-dest="happy" data-label="done">\n'
        '<path d="M1572.4,100 C1585.5,100 1585.5,102.5 1598.5,102.5 C1617.6,102.5 1617.6,102.5 1636.7,102.5 C1649.7,102.5 1649.7,100.1 1662.8,100.1" fill="none" stroke="#b0b0b0" stroke-width="1.2"/>\n'
        '<polygon points="1662.8,100.1 1654.8,103.7 1654.8,96.5" fill="#b0b0b0"/>\n'
        '<rect x="1598.5" y="94.5" width="38.2" height="16" rx="3" fill="#ffffff" fill-opacity="0.9"/>\n'
        '<text x="1617.6" y="106.5" text-anchor="middle" font-size="11" fill="#808080">done</text>\n'
        "</g>\n"
        '<g class="edge" data-source="first" data-dest="sad" data-label="failed">\n'
        '<path d="M904.5,148.3 C916.5,148.3 916.5,161.6 928.5,161.6 C949.6,161.6 949.6,161.6 970.8,161.6 C1127.2,161.6 1127.2,178 1283.6,178 C1450.6,178 1450.6,164.5 1617.6,164.5 C1644.7,164.5 1644.7,154.1 1671.8,154.1" fill="none" stroke="#b0b0b0" stroke-width="1.2"/>\n'
        '<polygon points="1671.8,154.1 1663.8,157.7 1663.8,150.5" fill="#b0b0b0"/>\n'
        '<rect x="928.5" y="153.6" width="42.3" height="16" rx="3" fill="#ffffff" fill-opacity="0.9"/>\n'
        '<text x="949.6" y="165.6" text-anchor="middle" font-size="11" fill="#808080">failed</text>\n'
        "</g>\n"
        '<g class="edge" data-source="second" data-dest="sad" data-label="failed">\n'
        '<path d="M1572.4,108 C1584.4,108 1584.4,127.5 1596.4,127.5 C1617.6,127.5 1617.6,127.5 1638.8,127.5 C1655.3,127.5 1655.3,146.1 1671.8,146.1" fill="none" stroke="#b0b0b0" stroke-width="1.2"/>\n'
        '<polygon points="1671.8,146.1 1663.8,149.7 1663.8,142.5" fill="#b0b0b0"/>\n'
        '<rect x="1596.4" y="119.5" width="42.3" height="16" rx="3" fill="#ffffff" fill-opacity="0.9"/>\n'
        '<text x="1617.6" y="131.5" text-anchor="middle" font-size="11" fill="#808080">failed</text>\n'
        "</g>\n"
        '<g class="edge taken" data-dest="first.out" data-label="">\n'
        '<path d="M106,165.5 C118.5,165.5 118.5,165.5 131,165.5 C143.5,165.5 143.5,165.9 156,165.9" fill="none" stroke="#1f6fb4" stroke-width="2.2"/>\n'
        '<polygon points="156,165.9 148,169.5 148,162.3" fill="#1f6fb4"/>\n'
        "</g>\n"
        '<g class="edge taken" data-source="first.out" data-dest="first.turn" data-label="done">\n'
        '<path d="M341.3,161.9 C354.3,161.9 354.3,154.1 367.4,154.1 C386.4,154.1 386.4,154.1 405.5,154.1 C418.6,154.1 418.6,144.1 431.6,144.1" fill="none" stroke="#1f6fb4" stroke-width="2.2"/>\n'
        '<polygon points="431.6,144.1 423.6,147.7 423.6,140.5" fill="#1f6fb4"/>\n'
        '<rect x="367.4" y="146.1" width="38.2" height="16" rx="3" fill="#ffffff" fill-opacity="0.9"/>\n'
        '<text x="386.4" y="158.1" text-anchor="middle" font-size="11" fill="#222222">done</text>\n'
        "</g>\n"
        '<g class="edge taken" data-source="first.turn" data-dest="first.home" data-label="done">\n'
        '<path d="M616.9,140.1 C629.9,140.1 629.9,135.1 643,135.1 C662,135.1 662,135.1 681.1,135.1 C694.2,135.1 694.2,126.3 707.2,126.3" fill="none" stroke="#1f6fb4" stroke-width="2.2"/>\n'
        '<polygon points="707.2,126.3 699.2,129.9 699.2,122.7" fill="#1f6fb4"/>\n'
        '<rect x="643" y="127.1" width="38.2" height="16" rx="3" fill="#ffffff" fill-opacity="0.9"/>\n'
        '<text x="662" y="139.1" text-anchor="middle" font-size="11" fill="#222222">done</text>\n'
        "</g>\n"
        '<g class="edge" data-source="first.out" data-dest="first.oops" data-label="failed">\n'
        '<path d="M341.3,169.9 C353.3,169.9 353.3,178.1 365.3,178.1 C386.4,178.1 386.4,178.1 407.6,178.1 C465.9,178.1 465.9,189.1 524.2,189.1 C593.1,189.1 593.1,186.4 662,186.4 C715.9,186.4 715.9,187.8 769.9,187.8" fill="none" stroke="#b0b0b0" stroke-width="1.2"/>\n'
        '<polygon points="769.9,187.8 761.9,191.4 761.9,184.2" fill="#b0b0b0"/>\n'
        '<rect x="365.3" y="170.1" width="42.3" height="16" rx="3" fill="#ffffff" fill-opacity="0.9"/>\n'
        '<text x="386.4" y="182.1" text-anchor="middle" font-size="11" fill="#808080">failed</text>\n'
        "</g>\n"
        '<g class="edge" data-source="first.turn" data-dest="first.oops" data-label="failed">\n'
        '<path d="M616.9,148.1 C628.9,148.1 628.9,163.9 640.9,163.9 C662,163.9 662,163.9 683.2,163.9 C726.5,163.9 726.5,179.8 769.9,179.8" fill="none" stroke="#b0b0b0" stroke-width="1.2"/>\n'
        '<polygon points="769.9,179.8 761.9,183.4 761.9,176.2" fill="#b0b0b0"/>\n'
        '<rect x="640.9" y="155.9" width="42.3" height="16" rx="3" fill="#ffffff" fill-opacity="0.9"/>\n'
        '<text x="662" y="167.9" text-anchor="middle" font-size="11" fill="#808080">failed</text>\n'
        "</g>\n"
        '<g class="edge taken" data-dest="second.out" data-label="">\n'
        '<path d="M1020.8,119.4 C1033.3,119.4 1033.3,119.4 1045.8,119.4 C1058.3,119.4 1058.3,119.9 1070.8,119.9" fill="none" stroke="#1f6fb4" stroke-width="2.2"/>\n'
        '<polygon points="1070.8,119.9 1062.8,123.5 1062.8,116.3" fill="#1f6fb4"/>\n'
        "</g>\n"
        '<g class="edge" data-source="second.out" data-dest="second.turn" data-label="done">\n'
        '<path d="M1256.1,115.9 C1269.1,115.9 1269.1,108.3 1282.2,108.3 C1301.2,108.3 1301.2,108.3 1320.3,108.3 C1333.4,108.3 1333.4,102.2 1346.4,102.2" fill="none" stroke="#b0b0b0" stroke-width="1.2"/>\n'
        '<polygon points="1346.4,102.2 1338.4,105.8 1338.4,98.6" fill="#b0b0b0"/>\n'
        '<rect x="1282.2" y="100.3" width="38.2" height="16" rx="3" fill="#ffffff" fill-opacity="0.9"/>\n'
        '<text x="1301.2" y="112.3" text-anchor="middle" font-size="11" fill="#808080">done</text>\n'
        "</g>\n"
        '<g class="edge" data-source="second.turn" data-dest="second.home" data-label="done">\n'
        '<path d="M1405.4,98.2 C1418.4,98.2 1418.4,94 1431.5,94 C1450.6,94 1450.6,94 1469.6,94 C1482.7,94 1482.7,86 1495.7,86" fill="none" stroke="#b0b0b0" stroke-width="1.2"/>\n'
        '<polygon points="1495.7,86 1487.7,89.6 1487.7,82.4" fill="#b0b0b0"/>\n'
        '<rect x="1431.5" y="86" width="38.2" height="16" rx="3" fill="#ffffff" fill-opacity="0.9"/>\n'
        '<text x="1450.6" y="98" text-anchor="middle" font-size="11" fill="#808080">done</text>\n'
        "</g>\n"
        '<g class="edge" data-source="second.out" data-dest="second.oops" data-label="failed">\n'
        '<path d="M1256.1,123.9 C1268.1,123.9 1268.1,132.3 1280.1,132.3 C1301.2,132.3 1301.2,132.3 1322.4,132.3 C1349.1,132.3 1349.1,139.7 1375.9,139.7 C1413.2,139.7 1413.2,137.8 1450.6,137.8 C1474.3,137.8 1474.3,140 1498.1,140" fill="none" stroke="#b0b0b0" stroke-width="1.2"/>\n'
        '<polygon points="1498.1,140 1490.1,143.6 1490.1,136.4" fill="#b0b0b0"/>\n'
        '<rect x="1280.1" y="124.3" width="42.3" height="16" rx="3" fill="#ffffff" fill-opacity="0.9"/>\n'
        '<text x="1301.2" y="136.3" text-anchor="middle" font-size="11" fill="#808080">failed</text>\n'
        "</g>\n"
        '<g class="edge" data-source="second.turn" data-dest="second.oops" data-label="failed">\n'
        '<path d="M1405.4,106.2 C1417.4,106.2 1417.4,119 1429.4,119 C1450.6,119 1450.6,119 1471.7,119 C1484.9,119 1484.9,132 1498.1,132" fill="none" stroke="#b0b0b0" stroke-width="1.2"/>\n'
        '<polygon points="1498.1,132 1490.1,135.6 1490.1,128.4" fill="#b0b0b0"/>\n'
        '<rect x="1429.4" y="111" width="42.3" height="16" rx="3" fill="#ffffff" fill-opacity="0.9"/>\n'
        '<text x="1450.6" y="123" text-anchor="middle" font-size="11" fill="#808080">failed</text>\n'
        "</g>\n"
        '<g class="state visited" data-state="first.out">\n'
        "<title>first.out: visited once, first at 0.00 s</title>\n"
        '<rect x="156" y="136.9" width="185.3" height="58" rx="6" fill="#e3effa" stroke="#1f6fb4" stroke-width="2.5"/>\n'
        '<text x="248.6" text-anchor="middle" y="154.9" font-size="13" font-weight="bold" fill="#222222">out</text>\n'
        '<text x="248.6" text-anchor="middle" y="169.9" font-size="11" fill="#222222">drive</text>\n'
        '<text x="248.6" text-anchor="middle" y="184.9" font-size="11" fill="#222222">visited once, first at 0.00 s</text>\n'
        "</g>\n"
        '<g class="state visited" data-state="first.turn">\n'
        "<title>first.turn: visited once, first at 2.00 s</title>\n"
        '<rect x="431.6" y="115.1" width="185.3" height="58" rx="6" fill="#e3effa" stroke="#1f6fb4" stroke-width="2.5"/>\n'
        '<text x="524.2" text-anchor="middle" y="133.1" font-size="13" font-weight="bold" fill="#222222">turn</text>\n'
        '<text x="524.2" text-anchor="middle" y="148.1" font-size="11" fill="#222222">rotate</text>\n'
        '<text x="524.2" text-anchor="middle" y="163.1" font-size="11" fill="#222222">visited once, first at 2.00 s</text>\n'
        "</g>\n"
        '<g class="state final-success visited" data-state="first.home">\n'
        "<title>first.home: visited once, first at 3.00 s</title>\n"
        '<rect x="707.2" y="104.8" width="185.3" height="43" rx="6" fill="#c8f0c8" stroke="#1f6fb4" stroke-width="2.5"/>\n'
        '<rect x="711.5" y="109" width="176.8" height="34.5" rx="4" fill="none" stroke="#1f6fb4" stroke-width="1"/>\n'
        '<text x="799.8" text-anchor="middle" y="122.8" font-size="13" font-weight="bold" fill="#222222">home</text>\n'
        '<text x="799.8" text-anchor="middle" y="137.8" font-size="11" fill="#222222">visited once, first at 3.00 s</text>\n'
        "</g>\n"
        '<g class="state final-failure not-visited" data-state="first.oops">\n'
        "<title>first.oops: not visited</title>\n"
        '<rect x="769.9" y="169.8" width="59.9" height="28" rx="6" fill="#f6c6c6" stroke="#b0b0b0" stroke-width="1.5"/>\n'
        '<rect x="773.6" y="173.5" width="52.4" height="20.5" rx="4" fill="none" stroke="#b0b0b0" stroke-width="1"/>\n'
        '<text x="799.8" text-anchor="middle" y="187.8" font-size="13" font-weight="bold" fill="#808080">oops</text>\n'
        "</g>\n"
        '<g class="state visited" data-state="second.out">\n'
        "<title>second.out: visited once, first at 3.00 s</title>\n"
        '<rect x="1070.8" y="90.9" width="185.3" height="58" rx="6" fill="#e3effa" stroke="#1f6fb4" stroke-width="2.5"/>\n'
        '<text x="1163.4" text-anchor="middle" y="108.9" font-size="13" font-weight="bold" fill="#222222">out</text>\n'
        '<text x="1163.4" text-anchor="middle" y="123.9" font-size="11" fill="#222222">drive</text>\n'
        '<text x="1163.4" text-anchor="middle" y="138.9" font-size="11" fill="#222222">visited once, first at 3.00 s</text>\n'
        "</g>\n"
        '<g class="state not-visited" data-state="second.turn">\n'
        "<title>second.turn: not visited</title>\n"
        '<rect x="1346.4" y="80.7" width="59" height="43" rx="6" fill="#ffffff" stroke="#b0b0b0" stroke-width="1.5"/>\n'
        '<text x="1375.9" text-anchor="middle" y="98.7" font-size="13" font-weight="bold" fill="#808080">turn</text>\n'
        '<text x="1375.9" text-anchor="middle" y="113.7" font-size="11" fill="#808080">rotate</text>\n'
        "</g>\n"
        '<g class="state final-success not-visited" data-state="second.home">\n'
        "<title>second.home: not visited</title>\n"
        '<rect x="1495.7" y="72" width="64.7" height="28" rx="6" fill="#c8f0c8" stroke="#b0b0b0" stroke-width="1.5"/>\n'
        '<rect x="1499.5" y="75.8" width="57.2" height="20.5" rx="4" fill="none" stroke="#b0b0b0" stroke-width="1"/>\n'
        '<text x="1528.1" text-anchor="middle" y="90" font-size="13" font-weight="bold" fill="#808080">home</text>\n'
        "</g>\n"
        '<g class="state final-failure not-visited" data-state="second.oops">\n'
        "<title>second.oops: not visited</title>\n"
        '<rect x="1498.1" y="122" width="59.9" height="28" rx="6" fill="#f6c6c6" stroke="#b0b0b0" stroke-width="1.5"/>\n'
        '<rect x="1501.9" y="125.8" width="52.4" height="20.5" rx="4" fill="none" stroke="#b0b0b0" stroke-width="1"/>\n'
        '<text x="1528.1" text-anchor="middle" y="140" font-size="13" font-weight="bold" fill="#808080">oops</text>\n'
        "</g>\n"
        '<g class="state final-success not-visited" data-state="happy">\n'
        "<title>happy: not visited</title>\n"
        '<rect x="1662.8" y="86.1" width="68.9" height="28" rx="6" fill="#c8f0c8" stroke="#b0b0b0" stroke-width="1.5"/>\n'
        '<rect x="1666.5" y="89.9" width="61.4" height="20.5" rx="4" fill="none" stroke="#b0b0b0" stroke-width="1"/>\n'
        '<text x="1697.2" text-anchor="middle" y="104.1" font-size="13" font-weight="bold" fill="#808080">happy</text>\n'
        "</g>\n"
        '<g class="state final-failure not-visited" data-state="sad">\n'
        "<title>sad: not visited</title>\n"
        '<rect x="1671.8" y="136.1" width="51" height="28" rx="6" fill="#f6c6c6" stroke="#b0b0b0" stroke-width="1.5"/>\n'
        '<rect x="1675.5" y="139.9" width="43.5" height="20.5" rx="4" fill="none" stroke="#b0b0b0" stroke-width="1"/>\n'
        '<text x="1697.2" text-anchor="middle" y="154.1" font-size="13" font-weight="bold" fill="#808080">sad</text>\n'
        "</g>\n"
        '<circle class="start" cx="23" cy="145.7" r="7" fill="#222222" data-dest="first"/>\n'
        '<circle class="start" cx="99" cy="165.5" r="7" fill="#222222" data-dest="first.out"/>\n'
        '<circle class="start" cx="1013.8" cy="119.4" r="7" fill="#222222" data-dest="second.out"/>\n'
        "</svg>\n"
    ),
}

GOLDEN_PNG: dict[str, list[str]] = {
    "loops": [
        "figure [9.03, 2.12] dpi 144 xlim [0.0, 650.35] ylim [153.0, 0.0] axis False",
        "path [[30.0, 115.51], [42.5, 115.51], [42.5, 115.51], [55.0, 115.51], [103.55, 115.51], [103.55, 115.5], [152.09, 115.5]] [1, 4, 4, 4, 4, 4, 4] z=1.5 face=#1f77b400 edge=#555555ff lw=1.2 ls=solid fill=False",
        "polygon [[152.09, 115.5], [144.09, 119.1], [144.09, 111.9], [152.09, 115.5]] closed=True z=1.5 face=#555555ff edge=#555555ff lw=1.0 ls=solid fill=True",
        "path [[191.87, 94.0], [191.87, 83.36], [165.35, 83.36], [165.35, 94.0]] [1, 4, 4, 4] z=1.5 face=#1f77b400 edge=#555555ff lw=1.2 ls=solid fill=False",
        "polygon [[165.35, 94.0], [161.75, 86.0], [168.95, 86.0], [165.35, 94.0]] closed=True z=1.5 face=#555555ff edge=#555555ff lw=1.0 ls=solid fill=True",
        "box [159.53, 46.0, 38.16, 16.0] Round pad=0.0 r=3.0 z=1.6 face=#ffffffe6 edge=#00000000 lw=1.0 ls=solid fill=True",
        "path [[367.56, 111.49], [354.52, 111.49], [354.52, 103.5], [341.47, 103.5], [322.39, 103.5], [322.39, 103.5], [303.31, 103.5], [254.22, 103.5], [254.22, 111.5], [205.13, 111.5]] [1, 4, 4, 4, 4, 4, 4, 4, 4, 4] z=1.5 face=#1f77b400 edge=#555555ff lw=1.2 ls=solid fill=False",
        "polygon [[205.13, 111.5], [213.13, 107.9], [213.13, 115.1], [205.13, 111.5]] closed=True z=1.5 face=#555555ff edge=#555555ff lw=1.0 ls=solid fill=True",
        "box [303.31, 95.5, 38.16, 16.0] Round pad=0.0 r=3.0 z=1.6 face=#ffffffe6 edge=#00000000 lw=1.0 ls=solid fill=True",
        "path [[205.13, 119.5], [253.18, 119.5], [253.18, 127.5], [301.22, 127.5], [322.39, 127.5], [322.39, 127.5], [343.56, 127.5], [355.56, 127.5], [355.56, 119.49], [367.56, 119.49]] [1, 4, 4, 4, 4, 4, 4, 4, 4, 4] z=1.5 face=#1f77b400 edge=#555555ff lw=1.2 ls=solid fill=False",
        "polygon [[367.56, 119.49], [359.56, 123.09], [359.56, 115.89], [367.56, 119.49]] closed=True z=1.5 face=#555555ff edge=#555555ff lw=1.0 ls=solid fill=True",
        "box [301.22, 119.5, 42.34, 16.0] Round pad=0.0 r=3.0 z=1.6 face=#ffffffe6 edge=#00000000 lw=1.0 ls=solid fill=True",
        "path [[191.87, 94.0], [191.87, 72.72], [165.35, 72.72], [165.35, 94.0]] [1, 4, 4, 4] z=1.5 face=#1f77b400 edge=#555555ff lw=1.2 ls=solid fill=False",
        "polygon [[165.35, 94.0], [161.75, 86.0], [168.95, 86.0], [165.35, 94.0]] closed=True z=1.5 face=#555555ff edge=#555555ff lw=1.0 ls=solid fill=True",
        "box [80.0, 62.0, 197.22, 16.0] Round pad=0.0 r=3.0 z=1.6 face=#ffffffe6 edge=#00000000 lw=1.0 ls=solid fill=True",
        "path [[498.92, 115.49], [510.92, 115.49], [510.92, 115.49], [522.92, 115.49], [550.14, 115.49], [550.14, 115.49], [577.36, 115.49], [589.36, 115.49], [589.36, 115.48], [601.36, 115.48]] [1, 4, 4, 4, 4, 4, 4, 4, 4, 4] z=1.5 face=#1f77b400 edge=#555555ff lw=1.2 ls=solid fill=False",
        "polygon [[601.36, 115.48], [593.36, 119.08], [593.36, 111.88], [601.36, 115.48]] closed=True z=1.5 face=#555555ff edge=#555555ff lw=1.0 ls=solid fill=True",
        "box [522.92, 107.49, 54.44, 16.0] Round pad=0.0 r=3.0 z=1.6 face=#ffffffe6 edge=#00000000 lw=1.0 ls=solid fill=True",
        "box [152.09, 94.0, 53.04, 43.0] Round pad=0.0 r=6.0 z=2 face=#ffffffff edge=#222222ff lw=1.5 ls=- fill=True",
        "box [367.56, 93.99, 131.36, 43.0] Round pad=0.0 r=6.0 z=2 face=#ffffffff edge=#222222ff lw=1.5 ls=- fill=True",
        "box [601.36, 101.48, 32.99, 28.0] Round pad=0.0 r=6.0 z=2 face=#f6c6c6ff edge=#a02020ff lw=1.5 ls=- fill=True",
        "box [605.11, 105.23, 25.49, 20.5] Round pad=0.0 r=4.0 z=2 face=#00000000 edge=#a02020ff lw=1.0 ls=solid fill=True",
        "circle [23.0, 115.51] r=7.0 z=3 face=#222222ff edge=#222222ff lw=1.0 ls=solid fill=True",
        "text [16.0, 31.0] 'loops & <co>' size=15.0 weight=bold color=#222222 ha=left va=baseline z=3",
        "text [178.61, 58.0] 'done' size=11.0 weight=normal color=#222222 ha=center va=baseline z=1.7",
        "text [322.39, 107.5] 'done' size=11.0 weight=normal color=#222222 ha=center va=baseline z=1.7",
        "text [322.39, 131.5] 'failed' size=11.0 weight=normal color=#222222 ha=center va=baseline z=1.7",
        "text [178.61, 74.0] 'when [range.distance_cm < 20]' size=11.0 weight=normal color=#222222 ha=center va=baseline z=1.7",
        "text [550.14, 119.49] 'timeout' size=11.0 weight=normal color=#222222 ha=center va=baseline z=1.7",
        "text [178.61, 112.0] 'a' size=13.0 weight=bold color=#222222 ha=center va=baseline z=3",
        "text [178.61, 127.0] 'drive' size=11.0 weight=normal color=#222222 ha=center va=baseline z=3",
        "text [433.24, 111.99] 'b' size=13.0 weight=bold color=#222222 ha=center va=baseline z=3",
        "text [433.24, 126.99] 'wait (timeout 5 s)' size=11.0 weight=normal color=#222222 ha=center va=baseline z=3",
        "text [617.85, 119.48] 'c' size=13.0 weight=bold color=#222222 ha=center va=baseline z=3",
        "savefig [('facecolor', '#ffffff'), ('format', 'png')]",
    ],
    "loops_run": [
        "figure [11.96, 2.33] dpi 144 xlim [0.0, 860.84] ylim [168.0, 0.0] axis False",
        "path [[30.0, 123.01], [42.5, 123.01], [42.5, 123.01], [55.0, 123.01], [67.5, 123.01], [67.5, 123.0], [80.0, 123.0]] [1, 4, 4, 4, 4, 4, 4] z=1.5 face=#1f77b400 edge=#1f6fb4ff lw=2.2 ls=solid fill=False",
        "polygon [[80.0, 123.0], [72.0, 126.6], [72.0, 119.4], [80.0, 123.0]] closed=True z=1.5 face=#1f6fb4ff edge=#1f6fb4ff lw=1.0 ls=solid fill=True",
        "path [[231.16, 94.0], [231.16, 83.36], [130.39, 83.36], [130.39, 94.0]] [1, 4, 4, 4] z=1.5 face=#1f77b400 edge=#1f6fb4ff lw=2.2 ls=solid fill=False",
        "polygon [[130.39, 94.0], [126.79, 86.0], [133.99, 86.0], [130.39, 94.0]] closed=True z=1.5 face=#1f6fb4ff edge=#1f6fb4ff lw=1.0 ls=solid fill=True",
        "box [161.69, 46.0, 38.16, 16.0] Round pad=0.0 r=3.0 z=1.6 face=#ffffffe6 edge=#00000000 lw=1.0 ls=solid fill=True",
        "path [[371.88, 118.99], [358.84, 118.99], [358.84, 111.0], [345.79, 111.0], [326.71, 111.0], [326.71, 111.0], [307.63, 111.0], [294.59, 111.0], [294.59, 119.0], [281.54, 119.0]] [1, 4, 4, 4, 4, 4, 4, 4, 4, 4] z=1.5 face=#1f77b400 edge=#b0b0b0ff lw=1.2 ls=solid fill=False",
        "polygon [[281.54, 119.0], [289.54, 115.4], [289.54, 122.6], [281.54, 119.0]] closed=True z=1.5 face=#b0b0b0ff edge=#b0b0b0ff lw=1.0 ls=solid fill=True",
        "box [307.63, 103.0, 38.16, 16.0] Round pad=0.0 r=3.0 z=1.6 face=#ffffffe6 edge=#00000000 lw=1.0 ls=solid fill=True",
        "path [[281.54, 127.0], [293.54, 127.0], [293.54, 135.0], [305.54, 135.0], [326.71, 135.0], [326.71, 135.0], [347.88, 135.0], [359.88, 135.0], [359.88, 126.99], [371.88, 126.99]] [1, 4, 4, 4, 4, 4, 4, 4, 4, 4] z=1.5 face=#1f77b400 edge=#1f6fb4ff lw=2.2 ls=solid fill=False",
        "polygon [[371.88, 126.99], [363.88, 130.59], [363.88, 123.39], [371.88, 126.99]] closed=True z=1.5 face=#1f6fb4ff edge=#1f6fb4ff lw=1.0 ls=solid fill=True",
        "box [305.54, 127.0, 42.34, 16.0] Round pad=0.0 r=3.0 z=1.6 face=#ffffffe6 edge=#00000000 lw=1.0 ls=solid fill=True",
        "path [[231.16, 94.0], [231.16, 72.72], [130.39, 72.72], [130.39, 94.0]] [1, 4, 4, 4] z=1.5 face=#1f77b400 edge=#1f6fb4ff lw=2.2 ls=solid fill=False",
        "polygon [[130.39, 94.0], [126.79, 86.0], [133.99, 86.0], [130.39, 94.0]] closed=True z=1.5 face=#1f6fb4ff edge=#1f6fb4ff lw=1.0 ls=solid fill=True",
        "box [82.16, 62.0, 197.22, 16.0] Round pad=0.0 r=3.0 z=1.6 face=#ffffffe6 edge=#00000000 lw=1.0 ls=solid fill=True",
        "path [[557.14, 122.99], [569.14, 122.99], [569.14, 122.99], [581.14, 122.99], [608.36, 122.99], [608.36, 122.99], [635.58, 122.99], [647.58, 122.99], [647.58, 122.98], [659.58, 122.98]] [1, 4, 4, 4, 4, 4, 4, 4, 4, 4] z=1.5 face=#1f77b400 edge=#1f6fb4ff lw=2.2 ls=solid fill=False",
        "polygon [[659.58, 122.98], [651.58, 126.58], [651.58, 119.38], [659.58, 122.98]] closed=True z=1.5 face=#1f6fb4ff edge=#1f6fb4ff lw=1.0 ls=solid fill=True",
        "box [581.14, 114.99, 54.44, 16.0] Round pad=0.0 r=3.0 z=1.6 face=#ffffffe6 edge=#00000000 lw=1.0 ls=solid fill=True",
        "box [80.0, 94.0, 201.54, 58.0] Round pad=0.0 r=6.0 z=2 face=#e3effaff edge=#1f6fb4ff lw=2.5 ls=- fill=True",
        "box [371.88, 93.99, 185.26, 58.0] Round pad=0.0 r=6.0 z=2 face=#e3effaff edge=#1f6fb4ff lw=2.5 ls=- fill=True",
        "box [659.58, 101.48, 185.26, 43.0] Round pad=0.0 r=6.0 z=2 face=#f6c6c6ff edge=#1f6fb4ff lw=4.0 ls=- fill=True",
        "box [664.58, 106.48, 175.26, 33.0] Round pad=0.0 r=4.0 z=2 face=#00000000 edge=#1f6fb4ff lw=1.0 ls=solid fill=True",
        "circle [23.0, 123.01] r=7.0 z=3 face=#222222ff edge=#222222ff lw=1.0 ls=solid fill=True",
        "text [16.0, 31.0] \"loops & <co>: failure in 'c'\" size=15.0 weight=bold color=#222222 ha=left va=baseline z=3",
        "text [180.77, 58.0] 'done' size=11.0 weight=normal color=#222222 ha=center va=baseline z=1.7",
        "text [326.71, 115.0] 'done' size=11.0 weight=normal color=#808080 ha=center va=baseline z=1.7",
        "text [326.71, 139.0] 'failed' size=11.0 weight=normal color=#222222 ha=center va=baseline z=1.7",
        "text [180.77, 74.0] 'when [range.distance_cm < 20]' size=11.0 weight=normal color=#222222 ha=center va=baseline z=1.7",
        "text [608.36, 126.99] 'timeout' size=11.0 weight=normal color=#222222 ha=center va=baseline z=1.7",
        "text [180.77, 112.0] 'a' size=13.0 weight=bold color=#222222 ha=center va=baseline z=3",
        "text [180.77, 127.0] 'drive' size=11.0 weight=normal color=#222222 ha=center va=baseline z=3",
        "text [180.77, 142.0] 'visited 3 times, first at 0.00 s' size=11.0 weight=normal color=#222222 ha=center va=baseline z=3",
        "text [464.51, 111.99] 'b' size=13.0 weight=bold color=#222222 ha=center va=baseline z=3",
        "text [464.51, 126.99] 'wait (timeout 5 s)' size=11.0 weight=normal color=#222222 ha=center va=baseline z=3",
        "text [464.51, 141.99] 'visited once, first at 3.00 s' size=11.0 weight=normal color=#222222 ha=center va=baseline z=3",
        "text [752.21, 119.48] 'c' size=13.0 weight=bold color=#222222 ha=center va=baseline z=3",
        "text [752.21, 134.48] 'visited once, first at 8.00 s' size=11.0 weight=normal color=#222222 ha=center va=baseline z=3",
        "savefig [('facecolor', '#ffffff'), ('format', 'png')]",
    ],
    "nested_run": [
        "figure [24.27, 3.14] dpi 144 xlim [0.0, 1747.7] ylim [225.75, 0.0] axis False",
        "box [80.0, 78.75, 824.46, 131.0] Round pad=0.0 r=6.0 z=1 face=#00000000 edge=#1f6fb4ff lw=2.5 ls=-- fill=True",
        "box [994.8, 46.0, 577.64, 116.0] Round pad=0.0 r=6.0 z=1 face=#00000000 edge=#1f6fb4ff lw=2.5 ls=-- fill=True",
        "path [[30.0, 145.71], [42.5, 145.71], [42.5, 145.71], [55.0, 145.71], [67.5, 145.71], [67.5, 144.25], [80.0, 144.25]] [1, 4, 4, 4, 4, 4, 4] z=1.5 face=#1f77b400 edge=#1f6fb4ff lw=2.2 ls=solid fill=False",
        "polygon [[80.0, 144.25], [72.0, 147.85], [72.0, 140.65], [80.0, 144.25]] closed=True z=1.5 face=#1f6fb4ff edge=#1f6fb4ff lw=1.0 ls=solid fill=True",
        "path [[904.46, 140.25], [917.51, 140.25], [917.51, 124.65], [930.55, 124.65], [949.63, 124.65], [949.63, 124.65], [968.71, 124.65], [981.76, 124.65], [981.76, 104.0], [994.8, 104.0]] [1, 4, 4, 4, 4, 4, 4, 4, 4, 4] z=1.5 face=#1f77b400 edge=#1f6fb4ff lw=2.2 ls=solid fill=False",
        "polygon [[994.8, 104.0], [986.8, 107.6], [986.8, 100.4], [994.8, 104.0]] closed=True z=1.5 face=#1f6fb4ff edge=#1f6fb4ff lw=1.0 ls=solid fill=True",
        "box [930.55, 116.65, 38.16, 16.0] Round pad=0.0 r=3.0 z=1.6 face=#ffffffe6 edge=#00000000 lw=1.0 ls=solid fill=True",
        "path [[1572.44, 100.0], [1585.48, 100.0], [1585.48, 102.54], [1598.53, 102.54], [1617.61, 102.54], [1617.61, 102.54], [1636.69, 102.54], [1649.73, 102.54], [1649.73, 100.11], [1662.78, 100.11]] [1, 4, 4, 4, 4, 4, 4, 4, 4, 4] z=1.5 face=#1f77b400 edge=#b0b0b0ff lw=1.2 ls=solid fill=False",
        "polygon [[1662.78, 100.11], [1654.78, 103.71], [1654.78, 96.51], [1662.78, 100.11]] closed=True z=1.5 face=#b0b0b0ff edge=#b0b0b0ff lw=1.0 ls=solid fill=True",
        "box [1598.53, 94.54, 38.16, 16.0] Round pad=0.0 r=3.0 z=1.6 face=#ffffffe6 edge=#00000000 lw=1.0 ls=solid fill=True",
        "path [[904.46, 148.25], [916.46, 148.25], [916.46, 161.65], [928.46, 161.65], [949.63, 161.65], [949.63, 161.65], [970.8, 161.65], [1127.21, 161.65], [1127.21, 178.0], [1283.62, 178.0], [1450.61, 178.0], [1450.61, 164.54], [1617.61, 164.54], [1644.68, 164.54], [1644.68, 154.11], [1671.76, 154.11]] [1, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4] z=1.5 face=#1f77b400 edge=#b0b0b0ff lw=1.2 ls=solid fill=False",
        "polygon [[1671.76, 154.11], [1663.76, 157.71], [1663.76, 150.51], [1671.76, 154.11]] closed=True z=1.5 face=#b0b0b0ff edge=#b0b0b0ff lw=1.0 ls=solid fill=True",
        "box [928.46, 153.65, 42.34, 16.0] Round pad=0.0 r=3.0 z=1.6 face=#ffffffe6 edge=#00000000 lw=1.0 ls=solid fill=True",
        "path [[1572.44, 108.0], [1584.44, 108.0], [1584.44, 127.54], [1596.44, 127.54], [1617.61, 127.54], [1617.61, 127.54], [1638.78, 127.54], [1655.27, 127.54], [1655.27, 146.11], [1671.76, 146.11]] [1, 4, 4, 4, 4, 4, 4, 4, 4, 4] z=1.5 face=#1f77b400 edge=#b0b0b0ff lw=1.2 ls=solid fill=False",
        "polygon [[1671.76, 146.11], [1663.76, 149.71], [1663.76, 142.51], [1671.76, 146.11]] closed=True z=1.5 face=#b0b0b0ff edge=#b0b0b0ff lw=1.0 ls=solid fill=True",
        "box [1596.44, 119.54, 42.34, 16.0] Round pad=0.0 r=3.0 z=1.6 face=#ffffffe6 edge=#00000000 lw=1.0 ls=solid fill=True",
        "path [[106.0, 165.51], [118.5, 165.51], [118.5, 165.51], [131.0, 165.51], [143.5, 165.51], [143.5, 165.87], [156.0, 165.87]] [1, 4, 4, 4, 4, 4, 4] z=1.5 face=#1f77b400 edge=#1f6fb4ff lw=2.2 ls=solid fill=False",
        "polygon [[156.0, 165.87], [148.0, 169.47], [148.0, 162.27], [156.0, 165.87]] closed=True z=1.5 face=#1f6fb4ff edge=#1f6fb4ff lw=1.0 ls=solid fill=True",
        "path [[341.26, 161.87], [354.31, 161.87], [354.31, 154.13], [367.35, 154.13], [386.43, 154.13], [386.43, 154.13], [405.51, 154.13], [418.56, 154.13], [418.56, 144.09], [431.6, 144.09]] [1, 4, 4, 4, 4, 4, 4, 4, 4, 4] z=1.5 face=#1f77b400 edge=#1f6fb4ff lw=2.2 ls=solid fill=False",
        "polygon [[431.6, 144.09], [423.6, 147.69], [423.6, 140.49], [431.6, 144.09]] closed=True z=1.5 face=#1f6fb4ff edge=#1f6fb4ff lw=1.0 ls=solid fill=True",
        "box [367.35, 146.13, 38.16, 16.0] Round pad=0.0 r=3.0 z=1.6 face=#ffffffe6 edge=#00000000 lw=1.0 ls=solid fill=True",
        "path [[616.86, 140.09], [629.9, 140.09], [629.9, 135.11], [642.95, 135.11], [662.03, 135.11], [662.03, 135.11], [681.11, 135.11], [694.16, 135.11], [694.16, 126.25], [707.2, 126.25]] [1, 4, 4, 4, 4, 4, 4, 4, 4, 4] z=1.5 face=#1f77b400 edge=#1f6fb4ff lw=2.2 ls=solid fill=False",
        "polygon [[707.2, 126.25], [699.2, 129.85], [699.2, 122.65], [707.2, 126.25]] closed=True z=1.5 face=#1f6fb4ff edge=#1f6fb4ff lw=1.0 ls=solid fill=True",
        "box [642.95, 127.11, 38.16, 16.0] Round pad=0.0 r=3.0 z=1.6 face=#ffffffe6 edge=#00000000 lw=1.0 ls=solid fill=True",
        "path [[341.26, 169.87], [353.26, 169.87], [353.26, 178.13], [365.26, 178.13], [386.43, 178.13], [386.43, 178.13], [407.6, 178.13], [465.92, 178.13], [465.92, 189.09], [524.23, 189.09], [593.13, 189.09], [593.13, 186.36], [662.03, 186.36], [715.94, 186.36], [715.94, 187.75], [769.86, 187.75]] [1, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4] z=1.5 face=#1f77b400 edge=#b0b0b0ff lw=1.2 ls=solid fill=False",
        "polygon [[769.86, 187.75], [761.86, 191.35], [761.86, 184.15], [769.86, 187.75]] closed=True z=1.5 face=#b0b0b0ff edge=#b0b0b0ff lw=1.0 ls=solid fill=True",
        "box [365.26, 170.13, 42.34, 16.0] Round pad=0.0 r=3.0 z=1.6 face=#ffffffe6 edge=#00000000 lw=1.0 ls=solid fill=True",
        "path [[616.86, 148.09], [628.86, 148.09], [628.86, 163.86], [640.86, 163.86], [662.03, 163.86], [662.03, 163.86], [683.2, 163.86], [726.53, 163.86], [726.53, 179.75], [769.86, 179.75]] [1, 4, 4, 4, 4, 4, 4, 4, 4, 4] z=1.5 face=#1f77b400 edge=#b0b0b0ff lw=1.2 ls=solid fill=False",
        "polygon [[769.86, 179.75], [761.86, 183.35], [761.86, 176.15], [769.86, 179.75]] closed=True z=1.5 face=#b0b0b0ff edge=#b0b0b0ff lw=1.0 ls=solid fill=True",
        "box [640.86, 155.86, 42.34, 16.0] Round pad=0.0 r=3.0 z=1.6 face=#ffffffe6 edge=#00000000 lw=1.0 ls=solid fill=True",
        "path [[1020.8, 119.41], [1033.3, 119.41], [1033.3, 119.41], [1045.8, 119.41], [1058.3, 119.41], [1058.3, 119.93], [1070.8, 119.93]] [1, 4, 4, 4, 4, 4, 4] z=1.5 face=#1f77b400 edge=#1f6fb4ff lw=2.2 ls=solid fill=False",
        "polygon [[1070.8, 119.93], [1062.8, 123.53], [1062.8, 116.33], [1070.8, 119.93]] closed=True z=1.5 face=#1f6fb4ff edge=#1f6fb4ff lw=1.0 ls=solid fill=True",
        "path [[1256.06, 115.93], [1269.11, 115.93], [1269.11, 108.3], [1282.15, 108.3], [1301.23, 108.3], [1301.23, 108.3], [1320.31, 108.3], [1333.36, 108.3], [1333.36, 102.23], [1346.4, 102.23]] [1, 4, 4, 4, 4, 4, 4, 4, 4, 4] z=1.5 face=#1f77b400 edge=#b0b0b0ff lw=1.2 ls=solid fill=False",
        "polygon [[1346.4, 102.23], [1338.4, 105.83], [1338.4, 98.63], [1346.4, 102.23]] closed=True z=1.5 face=#b0b0b0ff edge=#b0b0b0ff lw=1.0 ls=solid fill=True",
        "box [1282.15, 100.3, 38.16, 16.0] Round pad=0.0 r=3.0 z=1.6 face=#ffffffe6 edge=#00000000 lw=1.0 ls=solid fill=True",
        "path [[1405.38, 98.23], [1418.43, 98.23], [1418.43, 94.0], [1431.47, 94.0], [1450.55, 94.0], [1450.55, 94.0], [1469.63, 94.0], [1482.68, 94.0], [1482.68, 86.0], [1495.72, 86.0]] [1, 4, 4, 4, 4, 4, 4, 4, 4, 4] z=1.5 face=#1f77b400 edge=#b0b0b0ff lw=1.2 ls=solid fill=False",
        "polygon [[1495.72, 86.0], [1487.72, 89.6], [1487.72, 82.4], [1495.72, 86.0]] closed=True z=1.5 face=#b0b0b0ff edge=#b0b0b0ff lw=1.0 ls=solid fill=True",
        "box [1431.47, 86.0, 38.16, 16.0] Round pad=0.0 r=3.0 z=1.6 face=#ffffffe6 edge=#00000000 lw=1.0 ls=solid fill=True",
        "path [[1256.06, 123.93], [1268.06, 123.93], [1268.06, 132.3], [1280.06, 132.3], [1301.23, 132.3], [1301.23, 132.3], [1322.4, 132.3], [1349.15, 132.3], [1349.15, 139.73], [1375.89, 139.73], [1413.22, 139.73], [1413.22, 137.75], [1450.55, 137.75], [1474.33, 137.75], [1474.33, 140.0], [1498.11, 140.0]] [1, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4] z=1.5 face=#1f77b400 edge=#b0b0b0ff lw=1.2 ls=solid fill=False",
        "polygon [[1498.11, 140.0], [1490.11, 143.6], [1490.11, 136.4], [1498.11, 140.0]] closed=True z=1.5 face=#b0b0b0ff edge=#b0b0b0ff lw=1.0 ls=solid fill=True",
        "box [1280.06, 124.3, 42.34, 16.0] Round pad=0.0 r=3.0 z=1.6 face=#ffffffe6 edge=#00000000 lw=1.0 ls=solid fill=True",
        "path [[1405.38, 106.23], [1417.38, 106.23], [1417.38, 119.0], [1429.38, 119.0], [1450.55, 119.0], [1450.55, 119.0], [1471.72, 119.0], [1484.91, 119.0], [1484.91, 132.0], [1498.11, 132.0]] [1, 4, 4, 4, 4, 4, 4, 4, 4, 4] z=1.5 face=#1f77b400 edge=#b0b0b0ff lw=1.2 ls=solid fill=False",
        "polygon [[1498.11, 132.0], [1490.11, 135.6], [1490.11, 128.4], [1498.11, 132.0]] closed=True z=1.5 face=#b0b0b0ff edge=#b0b0b0ff lw=1.0 ls=solid fill=True",
        "box [1429.38, 111.0, 42.34, 16.0] Round pad=0.0 r=3.0 z=1.6 face=#ffffffe6 edge=#00000000 lw=1.0 ls=solid fill=True",
        "box [156.0, 136.87, 185.26, 58.0] Round pad=0.0 r=6.0 z=2 face=#e3effaff edge=#1f6fb4ff lw=2.5 ls=- fill=True",
        "box [431.6, 115.09, 185.26, 58.0] Round pad=0.0 r=6.0 z=2 face=#e3effaff edge=#1f6fb4ff lw=2.5 ls=- fill=True",
        "box [707.2, 104.75, 185.26, 43.0] Round pad=0.0 r=6.0 z=2 face=#c8f0c8ff edge=#1f6fb4ff lw=2.5 ls=- fill=True",
        "box [711.45, 109.0, 176.76, 34.5] Round pad=0.0 r=4.0 z=2 face=#00000000 edge=#1f6fb4ff lw=1.0 ls=solid fill=True",
        "box [769.86, 169.75, 59.94, 28.0] Round pad=0.0 r=6.0 z=2 face=#f6c6c6ff edge=#b0b0b0ff lw=1.5 ls=- fill=True",
        "box [773.61, 173.5, 52.44, 20.5] Round pad=0.0 r=4.0 z=2 face=#00000000 edge=#b0b0b0ff lw=1.0 ls=solid fill=True",
        "box [1070.8, 90.93, 185.26, 58.0] Round pad=0.0 r=6.0 z=2 face=#e3effaff edge=#1f6fb4ff lw=2.5 ls=- fill=True",
        "box [1346.4, 80.73, 58.98, 43.0] Round pad=0.0 r=6.0 z=2 face=#ffffffff edge=#b0b0b0ff lw=1.5 ls=- fill=True",
        "box [1495.72, 72.0, 64.72, 28.0] Round pad=0.0 r=6.0 z=2 face=#c8f0c8ff edge=#b0b0b0ff lw=1.5 ls=- fill=True",
        "box [1499.47, 75.75, 57.22, 20.5] Round pad=0.0 r=4.0 z=2 face=#00000000 edge=#b0b0b0ff lw=1.0 ls=solid fill=True",
        "box [1498.11, 122.0, 59.94, 28.0] Round pad=0.0 r=6.0 z=2 face=#f6c6c6ff edge=#b0b0b0ff lw=1.5 ls=- fill=True",
        "box [1501.86, 125.75, 52.44, 20.5] Round pad=0.0 r=4.0 z=2 face=#00000000 edge=#b0b0b0ff lw=1.0 ls=solid fill=True",
        "box [1662.78, 86.11, 68.93, 28.0] Round pad=0.0 r=6.0 z=2 face=#c8f0c8ff edge=#b0b0b0ff lw=1.5 ls=- fill=True",
        "box [1666.53, 89.86, 61.43, 20.5] Round pad=0.0 r=4.0 z=2 face=#00000000 edge=#b0b0b0ff lw=1.0 ls=solid fill=True",
        "box [1671.76, 136.11, 50.96, 28.0] Round pad=0.0 r=6.0 z=2 face=#f6c6c6ff edge=#b0b0b0ff lw=1.5 ls=- fill=True",
        "box [1675.51, 139.86, 43.46, 20.5] Round pad=0.0 r=4.0 z=2 face=#00000000 edge=#b0b0b0ff lw=1.0 ls=solid fill=True",
        "circle [23.0, 145.71] r=7.0 z=3 face=#222222ff edge=#222222ff lw=1.0 ls=solid fill=True",
        "circle [99.0, 165.51] r=7.0 z=3 face=#222222ff edge=#222222ff lw=1.0 ls=solid fill=True",
        "circle [1013.8, 119.41] r=7.0 z=3 face=#222222ff edge=#222222ff lw=1.0 ls=solid fill=True",
        "text [16.0, 31.0] 'twice: error' size=15.0 weight=bold color=#222222 ha=left va=baseline z=3",
        "text [90.0, 95.75] 'first' size=13.0 weight=bold color=#222222 ha=left va=baseline z=3",
        "text [1004.8, 63.0] 'second' size=13.0 weight=bold color=#222222 ha=left va=baseline z=3",
        "text [949.63, 128.65] 'done' size=11.0 weight=normal color=#222222 ha=center va=baseline z=1.7",
        "text [1617.61, 106.54] 'done' size=11.0 weight=normal color=#808080 ha=center va=baseline z=1.7",
        "text [949.63, 165.65] 'failed' size=11.0 weight=normal color=#808080 ha=center va=baseline z=1.7",
        "text [1617.61, 131.54] 'failed' size=11.0 weight=normal color=#808080 ha=center va=baseline z=1.7",
        "text [386.43, 158.13] 'done' size=11.0 weight=normal color=#222222 ha=center va=baseline z=1.7",
        "text [662.03, 139.11] 'done' size=11.0 weight=normal color=#222222 ha=center va=baseline z=1.7",
        "text [386.43, 182.13] 'failed' size=11.0 weight=normal color=#808080 ha=center va=baseline z=1.7",
        "text [662.03, 167.86] 'failed' size=11.0 weight=normal color=#808080 ha=center va=baseline z=1.7",
        "text [1301.23, 112.3] 'done' size=11.0 weight=normal color=#808080 ha=center va=baseline z=1.7",
        "text [1450.55, 98.0] 'done' size=11.0 weight=normal color=#808080 ha=center va=baseline z=1.7",
        "text [1301.23, 136.3] 'failed' size=11.0 weight=normal color=#808080 ha=center va=baseline z=1.7",
        "text [1450.55, 123.0] 'failed' size=11.0 weight=normal color=#808080 ha=center va=baseline z=1.7",
        "text [248.63, 154.87] 'out' size=13.0 weight=bold color=#222222 ha=center va=baseline z=3",
        "text [248.63, 169.87] 'drive' size=11.0 weight=normal color=#222222 ha=center va=baseline z=3",
        "text [248.63, 184.87] 'visited once, first at 0.00 s' size=11.0 weight=normal color=#222222 ha=center va=baseline z=3",
        "text [524.23, 133.09] 'turn' size=13.0 weight=bold color=#222222 ha=center va=baseline z=3",
        "text [524.23, 148.09] 'rotate' size=11.0 weight=normal color=#222222 ha=center va=baseline z=3",
        "text [524.23, 163.09] 'visited once, first at 2.00 s' size=11.0 weight=normal color=#222222 ha=center va=baseline z=3",
        "text [799.83, 122.75] 'home' size=13.0 weight=bold color=#222222 ha=center va=baseline z=3",
        "text [799.83, 137.75] 'visited once, first at 3.00 s' size=11.0 weight=normal color=#222222 ha=center va=baseline z=3",
        "text [799.83, 187.75] 'oops' size=13.0 weight=bold color=#808080 ha=center va=baseline z=3",
        "text [1163.43, 108.93] 'out' size=13.0 weight=bold color=#222222 ha=center va=baseline z=3",
        "text [1163.43, 123.93] 'drive' size=11.0 weight=normal color=#222222 ha=center va=baseline z=3",
        "text [1163.43, 138.93] 'visited once, first at 3.00 s' size=11.0 weight=normal color=#222222 ha=center va=baseline z=3",
        "text [1375.89, 98.73] 'turn' size=13.0 weight=bold color=#808080 ha=center va=baseline z=3",
        "text [1375.89, 113.73] 'rotate' size=11.0 weight=normal color=#808080 ha=center va=baseline z=3",
        "text [1528.08, 90.0] 'home' size=13.0 weight=bold color=#808080 ha=center va=baseline z=3",
        "text [1528.08, 140.0] 'oops' size=13.0 weight=bold color=#808080 ha=center va=baseline z=3",
        "text [1697.24, 104.11] 'happy' size=13.0 weight=bold color=#808080 ha=center va=baseline z=3",
        "text [1697.24, 154.11] 'sad' size=13.0 weight=bold color=#808080 ha=center va=baseline z=3",
        "savefig [('facecolor', '#ffffff'), ('format', 'png')]",
    ],
}


@pytest.mark.parametrize("case", sorted(GOLDEN_SVG))
def test_svg_is_the_checked_picture(tmp_path: Path, case: str) -> None:
    spec, run = _case(tmp_path, case)
    assert to_svg(spec, run).splitlines(keepends=True) == GOLDEN_SVG[case].splitlines(keepends=True)


@pytest.mark.parametrize("case", sorted(GOLDEN_PNG))
def test_png_draws_the_checked_artists(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, case: str
) -> None:
    spec, run = _case(tmp_path, case)
    artists, path = _png_artists(tmp_path, monkeypatch, spec, run)
    assert artists == GOLDEN_PNG[case]
    # The file itself: a PNG of 2 pixels per layout pixel (144 dpi), white behind the boxes.
    from matplotlib.image import imread

    pixels = imread(path)
    assert path.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    figure_line = artists[0]
    assert pixels.shape[2] in (3, 4)
    assert tuple(pixels[0, 0, :3]) == (1.0, 1.0, 1.0)
    assert figure_line.startswith("figure ")


# ------------------------------------------------------------------------- text widths


@pytest.mark.parametrize(
    ("chars", "em"),
    [
        ("ijl|!.,:;'", 0.30),
        ("frt()[]{} ", 0.42),
        ("mwMW@%", 0.98),
        ("ABXYZ", 0.74),
        ("aekz0_-", 0.64),
    ],
)
def test_text_width_per_character_class(chars: str, em: float) -> None:
    # Each class of character has its own width, so labels of thin or wide letters fit.
    for char in chars:
        assert text_width_px(char, 10.0) == pytest.approx(em * 10.0), char
        assert text_width_px(char, 10.0, bold=True) == pytest.approx(em * 10.0 * 1.08), char
    assert text_width_px(chars, 2.0) == pytest.approx(em * 2.0 * len(chars))
    assert text_width_px("", 12.0) == 0.0


# ---------------------------------------------------------------------------- run marks


def test_run_marks_from_frames_without_a_usable_result_list() -> None:
    frames = [{"state": "a"}, {"t": 0.5, "state": "a"}, {"t": 1.5, "state": "b"}, {"t": 2.0}]
    # A malformed list (an entry of three items) is ignored: the frames are used.
    marks = RunMarks.from_frames(frames, {"states": [[0.0, "x", 1]], "outcome": 3})
    assert marks.entered == ((0.0, "a"), (1.5, "b"))
    assert marks.outcome is None
    assert marks.final_state == "b"
    empty = RunMarks.from_frames([], None)
    assert (empty.entered, empty.outcome, empty.final_state) == ((), None, None)


def test_run_marks_count_a_nested_state_by_its_inner_states() -> None:
    from roboscript.mission.graph_layout import EdgeLine

    marks = RunMarks(((0.0, "a"), (1.0, "first.out"), (2.0, "firstly")))
    assert marks.visited("first")
    assert not marks.visited("firs")
    assert marks.took(EdgeLine("a", "first", "done", (), None, None))
    assert not marks.took(EdgeLine("a", "firs", "done", (), None, None))
    assert marks.note("first.out") == "visited once, first at 1.00 s"
    assert marks.note("first") is None


def test_require_matplotlib_names_the_option_and_the_fix(monkeypatch: pytest.MonkeyPatch) -> None:
    import sys

    from roboscript.mission.graph_picture import PictureUnavailableError

    monkeypatch.setitem(sys.modules, "matplotlib", None)
    with pytest.raises(PictureUnavailableError) as err:
        require_matplotlib()
    assert str(err.value) == (
        "--format png needs matplotlib, which is not installed"
        " (pip install 'roboscript[plot]'; or use --format svg, which needs nothing)"
    )


def test_a_nested_state_entered_only_through_its_inner_states_shows_as_visited(
    tmp_path: Path,
) -> None:
    spec, _ = _case(tmp_path, "nested")
    svg = to_svg(spec, RunMarks(((0.0, "first.out"),)))
    # It has no note of its own (the run never reported it), but the run was inside it.
    assert "<title>first: visited</title>" in svg
    assert "<title>second: not visited</title>" in svg


def test_png_pixels_lie_where_the_layout_puts_the_boxes(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    from matplotlib.image import imread

    from roboscript.mission.graph_picture import diagram_for

    spec, run = _case(tmp_path, "loops_run")
    _, path = _png_artists(tmp_path, monkeypatch, spec, run)
    pixels = imread(path)
    diagram = diagram_for(spec, run)
    # 144 dpi: two pixels per layout pixel, the whole diagram on the image.
    # (matplotlib drops the fraction of a pixel)
    assert pixels.shape[:2] == (int(diagram.height_px * 2), int(diagram.width_px * 2))
    fills = {"a": (0xE3, 0xEF, 0xFA), "b": (0xE3, 0xEF, 0xFA), "c": (0xF6, 0xC6, 0xC6)}
    for box in diagram.states:
        x, y, _, _ = box.rect
        # Near the top-left corner: inside the stroke (and a final box's inner line), above
        # the text.
        pixel = pixels[round((y + 10) * 2), round((x + 12) * 2), :3]
        assert tuple(round(float(v) * 255) for v in pixel) == fills[box.name], box.name
