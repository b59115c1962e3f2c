"""roboscript web build: what goes into the offline folder, without a browser."""

from __future__ import annotations

import io
import json
import re
import zipfile
from pathlib import Path

import pytest
from helpers import MISSIONS, ROOT, run_cli

from roboscript.web import build
from roboscript.web.build import WebBuildError, build_web_app, site_packages_zip


def _fake_pyodide(folder: Path) -> Path:
    """A stand-in with the files and the one shape the build relies on."""
    folder.mkdir()
    (folder / "pyodide.js").write_text("var loadPyodide = function () {};\n")
    (folder / "pyodide.asm.mjs").write_text(
        "async function _createPyodideModule(m){var u=import.meta.url;return m}"
        "export default _createPyodideModule;"
    )
    (folder / "pyodide-lock.json").write_text('{"packages": {}}')
    (folder / "pyodide.asm.wasm").write_bytes(b"\0asm\1\0\0\0")
    (folder / "python_stdlib.zip").write_bytes(b"PK\5\6" + b"\0" * 18)
    return folder


def _fake_codemirror(folder: Path) -> Path:
    for part in (
        "lib/codemirror.js",
        "lib/codemirror.css",
        "mode/yaml/yaml.js",
        "mode/python/python.js",
    ):
        (folder / part).parent.mkdir(parents=True, exist_ok=True)
        (folder / part).write_text(f"/* {part} */\n")
    return folder


def test_the_packages_zip_holds_roboscript_and_its_pure_python_dependencies() -> None:
    names = zipfile.ZipFile(io.BytesIO(site_packages_zip())).namelist()
    for needed in (
        "roboscript/web/bridge.py",
        "roboscript/sim/worlds/empty.yaml",
        "roboscript/replay/viewer.js",
        "serial/__init__.py",
        "simple_pid/pid.py",
        "transitions/core.py",
        "six.py",
        "yaml/__init__.py",
    ):
        assert needed in names, needed
    assert not [n for n in names if n.endswith((".so", ".pyd")) or "__pycache__" in n]


def test_the_packages_zip_is_the_same_bytes_every_time() -> None:
    assert site_packages_zip() == site_packages_zip()


def test_the_runtime_module_becomes_a_classic_script() -> None:
    text = build._classic_runtime(
        "async function _createPyodideModule(){return import.meta.url}"
        "export default _createPyodideModule;",
        "self.rsBaseURI",
    )
    assert "export" not in text and "import.meta" not in text
    assert text.endswith("globalThis.rsCreatePyodide=_createPyodideModule;")


def test_a_runtime_of_another_shape_is_refused_in_one_sentence() -> None:
    with pytest.raises(WebBuildError, match="shape the app does not know"):
        build._classic_runtime("export { createPyodide };", "self.rsBaseURI")


def test_the_folder_has_the_page_and_every_script_it_loads(tmp_path: Path) -> None:
    built = build_web_app(
        tmp_path / "app",
        pyodide=str(_fake_pyodide(tmp_path / "pyodide")),
        codemirror=str(_fake_codemirror(tmp_path / "cm")),
    )
    page = built.page.read_text(encoding="utf-8")
    for source in re.findall(r'(?:src|href)="([^"]+)"', page):
        assert (built.page.parent / source).is_file(), source
    assert built.size_bytes == sum(
        p.stat().st_size for p in (tmp_path / "app").rglob("*") if p.is_file()
    )
    wasm = (tmp_path / "app" / "roboscript-web" / "pyodide-wasm.js").read_text()
    assert (
        wasm == '(window.rsAssets = window.rsAssets || {})["pyodide.asm.wasm"] = "AGFzbQEAAAA=";\n'
    )


def test_the_examples_are_the_tutorials_and_the_missions_own() -> None:
    examples = build._examples()
    assert examples["square.yaml"] == (MISSIONS / "square.yaml").read_text(encoding="utf-8")
    tutorial = (ROOT / "docs" / "tutorial" / "first-mission.md").read_text(encoding="utf-8")
    assert f"```yaml\n{examples['hello.yaml']}```" in tutorial


