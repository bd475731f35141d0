"""The file formats, apart from the math: scenario TOML in and out, result JSON out and back into typed frames.

One module per job: ``files`` (reading and atomic writing with one-line errors), ``output_paths`` (output paths
checked before any work), ``table_reader`` (typed access to parsed TOML/JSON tables whose every error names the
file and the key), ``scenario_read`` (TOML -> Scenario),
``toml_write`` (dict -> TOML text), ``scenario_write`` (Problem -> scenario dict), ``frame`` (the typed frame:
a solved pose as world-space arrays), ``result_write`` (Result -> a frame of the result JSON or of the compact
file), ``result_stream`` (result files written frame by frame), ``model_json`` (a Model as JSON values, the
compact file's header), ``result_scan`` (result files parsed piece by piece) and ``result_read`` (-> frames).
The public names are re-exported by the package ``solver`` (``solver.load_scenario``, ``solver.read_result``,
...); this package imports nothing itself.
"""
