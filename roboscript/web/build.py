"""``roboscript web build DIR``: the browser app, one folder that works offline from ``file://``.

The folder holds a page, Pyodide (CPython compiled to WebAssembly), this roboscript package
and its pure-Python dependencies, and the editor. Nothing is fetched when the page runs: it
opens from a USB stick, a file share or any static host (an LMS page, GitHub Pages).

``file://`` pages may not ``fetch`` files or load JavaScript modules in Chrome, so every binary
the runtime needs (the WebAssembly, the standard library, the packages) is stored in a
classic ``<script>`` as base64, and the page answers Pyodide's requests for them from there.
Building needs node's ``npm`` once, to fetch the Pyodide and CodeMirror packages into a cache
(or ``--pyodide DIR``/``--codemirror DIR`` with unpacked packages); the built folder needs
neither.
"""

from __future__ import annotations

import base64
import contextlib
import hashlib
import importlib
import io
import json
import os
import shutil
import subprocess
import tarfile
import tempfile
import zipfile
from collections.abc import Iterator, Sequence
from dataclasses import dataclass
from pathlib import Path

from roboscript.errors import RoboscriptError
from roboscript.grading.autograder import spec_files
from roboscript.grading.batch import find_specs
from roboscript.grading.spec import TestSpec

__all__ = [
    "CODEMIRROR_VERSION",
    "PYODIDE_VERSION",
    "WEB_PACKAGES",
    "WebBuildError",
    "build_web_app",
]

PYODIDE_VERSION = "314.0.7"
"""The Pyodide release the app is built on (npm's ``pyodide``; CPython 3.14)."""
CODEMIRROR_VERSION = "5.65.21"
"""The editor (npm's ``codemirror``, the 5.x line: one script, modes for YAML and Python)."""

WEB_PACKAGES = ("roboscript", "serial", "simple_pid", "transitions", "six", "yaml")
"""The import packages the app carries: roboscript and its dependencies (PyYAML without its
C extension: it uses its pure-Python reader then)."""

_ASSET_DIR = "roboscript-web"
_COMPILED = (".so", ".pyd", ".dylib", ".dll")
_CODEMIRROR_FILES = (
    "lib/codemirror.js",
    "lib/codemirror.css",
    "mode/yaml/yaml.js",
    "mode/python/python.js",
)


class WebBuildError(RoboscriptError):
    """The app could not be built; the message says why in one sentence."""


@dataclass(frozen=True)
class BuiltApp:
    """What ``build_web_app`` wrote.

    Attributes:
        page: The page to open (``DIR/index.html``).
        size_bytes: The whole folder's size.
        hidden_tests: The shipped tests that have hidden runs (which a page cannot keep from
            a student who reads its files).
        compiled: True when the Python the page imports was compiled to bytecode at build
            time (it needs node); otherwise the page compiles it each time it opens.
    """

    page: Path
    size_bytes: int
    hidden_tests: tuple[str, ...] = ()
    compiled: bool = False


# ----------------------------------------------------------------------------- npm packages


def _cache() -> Path:
    base = os.environ.get("XDG_CACHE_HOME") or str(Path.home() / ".cache")
    return Path(base) / "roboscript" / "web"


def _npm_package(name: str, version: str) -> Path:
    """The unpacked npm package ``name@version`` (``package/``), fetched once into the cache."""
    folder = _cache() / f"{name}-{version}"
    unpacked = folder / "package"
    if (unpacked / "package.json").is_file():
        return unpacked
    npm = shutil.which("npm")
    if npm is None:
        raise WebBuildError(
            f"building the web app needs {name} {version} from npm, and npm is not installed: "
            f"install node.js (it brings npm), or give an unpacked package with --{name} DIR"
        )
    folder.mkdir(parents=True, exist_ok=True)
    # Fetched and unpacked aside, then renamed into place: two builds at once (two terminals,
    # parallel tests) never see a half-unpacked package, and the second one's rename loses.
    with tempfile.TemporaryDirectory(prefix="fetching-", dir=folder) as scratch:
        done = subprocess.run(
            [npm, "pack", f"{name}@{version}", "--silent"],
            cwd=scratch,
            capture_output=True,
            text=True,
            check=False,
        )
        tarballs = sorted(Path(scratch).glob("*.tgz"))
        if done.returncode != 0 or not tarballs:
            reason = (done.stderr.strip().splitlines() or ["no package came"])[-1]
            raise WebBuildError(f"npm could not fetch {name}@{version}: {reason}")
        with tarfile.open(tarballs[-1]) as archive:
            archive.extractall(scratch, filter="data")
        if not (unpacked / "package.json").is_file():  # else another build got it first
            shutil.rmtree(unpacked, ignore_errors=True)  # what an interrupted fetch left
            with contextlib.suppress(OSError):  # another build renamed its own meanwhile
                os.rename(Path(scratch) / "package", unpacked)
    return unpacked


def _package_dir(given: str | None, name: str, version: str, needs: str) -> Path:
    folder = Path(given) if given else _npm_package(name, version)
    if not (folder / needs).is_file():
        raise WebBuildError(f"{folder} is not an unpacked {name} package (it has no {needs})")
    return folder


