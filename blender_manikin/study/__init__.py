"""A population study from the sidebar (bpy): ``properties`` (the study settings and the last study's rows on the
scene), ``control`` (start, watch and stop the background study; load a row: what the operators call), ``job``
(the ``python -m solver study`` subprocess and its journal), ``table`` (the table's cells and header, its score
columns from the score registry; no bpy), ``operators`` and ``panel``. This ``__init__`` imports
nothing."""
