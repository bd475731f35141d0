"""The command line's shape: one module per command, assembled by the parser in ``solver.cli.main``, and a start-up
that loads no numerics (``--help`` answers at once, also where scipy is slow to import)."""

from __future__ import annotations

import argparse
import subprocess
import sys
from importlib import import_module
from pathlib import Path

import pytest

from solver.cli.common import check_count, check_file_output, check_folder_name
from solver.cli.envelope import FEET_NAMES, HAND_NAMES, HEMISPHERE_NAMES
from solver.cli.main import COMMANDS, build_parser, main
from solver.errors import UsageError

REPO = Path(__file__).resolve().parents[3]


def _subcommands(parser: argparse.ArgumentParser) -> dict[str, argparse.ArgumentParser]:
    (action,) = [a for a in parser._actions if isinstance(a, argparse._SubParsersAction)]
    return dict(action.choices)


def test_every_command_is_its_own_module_with_add_parser_and_run() -> None:
    subcommands = _subcommands(build_parser())
    assert list(subcommands) == list(COMMANDS)
    for name in COMMANDS:
        module = import_module(f"solver.cli.{name}")
        assert subcommands[name].get_default("run") is module.run, name


@pytest.mark.parametrize("command", ["", *COMMANDS])
def test_help_loads_neither_numpy_nor_scipy(command: str) -> None:
    """``python -m solver [COMMAND] --help`` as a user runs it: the numerics are imported by the commands' runs."""
    code = (
        "import runpy, sys\n"
        f"sys.argv = ['solver', *{command.split()!r}, '--help']\n"
        "try:\n    runpy.run_module('solver', run_name='__main__')\n"
        "except SystemExit as exc:\n    assert exc.code == 0, exc.code\n"
        "print(sorted({m.split('.')[0] for m in sys.modules} & {'numpy', 'scipy', 'matplotlib'}), file=sys.stderr)\n"
    )
    done = subprocess.run([sys.executable, "-c", code], cwd=REPO, capture_output=True, text=True, timeout=60)
    assert done.returncode == 0, done.stderr
    assert "usage: python -m solver" in done.stdout
    assert done.stderr.strip() == "[]"


def test_envelope_choices_are_the_envelope_modules_names() -> None:
    """The parser writes the names out (to stay light); they are the keys of the tables the envelope code uses."""
    from solver.envelope.directions import HEMISPHERES
    from solver.envelope.job import HANDS
    from solver.envelope.reach import FEET_MODES

    assert HAND_NAMES == tuple(sorted(HANDS))
    assert HEMISPHERE_NAMES == tuple(HEMISPHERES)
    assert FEET_NAMES == tuple(FEET_MODES)


def test_shared_checks_say_what_was_expected(tmp_path: Path) -> None:
    with pytest.raises(UsageError, match=r"^--workers: expected a whole number >= 1, got 0$"):
        check_count(0, "--workers")
    check_count(None, "--workers")
    check_count(1, "--workers")
    with pytest.raises(UsageError, match=r"^-o: expected a folder name, got ''$"):
        check_folder_name("  ")
    source = tmp_path / "in.toml"
    source.write_text("", encoding="utf-8")
    with pytest.raises(UsageError, match="the same file as the input"):
        check_file_output(str(source), str(source))
    with pytest.raises(UsageError, match="is a directory"):
        check_file_output(str(tmp_path), None)
    check_file_output("-", str(source))
    check_file_output(None, str(source))
    check_file_output(str(tmp_path / "out.json"), str(source))


def test_an_unknown_command_is_one_line_naming_the_commands(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["bogus"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith("error: argument command: invalid choice: 'bogus'")
    assert all(f"'{name}'" in err for name in COMMANDS)
