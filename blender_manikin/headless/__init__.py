"""The headless motion pipeline behind ``batch.py`` and the demo: a scene in, a bake, files out (the .blend,
exports, the JSON report, plots and a picture of key poses)."""
