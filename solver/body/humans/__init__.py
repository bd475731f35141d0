"""The bodies the solver poses: the human (published anthropometry) and the thesis' snake."""
