"""Sphinx helpers of the Manikin documentation: the command lines' help as the commands print it, one page's
worth of ``automodule`` per package, and docstrings read as the plain text they are written as.

- ``.. command-help:: solver solve`` runs ``python -m solver solve --help`` (100 columns) and shows its output, so
  the CLI reference cannot drift from the parsers (a first argument ending in ``.py`` is a script of the checkout).
- ``.. package-modules:: solver.collision`` documents the package's docstring and then every module in it (members
  included), found on disk: a new module appears in the API reference without editing a page.
- Docstrings are read as they are written (``autodoc-process-docstring``): ``|x|`` is a norm or an absolute value,
  never a reStructuredText substitution, so those bars are escaped (outside literals, roles and literal blocks);
  and a relative reference such as ``:mod:`.transfer``` means what the same import would (the sibling module of
  the documented one), so it is made absolute where that exists instead of matching any ``*.transfer``.
"""

from __future__ import annotations

import os
import pkgutil
import re
import subprocess
import sys
from importlib import import_module
from pathlib import Path

from docutils import nodes
from docutils.parsers.rst import directives
from docutils.statemachine import StringList
from sphinx.application import Sphinx
from sphinx.util.docutils import SphinxDirective
from sphinx.util.parsing import nested_parse_to_nodes

ROOT = Path(__file__).resolve().parents[2]
# Backquoted text (literals, roles, interpreted text) is left alone: a bar there is the author's own.
QUOTED = re.compile(r"(``.*?``|`[^`]*`)")
RELATIVE = re.compile(r"(:(?:mod|func|class|meth|attr|data|obj|exc):)`(~?)\.([\w.]+)`")


class CommandHelp(SphinxDirective):
    """``python -m MODULE [SUBCOMMAND] --help`` (or ``python SCRIPT.py --help``) as a literal block."""

    required_arguments = 1
    optional_arguments = 1

    def run(self) -> list[nodes.Node]:
        command, *rest = self.arguments
        program = [str(ROOT / command)] if command.endswith(".py") else ["-m", command]
        env = dict(os.environ, COLUMNS="100", PYTHONPATH=str(ROOT))
        done = subprocess.run(
            [sys.executable, *program, *rest, "--help"],
            cwd=ROOT, env=env, capture_output=True, text=True, timeout=120,
        )  # fmt: skip
        if done.returncode != 0:
            raise self.error(f"command-help: {' '.join(self.arguments)} --help failed: {done.stderr.strip()}")
        block = nodes.literal_block(done.stdout, done.stdout)
        block["language"] = "text"
        return [block]


class PackageModules(SphinxDirective):
    """The package's own docstring and members, then ``automodule`` with members for each of its modules
    (subpackages too, unless ``:shallow:``), in name order; ``:exclude:`` names modules to leave out (space
    separated)."""

    required_arguments = 1
    option_spec = {"exclude": directives.unchanged, "shallow": directives.flag}

    def run(self) -> list[nodes.Node]:
        name = self.arguments[0]
        package = import_module(name)
        excluded = set((self.options.get("exclude") or "").split())
        found = pkgutil.walk_packages(package.__path__, prefix=name + ".")
        found = [m for m in found if m.name not in excluded and not m.name.endswith("__main__")]
        packages = {m.name for m in found if m.ispkg}  # their re-exported names are documented at home
        modules = sorted(m.name for m in found)
        if "shallow" in self.options:
            modules = [m for m in modules if "." not in m[len(name) + 1 :]]
        # The package's own functions and classes (not the names it re-exports: those are documented at home).
        lines = [f".. automodule:: {name}", "   :members:", "   :ignore-module-all:", ""]
        for module in modules:
            title = module[len(name) + 1 :]
            lines += [f"``{title}``", "-" * (len(title) + 4), "", f".. automodule:: {module}", "   :members:"]
            lines += ["   :ignore-module-all:", ""] if module in packages else [""]
        return nested_parse_to_nodes(self.state, StringList(lines, source=f"package-modules {name}"))


def escape_bars(app: Sphinx, what: str, name: str, obj: object, options: dict, lines: list[str]) -> None:
    """Turn a bare ``|`` of a docstring into ``\\|`` (a literal bar), outside literal blocks and backquotes."""
    literal_indent: int | None = None  # inside a literal block: the indentation of the line that opened it
    for i, line in enumerate(lines):
        indent = len(line) - len(line.lstrip())
        if literal_indent is not None:
            if not line.strip() or indent > literal_indent:
                continue
            literal_indent = None
        if "|" in line:
            parts = QUOTED.split(line)
            lines[i] = "".join(p if j % 2 else p.replace("|", r"\|") for j, p in enumerate(parts))
        if line.rstrip().endswith("::"):
            literal_indent = indent


def exists(dotted: str, module_only: bool) -> bool:
    """Whether ``dotted`` names a module (or, unless ``module_only``, an attribute reached from one)."""
    parts = dotted.split(".")
    for cut in range(len(parts), 0, -1):
        try:
            target: object = import_module(".".join(parts[:cut]))
        except ImportError:
            continue
        if module_only:
            return cut == len(parts)
        for attribute in parts[cut:]:
            if not hasattr(target, attribute):
                return False
            target = getattr(target, attribute)
        return True
    return False


def absolute_references(app: Sphinx, what: str, name: str, obj: object, options: dict, lines: list[str]) -> None:
    """``:role:`.x``` in a docstring of module M becomes ``:role:`~M.x``` if M has ``x``, else ``:role:`~P.x``` if
    M's package P has it (as ``from .x import ...`` in M would read); a module for ``:mod:``. Else it stays."""
    prefixes = [name.rsplit(".", cut)[0] for cut in range(name.count(".") + 1)]  # longest first
    module = next((prefix for prefix in prefixes if prefix in sys.modules), None)
    if module is None:
        return
    package = module if hasattr(sys.modules[module], "__path__") else module.rpartition(".")[0]
    bases = [module, package] if package and package != module else [module]

    def absolute(match: re.Match[str]) -> str:
        role, _, target = match.groups()
        found = [base for base in bases if exists(f"{base}.{target}", module_only=role == ":mod:")]
        return f"{role}`~{found[0]}.{target}`" if found else match.group(0)

    lines[:] = [RELATIVE.sub(absolute, line) for line in lines]


def setup(app: Sphinx) -> dict[str, object]:
    app.add_directive("command-help", CommandHelp)
    app.add_directive("package-modules", PackageModules)
    app.connect("autodoc-process-docstring", escape_bars)
    app.connect("autodoc-process-docstring", absolute_references)
    return {"parallel_read_safe": True, "parallel_write_safe": True}