# ------------------------------------------------------------------------------ the parts


def _python_files() -> Iterator[tuple[str, Path]]:
    """``(path in site-packages, file)`` for every pure-Python file of :data:`WEB_PACKAGES`."""
    for name in WEB_PACKAGES:
        module = importlib.import_module(name)
        origin = Path(module.__file__ or "")
        if origin.name != "__init__.py":  # a module of one file (six)
            yield origin.name, origin
            continue
        root = origin.parent
        for path in sorted(root.rglob("*")):
            if not path.is_file() or "__pycache__" in path.parts or path.suffix in _COMPILED:
                continue
            yield str(Path(name) / path.relative_to(root)), path


def site_packages_zip() -> bytes:
    """The packages the app imports, as a zip for Pyodide's site-packages (reproducible)."""
    buffer = io.BytesIO()
    with zipfile.ZipFile(buffer, "w", zipfile.ZIP_DEFLATED) as archive:
        for name, path in _python_files():
            info = zipfile.ZipInfo(name, date_time=(1980, 1, 1, 0, 0, 0))
            info.compress_type = zipfile.ZIP_DEFLATED
            info.external_attr = 0o644 << 16
            archive.writestr(info, path.read_bytes())
    return buffer.getvalue()


_COMPILE_TIMEOUT_S = 900.0  # loading Pyodide in node and compiling takes a minute when busy


def _bytecode(runtime: Path, zips: dict[str, tuple[bytes, bool]]) -> dict[str, bytes]:
    """Each zip of Python files compiled to bytecode by the Pyodide in ``runtime``.

    Args:
        runtime: The unpacked Pyodide package.
        zips: ``{name: (zip, beside_source)}`` (see :func:`roboscript.web.bytecode.compile_zip`).

    Returns:
        The compiled zips by name: each is made once, with node, and kept in the cache; none
        when node is not installed or the compiling fails (the page then compiles at start).
    """
    here = Path(__file__).resolve().parent
    module = here / "bytecode.py"
    salt = PYODIDE_VERSION.encode() + module.read_bytes()
    cached: dict[str, Path] = {}
    for name, (data, beside) in zips.items():
        key = hashlib.sha256(salt + bytes([beside]) + data).hexdigest()[:24]
        cached[name] = _cache() / "bytecode" / f"{key}.zip"
    missing = [name for name, path in cached.items() if not path.is_file()]
    node = shutil.which("node")
    if missing and (node is None or not (runtime / "pyodide.mjs").is_file()):
        return {}
    if missing:
        with tempfile.TemporaryDirectory(prefix="roboscript-web-") as scratch:
            jobs: list[str] = []
            for name in missing:
                data, beside = zips[name]
                source = Path(scratch) / f"{name}.in.zip"
                source.write_bytes(data)
                jobs += [str(source), str(Path(scratch) / name), "beside" if beside else "alone"]
            try:
                done = subprocess.run(
                    [str(node), str(here / "compile.mjs"), str(runtime), str(module), *jobs],
                    capture_output=True,
                    timeout=_COMPILE_TIMEOUT_S,
                    check=False,
                )
            except (OSError, subprocess.TimeoutExpired):
                return {}
            if done.returncode != 0:
                return {}
            for name in missing:
                cached[name].parent.mkdir(parents=True, exist_ok=True)
                # copied beside, then renamed: another build never reads half a file
                partial = cached[name].with_suffix(f".{os.getpid()}.part")
                shutil.move(Path(scratch) / name, partial)
                os.replace(partial, cached[name])
    return {name: path.read_bytes() for name, path in cached.items()}


def _asset_script(name: str, data: bytes) -> str:
    """A classic script that stores ``data`` as base64 under ``name`` for the page."""
    encoded = base64.b64encode(data).decode("ascii")
    return f'(window.rsAssets = window.rsAssets || {{}})[{json.dumps(name)}] = "{encoded}";\n'


def _classic_runtime(module_text: str, base: str) -> str:
    """Pyodide's runtime module as a classic script (``file://`` pages cannot import modules):
    its one export becomes a global the loader is handed, and ``base`` (an expression) stands
    for the module's own URL (the worker has no document: it is given its base in a global)."""
    text = module_text.replace(
        "export default _createPyodideModule;", "globalThis.rsCreatePyodide=_createPyodideModule;"
    )
    if "rsCreatePyodide" not in text:
        raise WebBuildError("this Pyodide's runtime has a shape the app does not know")
    return text.replace("import.meta.url", base)


def _worker_script(loader: str, runtime_module: str, worker: str, fetch_shim: str) -> str:
    """The page's Python worker as text in a classic script (``window.rsWorkerSource``): a
    ``file://`` page may start no worker from a file, only from text it holds (a Blob).
    The fetch shim the page loads too (``answered-fetch.js``) and roboscript's worker
    (``worker.js``) come first, to prepare the ground Pyodide's loader looks at as it loads;
    then the loader and the runtime it calls when the page says boot."""
    runtime = _classic_runtime(runtime_module, "self.rsBaseURI")
    source = f"{fetch_shim}\n{worker}\n{loader}\n{runtime}"
    return f"window.rsWorkerSource = {json.dumps(source)};\n"


