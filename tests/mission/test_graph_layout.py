# ruff: noqa: E501  (the goldens hold whole lines of coordinates)
"""The state diagram's layout as data (``layout``): what the SVG and PNG are drawn from."""

from __future__ import annotations

from pathlib import Path

import pytest
from helpers import MISSIONS

from roboscript.mission import load_mission
from roboscript.mission.graph_layout import TITLE_FONT_PX, layout, text_width_px

LONG_NAME = """
mission: a mission whose name is much wider than its one state
initial: only
states:
  only:
    final: success
"""

NESTED_LOOP = """
from roboscript import Drive, Mission, state


class Inner(Mission):
    go = state(Drive(distance_mm=100), initial=True, on_done="go", on_failed="stop")
    stop = state(final="failure")


class Outer(Mission):
    first = state(Inner, initial=True, on_done="end", on_failed="end")
    end = state(final="success")
"""


def test_a_long_mission_name_widens_the_picture_to_fit_its_bold_caption(tmp_path: Path) -> None:
    path = tmp_path / "long.yaml"
    path.write_text(LONG_NAME, encoding="utf-8")
    spec = load_mission(path)[0]
    diagram = layout(spec)
    assert diagram.title == "a mission whose name is much wider than its one state"
    # The caption is bold (wider than plain text); the margins are 16 px either side.
    caption = text_width_px(diagram.title, TITLE_FONT_PX, bold=True)
    assert diagram.width_px == caption + 2 * 16.0
    assert diagram.title_pos == (16.0, 16.0 + TITLE_FONT_PX)


def test_a_self_loop_inside_a_nested_state_belongs_to_it(tmp_path: Path) -> None:
    path = tmp_path / "outer.py"
    path.write_text(NESTED_LOOP, encoding="utf-8")
    spec = load_mission(path)[0]
    diagram = layout(spec)
    loops = [(e.source, e.dest, e.label, e.parent) for e in diagram.edges if e.source == e.dest]
    assert loops == [("first.go", "first.go", "done", "first")]
    boxes = {box.name: (box.parent, box.lines) for box in diagram.states}
    # A nested state shows its inner states instead of text lines of its own.
    assert boxes == {
        "first": (None, ()),
        "first.go": ("first", ("drive",)),
        "first.stop": ("first", ()),
        "end": (None, ()),
    }
    # Nor does a run's note go on it (its tooltip has the note): only on plain states.
    noted = layout(spec, {"first": "visited once", "first.go": "visited twice"})
    lines = {box.name: box.lines for box in noted.states}
    assert (lines["first"], lines["first.go"]) == ((), ("drive", "visited twice"))


# Where every box and arrow of the bigger example missions goes: column order, row placement,
# crossing reduction, arrows spread over a box's side, nested blocks moved into place.
BIG = [
    "stackmod_patrol.yaml",
    "bump_and_turn.yaml",
    "bump_and_turn.py",
    "square.yaml",
    "plen_walk.py",
]


def _summary(name: str) -> list[str]:
    diagram = layout(load_mission(MISSIONS / name)[0])
    lines = [f"size {diagram.width_px:.1f} x {diagram.height_px:.1f}"]
    for box in diagram.states:
        x, y, w, h = box.rect
        lines.append(f"box {box.name} {x:.1f},{y:.1f} {w:.1f}x{h:.1f} {box.lines}")
    for edge in diagram.edges:
        points = [edge.curves[0][0]] + [c[3] for c in edge.curves]
        where = " ".join(f"{px:.1f},{py:.1f}" for px, py in points)
        label = "" if edge.label_rect is None else " at {:.1f},{:.1f}".format(*edge.label_rect[:2])
        lines.append(f"edge {edge.source}>{edge.dest} {edge.label!r}{label}: {where}")
    for mark in diagram.starts:
        lines.append(f"start {mark.dest} {mark.center[0]:.1f},{mark.center[1]:.1f}")
    return lines


