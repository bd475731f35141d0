"""Predictions held against motion capture: a BVH reader, CMU key frames made pose problems, posture measures
computed the same way on the measured and the predicted skeleton, and the tables and picture of a run
(``manikin validate``; docs/explanation/mocap-validation.md)."""