def _specs_script(specs: Sequence[TestSpec]) -> str:
    """The teacher's practice specs and the world and ``check`` files they name, as text by
    path (relative to one folder, so ``world: ../worlds/maze.yaml`` still finds its file)."""
    files = (
        {name: path.read_text(encoding="utf-8") for name, path in spec_files(specs).items()}
        if specs
        else {}
    )
    return f"window.rsSpecs = {json.dumps(files, sort_keys=True)};\n"


def _examples() -> dict[str, str]:
    """The example missions offered in the page, by file name (shipped with roboscript)."""
    folder = Path(__file__).resolve().parent / "examples"
    return {path.name: path.read_text(encoding="utf-8") for path in sorted(folder.iterdir())}


# ---------------------------------------------------------------------------------- build


def build_web_app(
    out: str | Path,
    *,
    pyodide: str | None = None,
    codemirror: str | None = None,
    specs: Sequence[str | Path] = (),
) -> BuiltApp:
    """Write the browser app into the folder ``out`` (made if needed; files replaced).

    Args:
        out: The folder; open ``out/index.html`` in a browser.
        pyodide: An unpacked npm ``pyodide`` package; default: fetched once with npm.
        codemirror: An unpacked npm ``codemirror`` 5 package; default: fetched once with npm.
        specs: Test spec files (or folders of them) to practise against in the page: the
            grading panel offers them, with the world and ``check`` files they name.

    Raises:
        WebBuildError: A package could not be had, or the folder cannot be written.
        SpecError: A spec is invalid (at ``file:line:col``).
    """
    # read before anything is written: a spec's mistake leaves no half-built folder
    tests = find_specs([str(spec) for spec in specs]) if specs else []
    runtime = _package_dir(pyodide, "pyodide", PYODIDE_VERSION, "pyodide.asm.wasm")
    stdlib = (runtime / "python_stdlib.zip").read_bytes()
    packages = site_packages_zip()
    compiled = _bytecode(runtime, {"stdlib": (stdlib, False), "packages": (packages, True)})
    editor = _package_dir(codemirror, "codemirror", CODEMIRROR_VERSION, "lib/codemirror.js")
    root = Path(out)
    assets = root / _ASSET_DIR
    here = Path(__file__).resolve().parent
    replay = here.parent / "replay"
    try:
        assets.mkdir(parents=True, exist_ok=True)
        files: dict[str, str] = {
            "worker-source.js": _worker_script(
                (runtime / "pyodide.js").read_text(encoding="utf-8"),
                (runtime / "pyodide.asm.mjs").read_text(encoding="utf-8"),
                (here / "worker.js").read_text(encoding="utf-8"),
                (here / "answered-fetch.js").read_text(encoding="utf-8"),
            ),
            "answered-fetch.js": (here / "answered-fetch.js").read_text(encoding="utf-8"),
            "pyodide-lock.js": "window.rsPyodideLock = "
            + json.dumps((runtime / "pyodide-lock.json").read_text(encoding="utf-8"))
            + ";\n",
            "pyodide-wasm.js": _asset_script(
                "pyodide.asm.wasm", (runtime / "pyodide.asm.wasm").read_bytes()
            ),
            "python-stdlib.js": _asset_script("python_stdlib.zip", compiled.get("stdlib", stdlib)),
            "site-packages.js": _asset_script(
                "site-packages.zip", compiled.get("packages", packages)
            ),
            "examples.js": f"window.rsExamples = {json.dumps(_examples())};\n",
            "specs.js": _specs_script(tests),
            "viewer.js": (replay / "viewer.js").read_text(encoding="utf-8"),
            "viewer.css": (replay / "viewer.css").read_text(encoding="utf-8"),
            "app.js": (here / "app.js").read_text(encoding="utf-8"),
            "robot-port.js": (here / "robot-port.js").read_text(encoding="utf-8"),
            "grade.js": (here / "grade.js").read_text(encoding="utf-8"),
            "platform.js": (here / "platform.js").read_text(encoding="utf-8"),
            "app.css": (here / "app.css").read_text(encoding="utf-8"),
        }
        for part in _CODEMIRROR_FILES:
            files[f"codemirror-{Path(part).name}"] = (editor / part).read_text(encoding="utf-8")
        for name, text in files.items():
            (assets / name).write_text(text, encoding="utf-8")
        page = root / "index.html"
        page.write_text((here / "index.html").read_text(encoding="utf-8"), encoding="utf-8")
    except OSError as exc:
        raise WebBuildError(f"cannot write the web app to {root}: {exc.strerror or exc}") from None
    size = sum(path.stat().st_size for path in root.rglob("*") if path.is_file())
    hidden = tuple(spec.name for spec in tests if any(v.hidden for v in spec.variants))
    return BuiltApp(page, size, hidden, bool(compiled))
