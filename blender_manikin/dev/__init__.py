"""Developer tools, run from a checkout and never shipped (``blender_manifest.toml`` excludes this folder):
``build`` (the extension zips), ``snapshot`` (a headless render of the installed zip), ``prepare_body_mesh`` (the
body-mesh data in presets/body_mesh). The bake benchmark is ``python -m bench.blender_bake``.
"""
