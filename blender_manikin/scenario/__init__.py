"""Scenario files in Blender (bpy): ``read`` (a scenario TOML into the scene: the function Import Scenario and the
headless job call), ``write`` (the scene as a scenario: Export Scenario, and the study's scenario), ``keys`` (keyed
targets <-> keyframes on the empties) and ``operators`` (Import / Export Scenario, their File menu entries). This
``__init__`` imports nothing."""
