"""The file formats, apart from the math: scenario and body files in and out, result files out and back in.

``files`` (reading and atomic writing with one-line errors), ``output_paths`` (output paths checked before any
work), ``table_reader`` (typed access to parsed TOML/JSON tables whose every error names the file and the key),
``toml_write`` (dict -> TOML text), ``values`` (arrays -> plain values), ``urdf`` (a Model as URDF);
``scenario/`` (scenario and body TOML -> Scenario and Model, and back) and ``result/`` (Result -> result files,
written frame by frame, and result files -> typed frames). The public names are re-exported by the package
``solver`` (``solver.load_scenario``, ``solver.read_result``, ...); this package imports nothing itself.
"""
