"""The one build step pyproject.toml cannot say: the example missions go into the wheel.

``missions/`` sits beside the package in the source folder, where the guides and the test
suite run it. A wheel (``pip install .``, ``pip wheel .``, ``python -m build``) carries a copy
as ``roboscript/examples/``, which ``roboscript examples`` writes out as ``missions/`` for a
user who has the package and not the folder. An editable install reads ``missions/`` itself.
"""

from __future__ import annotations

import shutil
from pathlib import Path

from setuptools import setup
from setuptools.command.build_py import build_py

EXAMPLES = Path(__file__).resolve().parent / "missions"


class BuildWithExamples(build_py):
    """``build_py`` that also copies ``missions/`` into the built package as ``examples/``."""

    def run(self) -> None:
        super().run()
        if getattr(self, "editable_mode", False):  # an editable install reads missions/ itself
            return
        target = Path(self.build_lib) / "roboscript" / "examples"
        shutil.rmtree(target, ignore_errors=True)  # a file removed from missions/ goes too
        shutil.copytree(EXAMPLES, target, ignore=shutil.ignore_patterns("__pycache__", "*.py[co]"))


setup(cmdclass={"build_py": BuildWithExamples})
