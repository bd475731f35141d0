"""The documentation site (docs/, Sphinx + MyST) builds with warnings as errors, and the README stays a landing page
whose two commands are the installation page's and CI's."""

from __future__ import annotations

import re
import subprocess
import sys
import tomllib
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
README_MAX_LINES = 200  # a landing page: what it is, a picture, the two commands, where the docs are


def fenced(text: str, language: str) -> list[str]:
    """The ```language fenced blocks of a Markdown text."""
    return re.findall(rf"^```{language}\n(.*?)^```", text, flags=re.MULTILINE | re.DOTALL)


def two_commands(document: str) -> list[str]:
    """The command lines (not the comments) of the first ```sh block of ``document``."""
    block = fenced((ROOT / document).read_text(encoding="utf-8"), "sh")[0]
    return [line for line in block.splitlines() if line.strip() and not line.lstrip().startswith("#")]


@pytest.mark.slow  # about 40 s: autodoc imports every solver module and each command prints its --help
def test_the_docs_build_with_warnings_as_errors(tmp_path: Path) -> None:
    # -j auto: the pages are read in as many processes as there are cores (the extensions say they may be)
    build = [sys.executable, "-m", "sphinx", "-j", "auto", "-W", "--keep-going", "-q", "-b", "html", "-d",
             str(tmp_path / "doctrees"), "docs", str(tmp_path / "html")]  # fmt: skip
    done = subprocess.run(build, cwd=ROOT, capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, f"sphinx-build failed (warnings are errors):\n{done.stderr[-6000:]}"
    api = (tmp_path / "html" / "api" / "iteration.html").read_text(encoding="utf-8")
    assert 'id="solver.iteration.result.Result"' in api  # the API pages hold the docstrings, not just titles
    cli = (tmp_path / "html" / "reference" / "cli.html").read_text(encoding="utf-8")
    assert "usage: python -m solver solve" in cli  # the commands' own help


def test_the_docs_version_is_the_package_version() -> None:
    conf = (ROOT / "docs" / "conf.py").read_text(encoding="utf-8")
    version = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))["project"]["version"]
    assert re.search(r'^release = version = "(.*?)"', conf, flags=re.MULTILINE).group(1) == version


def test_the_readme_is_a_landing_page() -> None:
    text = (ROOT / "README.md").read_text(encoding="utf-8")
    assert len(text.splitlines()) <= README_MAX_LINES
    linked = re.findall(r"\]\(([^)#]+)\)", text)  # pictures and pages it points to
    assert linked and [path for path in linked if not (ROOT / path).is_file()] == []
    assert "python -m sphinx docs docs/_build/html" in text  # how to build the docs


def test_the_two_commands_are_the_install_page_and_ci() -> None:
    readme = two_commands("README.md")
    assert len(readme) == 2 and readme == two_commands("docs/install.md")
    ci = (ROOT / ".ci" / "run").read_text(encoding="utf-8")
    assert readme[1] in ci  # CI runs command 2 exactly
