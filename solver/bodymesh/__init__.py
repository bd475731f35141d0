"""A skinned human body for a manikin, from the CC0 MakeHuman / MPFB 2 data in ``presets/body_mesh``. NumPy only."""