GOLDEN_LAYOUT: dict[str, list[str]] = {
    "stackmod_patrol.yaml": [
        "size 992.5 x 237.0",
        "box forward 80.0,91.5 141.7x43.0 ('drive (timeout 25 s)',)",
        "box alert 471.2,103.0 81.2x43.0 ('play_tone',)",
        "box back_off 466.9,178.0 89.7x43.0 ('drive',)",
        "box turn 647.0,106.5 59.0x43.0 ('rotate',)",
        "box home 903.5,71.6 64.7x43.0 ('stop',)",
        "box lost 895.3,136.6 81.2x43.0 ('play_tone',)",
        "edge None>forward '': 30.0,109.0 55.0,109.0 80.0,113.0",
        "edge forward>turn 'done' at 325.2,70.0: 221.7,105.3 325.2,78.0 363.4,78.0 511.8,75.0 601.8,96.7 647.0,116.0",
        "edge alert>turn 'done' at 582.7,118.7: 552.4,124.5 582.7,126.7 620.9,126.7 647.0,132.0",
        "edge back_off>turn 'done' at 582.7,145.3: 556.6,195.5 582.7,153.3 620.9,153.3 647.0,140.0",
        "edge turn>home 'done [visits.turn >= 6]' at 729.9,98.0: 705.9,124.0 729.9,106.0 871.3,106.0 903.5,93.1",
        "edge turn>forward 'done' at 325.2,94.0: 647.0,124.0 601.8,108.7 511.8,87.0 363.4,102.0 325.2,102.0 221.7,110.4",
        "edge forward>lost 'failed' at 323.1,46.0: 221.7,100.1 323.1,54.0 365.5,54.0 511.8,63.0 601.8,75.7 676.5,90.5 800.6,124.0 895.3,146.1",
        "edge back_off>lost 'failed' at 580.6,181.3: 556.6,203.5 580.6,189.3 623.0,189.3 676.5,179.6 800.6,172.0 895.3,170.1",
        "edge turn>lost 'failed' at 779.4,134.0: 705.9,132.0 779.4,142.0 821.8,142.0 895.3,154.1",
        "edge forward>lost 'timeout' at 317.1,142.0: 221.7,120.7 317.1,150.0 371.5,150.0 511.8,162.0 601.8,171.3 676.5,165.5 800.6,160.0 895.3,162.1",
        "edge forward>alert 'when [range.distance_cm < 25]' at 245.7,118.0: 221.7,115.6 245.7,126.0 442.9,126.0 471.2,124.5",
        "edge forward>back_off 'when [bumper.any]' at 282.4,166.0: 221.7,125.9 282.4,174.0 406.2,174.0 466.9,199.5",
        "start forward 23.0,109.0",
    ],
    "bump_and_turn.yaml": [
        "size 992.5 x 198.0",
        "box forward 80.0,92.5 141.7x43.0 ('drive (timeout 20 s)',)",
        "box back_off 466.9,91.5 89.7x43.0 ('drive',)",
        "box turn 647.0,80.3 59.0x43.0 ('rotate',)",
        "box home 895.3,64.2 81.2x43.0 ('play_tone',)",
        "box lost 895.3,129.2 81.2x43.0 ('play_tone',)",
        "edge None>forward '': 30.0,113.8 55.0,113.8 80.0,114.0",
        "edge forward>turn 'done' at 325.2,46.0: 221.7,101.1 325.2,54.0 363.4,54.0 511.8,63.5 601.8,75.3 647.0,89.8",
        "edge back_off>turn 'done' at 582.7,97.3: 556.6,109.0 582.7,105.3 620.9,105.3 647.0,105.8",
        "edge turn>home 'done [visits.turn >= 3]' at 729.9,85.7: 705.9,97.8 729.9,93.7 871.3,93.7 895.3,85.7",
        "edge turn>forward 'done' at 325.2,70.0: 647.0,97.8 601.8,87.3 511.8,75.5 363.4,78.0 325.2,78.0 221.7,106.2",
        "edge forward>back_off 'failed' at 323.1,94.0: 221.7,111.4 323.1,102.0 365.5,102.0 466.9,109.0",
        "edge back_off>lost 'failed' at 580.6,133.3: 556.6,117.0 580.6,141.3 623.0,141.3 676.5,143.3 800.6,145.5 895.3,150.7",
        "edge turn>lost 'failed' at 779.4,118.2: 705.9,105.8 779.4,126.2 821.8,126.2 895.3,142.7",
        "edge forward>lost 'timeout' at 317.1,166.0: 221.7,126.9 317.1,174.0 371.5,174.0 511.8,169.7 601.8,165.5 676.5,161.4 800.6,157.5 895.3,158.7",
        "edge forward>back_off 'when [bumper.any]' at 282.4,118.0: 221.7,116.5 282.4,126.0 406.2,126.0 466.9,117.0",
        "edge forward>turn 'when [range.distance_cm < 25]' at 245.7,142.0: 221.7,121.7 245.7,150.0 442.9,150.0 511.8,150.5 601.8,123.3 647.0,113.8",
        "start forward 23.0,113.8",
    ],
    "bump_and_turn.py": [
        "size 943.0 x 198.0",
        "box forward 80.0,92.5 141.7x43.0 ('drive (timeout 20 s)',)",
        "box back_off 392.1,91.5 89.7x43.0 ('drive',)",
        "box turn 572.2,80.3 59.0x43.0 ('rotate',)",
        "box home 845.8,64.2 81.2x43.0 ('play_tone',)",
        "box lost 845.8,129.2 81.2x43.0 ('play_tone',)",
        "edge None>forward '': 30.0,113.8 55.0,113.8 80.0,114.0",
        "edge forward>turn 'done' at 287.8,46.0: 221.7,101.1 287.8,54.0 326.0,54.0 437.0,63.5 527.0,75.3 572.2,89.8",
        "edge back_off>turn 'done' at 507.9,97.3: 481.8,109.0 507.9,105.3 546.1,105.3 572.2,105.8",
        "edge turn>home 'done [turned_three_times]' at 655.1,85.7: 631.1,97.8 655.1,93.7 821.8,93.7 845.8,85.7",
        "edge turn>forward 'done' at 287.8,70.0: 572.2,97.8 527.0,87.3 437.0,75.5 326.0,78.0 287.8,78.0 221.7,106.2",
        "edge forward>back_off 'failed' at 285.7,94.0: 221.7,111.4 285.7,102.0 328.1,102.0 392.1,109.0",
        "edge back_off>lost 'failed' at 505.8,133.3: 481.8,117.0 505.8,141.3 548.2,141.3 601.7,143.3 738.5,145.5 845.8,150.7",
        "edge turn>lost 'failed' at 717.3,118.2: 631.1,105.8 717.3,126.2 759.6,126.2 845.8,142.7",
        "edge forward>lost 'timeout' at 279.7,166.0: 221.7,126.9 279.7,174.0 334.1,174.0 437.0,169.7 527.0,165.5 601.7,161.4 738.5,157.5 845.8,158.7",
        "edge forward>back_off 'when [bumped]' at 256.0,118.0: 221.7,116.5 256.0,126.0 357.8,126.0 392.1,117.0",
        "edge forward>turn 'when [wall_ahead]' at 245.7,142.0: 221.7,121.7 245.7,150.0 368.1,150.0 437.0,150.5 527.0,123.3 572.2,113.8",
        "start forward 23.0,113.8",
    ],
    "square.yaml": [
        "size 926.4 x 189.4",
        "box side 80.0,95.8 141.7x43.0 ('drive (timeout 10 s)',)",
        "box corner 393.4,46.0 71.7x43.0 ('rotate',)",
        "box beep 555.5,47.5 81.2x43.0 ('play_tone',)",
        "box stuck 555.5,112.5 81.2x43.0 ('play_tone',)",
        "box finished 827.2,54.7 83.2x28.0 ()",
        "edge None>side '': 30.0,117.0 55.0,117.0 80.0,117.3",
        "edge side>corner 'done' at 288.5,61.4: 221.7,104.4 288.5,69.4 326.6,69.4 393.4,67.5",
        "edge corner>beep 'done' at 491.3,55.2: 465.2,63.5 491.3,63.2 529.4,63.2 555.5,65.0",
        "edge beep>finished 'done [visits.side >= 4]' at 660.7,60.8: 636.7,69.0 660.7,68.8 803.2,68.8 827.2,68.7",
        "edge beep>side 'done' at 288.5,85.4: 555.5,73.0 510.3,105.2 429.3,105.0 326.6,93.4 288.5,93.4 221.7,110.9",
        "edge side>stuck 'failed' at 286.4,109.4: 221.7,117.3 286.4,117.4 328.7,117.4 429.3,120.8 510.3,124.3 555.5,130.0",
        "edge corner>stuck 'failed' at 489.2,79.2: 465.2,71.5 489.2,87.2 531.5,87.2 555.5,122.0",
        "edge side>stuck 'timeout' at 280.4,133.4: 221.7,123.8 280.4,141.4 334.8,141.4 429.3,138.8 510.3,136.3 555.5,138.0",
        "edge side>stuck 'when [bumper.any]' at 245.7,157.4: 221.7,130.2 245.7,165.4 369.4,165.4 429.3,156.8 510.3,148.3 555.5,146.0",
        "start side 23.0,117.0",
    ],
    "plen_walk.py": [
        "size 1125.2 x 157.3",
        "box forward 80.0,95.0 140.8x43.0 ('walk (timeout 10 s)',)",
        "box turn_right 323.3,77.9 136.0x43.0 ('turn (timeout 15 s)',)",
        "box back 561.7,65.2 140.8x43.0 ('walk (timeout 10 s)',)",
        "box turn_back 804.9,55.8 136.0x43.0 ('turn (timeout 15 s)',)",
        "box rest 1049.4,46.0 53.8x43.0 ('wait',)",
        "box stuck 1043.4,111.0 65.8x28.0 ()",
        "edge None>forward '': 30.0,115.6 55.0,115.6 80.0,116.5",
        "edge forward>turn_right 'done' at 253.0,97.1: 220.8,112.5 253.0,105.1 291.1,105.1 323.3,99.4",
        "edge turn_right>back 'done' at 491.4,82.3: 459.2,95.4 491.4,90.3 529.5,90.3 561.7,86.7",
        "edge back>turn_back 'done' at 734.6,71.4: 702.5,82.7 734.6,79.4 772.8,79.4 804.9,77.3",
        "edge turn_back>rest 'done' at 973.1,64.5: 940.9,73.3 973.1,72.5 1011.2,72.5 1049.4,67.5",
        "edge forward>stuck 'timeout' at 244.8,121.1: 220.8,120.5 244.8,129.1 299.3,129.1 391.2,136.9 510.5,137.2 632.1,137.7 753.7,138.2 872.9,138.8 992.1,139.3 1043.4,133.4",
        "edge turn_right>stuck 'timeout' at 483.2,106.3: 459.2,103.4 483.2,114.3 537.7,114.3 632.1,124.2 753.7,125.5 872.9,126.8 992.1,127.3 1043.4,127.8",
        "edge back>stuck 'timeout' at 726.5,95.4: 702.5,90.7 726.5,103.4 780.9,103.4 872.9,114.8 992.1,115.3 1043.4,122.2",
        "edge turn_back>stuck 'timeout' at 964.9,89.3: 940.9,81.3 964.9,97.3 1019.4,97.3 1043.4,116.6",
        "start forward 23.0,115.6",
    ],
}


@pytest.mark.parametrize("name", BIG)
def test_layout_of_the_bigger_example_missions(name: str) -> None:
    assert _summary(name) == GOLDEN_LAYOUT[name]


THREE_LOOPS = """
mission: three loops
initial: a
states:
  a:
    do: {drive: {distance: 10 cm}}
    on: {done: a, failed: a, timeout: b}
    timeout: 5 s
    when:
      - {if: "range.distance_cm < 20", goto: a}
  b:
    final: success
"""


def test_every_self_loop_of_a_state_has_its_own_arc_and_label(tmp_path: Path) -> None:
    path = tmp_path / "three.yaml"
    path.write_text(THREE_LOOPS, encoding="utf-8")
    diagram = layout(load_mission(path)[0])
    loops = [e for e in diagram.edges if e.source == e.dest == "a"]
    assert len(loops) == 3
    # Each arc reaches higher than the one before, and the labels are stacked, not overlaid.
    peaks = [e.curves[0][1][1] for e in loops]
    assert peaks == sorted(peaks, reverse=True)
    assert len(set(peaks)) == 3
    tops = [e.label_rect[1] for e in loops if e.label_rect is not None]
    assert len(set(tops)) == 3
