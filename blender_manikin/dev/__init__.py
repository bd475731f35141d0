"""Developer tools, run from a checkout and never shipped (``blender_manifest.toml`` excludes this folder):
``build`` (the extension zips), ``snapshot`` (a headless render of the installed zip), ``bench`` (bake throughput).
"""
