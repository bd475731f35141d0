"""Reach envelopes in Blender (bpy): ``objects`` (an envelope file as objects on the manikin: the function Import
Reach Envelope calls) and ``operators`` (the operator and its File > Import entry). This ``__init__`` imports
nothing."""
