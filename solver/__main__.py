"""``python -m solver``: the command line (:mod:`solver.cli.main`)."""

from .cli.main import main

if __name__ == "__main__":
    raise SystemExit(main())
