"""The manikin as a mechanism: its joint tree, kinematics, statics, contacts and variable reduction."""
