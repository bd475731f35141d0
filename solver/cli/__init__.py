"""The command line: ``manikin`` (``python -m solver``), the parser and one module per command."""
