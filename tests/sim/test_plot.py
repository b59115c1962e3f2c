"""``run --plot``: a PNG of the world and the run, and a clear sentence without matplotlib."""

from __future__ import annotations

import struct
import subprocess
import sys
from pathlib import Path

import pytest
from helpers import HANG_BOUND_S, ROOT, run_cli

from roboscript.sim.body import Contact, SimLog
from roboscript.sim.world import load_world

PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"


def png_size(path: Path) -> tuple[int, int]:
    """Width and height in pixels of a PNG file (from its IHDR chunk)."""
    data = path.read_bytes()
    assert data[:8] == PNG_SIGNATURE
    assert data[12:16] == b"IHDR"
    width, height = struct.unpack(">II", data[16:24])
    return int(width), int(height)


def test_a_run_is_drawn_as_a_png_of_sensible_size(tmp_path: Path) -> None:
    pytest.importorskip("matplotlib")
    from roboscript.sim.plot import plot_run

    log = SimLog()
    log.path.extend([(0.0, 0.0, 0.0, 0.0), (1.0, 0.0, 500.0, 0.0), (2.0, 300.0, 700.0, 90.0)])
    log.tones.append((1.0, 880.0, 0.2))
    log.contacts.append(Contact(1.5, 100.0, 600.0, "left", 1.8))
    out = tmp_path / "run.png"
    plot_run(load_world("square-room"), log, "test: success", out, body_radius_mm=100.0)
    width, height = png_size(out)
    assert 500 <= width <= 2000 and 500 <= height <= 2000
    assert 0.6 < height / width < 1.4  # a square room stays roughly square
    assert out.stat().st_size > 10_000  # there is a picture in it, not a blank


def test_run_plot_writes_the_png_and_still_reports_the_mission(tmp_path: Path) -> None:
    pytest.importorskip("matplotlib")
    out = tmp_path / "square.png"
    result = run_cli("run", "missions/square.yaml", "--quiet", "--plot", str(out))
    assert result.returncode == 0, result.stderr
    assert "success: square" in result.stderr
    assert png_size(out)[0] > 500


def test_run_plot_into_a_missing_folder_makes_it(tmp_path: Path) -> None:
    pytest.importorskip("matplotlib")
    out = tmp_path / "no-such-folder" / "square.png"
    result = run_cli("run", "missions/square.yaml", "--quiet", "--plot", str(out))
    assert result.returncode == 0, result.stderr
    assert out.read_bytes().startswith(b"\x89PNG")


def test_run_plot_under_a_file_is_one_sentence_before_the_run(tmp_path: Path) -> None:
    pytest.importorskip("matplotlib")
    (tmp_path / "notes").write_text("mine\n", encoding="utf-8")
    out = tmp_path / "notes" / "square.png"
    result = run_cli("run", "missions/square.yaml", "--quiet", "--plot", str(out))
    assert result.returncode == 2
    assert (
        result.stderr
        == f"error: cannot write {out}: {tmp_path / 'notes'} is a file, not a folder\n"
    )


def test_without_matplotlib_run_plot_says_how_to_get_it_before_running(tmp_path: Path) -> None:
    # A None entry in sys.modules makes "import matplotlib" fail, as if it were not installed.
    code = (
        "import sys; sys.modules['matplotlib'] = None; from roboscript.cli import main; "
        f"main(['run', 'missions/square.yaml', '--plot', {str(tmp_path / 'x.png')!r}])"
    )
    result = subprocess.run(
        [sys.executable, "-c", code],
        capture_output=True,
        text=True,
        cwd=ROOT,
        env={"PYTHONPATH": str(ROOT), "PATH": ""},
        timeout=HANG_BOUND_S,
        check=False,
    )
    assert result.returncode == 1
    assert result.stderr.strip() == (
        "error: --plot needs matplotlib, which is not installed (pip install 'roboscript[plot]')"
    )
    assert not (tmp_path / "x.png").exists()
