"""Scenario and body files (TOML) read into problems and written back, obstacles with their mesh files."""