def test_without_npm_the_command_says_what_to_do(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "cache"))
    monkeypatch.setenv("PATH", str(tmp_path))  # no npm on it
    result = run_cli("web", "build", str(tmp_path / "app"))
    assert result.returncode == 1
    assert result.stderr == (
        "error: building the web app needs pyodide 314.0.7 from npm, and npm is not installed:"
        " install node.js (it brings npm), or give an unpacked package with --pyodide DIR\n"
    )


def _built_specs(folder: Path) -> dict[str, str]:
    script = (folder / "roboscript-web" / "specs.js").read_text(encoding="utf-8")
    prefix = "window.rsSpecs = "
    assert script.startswith(prefix)
    return json.loads(script[len(prefix) :].rstrip().rstrip(";"))  # type: ignore[no-any-return]


def test_a_shipped_spec_comes_with_the_files_it_names_and_no_mission(tmp_path: Path) -> None:
    build_web_app(
        tmp_path / "app",
        pyodide=str(_fake_pyodide(tmp_path / "pyodide")),
        codemirror=str(_fake_codemirror(tmp_path / "cm")),
        specs=[MISSIONS / "teacher" / "line-track"],
    )
    shipped = _built_specs(tmp_path / "app")
    assert sorted(shipped) == ["line_checks.py", "test.yaml"]  # not good.yaml, not bad.yaml
    folder = MISSIONS / "teacher" / "line-track"
    assert shipped["test.yaml"] == (folder / "test.yaml").read_text(encoding="utf-8")


def test_without_specs_the_page_ships_none(tmp_path: Path) -> None:
    build_web_app(
        tmp_path / "app",
        pyodide=str(_fake_pyodide(tmp_path / "pyodide")),
        codemirror=str(_fake_codemirror(tmp_path / "cm")),
    )
    assert _built_specs(tmp_path / "app") == {}


def test_a_spec_with_a_mistake_stops_the_build_at_its_line(tmp_path: Path) -> None:
    spec = tmp_path / "test.yaml"
    text = (MISSIONS / "teacher" / "square" / "test.yaml").read_text(encoding="utf-8")
    spec.write_text(text.replace("tones:", "tonez:"), encoding="utf-8")
    result = run_cli("web", "build", str(tmp_path / "app"), "--spec", str(spec))
    assert result.returncode == 2
    assert result.stderr.startswith(f"{spec}:")
    assert "tonez" in result.stderr and not (tmp_path / "app").exists()


def test_a_spec_with_hidden_runs_is_shipped_with_a_warning(tmp_path: Path) -> None:
    spec = tmp_path / "test.yaml"
    text = (MISSIONS / "teacher" / "square" / "test.yaml").read_text(encoding="utf-8")
    spec.write_text(text.replace("- {seed: 1}", "- {seed: 1, hidden: true}"), encoding="utf-8")
    pyodide, codemirror = _fake_pyodide(tmp_path / "p"), _fake_codemirror(tmp_path / "c")
    result = run_cli(
        "web", "build", str(tmp_path / "app"), "--spec", str(spec),
        "--pyodide", str(pyodide), "--codemirror", str(codemirror),
    )  # fmt: skip
    assert result.returncode == 0, result.stderr
    assert (
        "warning: square-50cm has hidden runs: the page carries the spec, so a student who"
        " reads the page's files can see them; ship a practice spec without hidden runs\n"
    ) in result.stderr


def test_the_page_and_its_worker_answer_fetch_with_one_shared_script(tmp_path: Path) -> None:
    built = build_web_app(
        tmp_path / "app",
        pyodide=str(_fake_pyodide(tmp_path / "pyodide")),
        codemirror=str(_fake_codemirror(tmp_path / "cm")),
    )
    assets = tmp_path / "app" / "roboscript-web"
    shim = (assets / "answered-fetch.js").read_text(encoding="utf-8")
    assert '<script src="roboscript-web/answered-fetch.js">' in built.page.read_text("utf-8")
    worker = (assets / "worker-source.js").read_text(encoding="utf-8")
    source = json.loads(worker.removeprefix("window.rsWorkerSource = ").removesuffix(";\n"))
    assert source.startswith(shim)
    for script in ("app.js", "worker.js"):  # neither keeps a copy of its own
        text = (Path(build.__file__).parent / script).read_text(encoding="utf-8")
        assert "self.fetch = " not in text and "window.fetch = " not in text
