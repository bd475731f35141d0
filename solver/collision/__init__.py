"""Collision geometry: obstacle shapes, mesh files, and signed distances from the body's capsules to obstacles and
between capsules (pure NumPy).

Conventions: world coordinates in m; a capsule is a segment p0-p1 swept by a ball of radius r; distances are
surface to surface (negative = penetration); the normal points from the obstacle to the capsule and is the
gradient of the distance with respect to the witness point on the capsule's axis. Obstacle kinds (sphere, capsule,
box, plane, mesh) are registered in :mod:`solver.collision.kinds`, one module each.
"""

from .distance import capsule_pairs
from .kinds import KINDS, Box, Capsule, HalfSpace, Mesh, Obstacle, Sphere, obstacle_distance, read_mesh
from .kinds.box import box_distance, boxes_distance
from .kinds.capsule import capsule_distance
from .kinds.plane import halfspace_distance
from .kinds.sphere import sphere_distance
from .mesh_distance import mesh_distance
from .mesh_files import write_obj
from .mesh_index import MeshIndex
from .proximity import PairProximity, Proximity
from .triangle_frames import degenerate_faces

__all__ = [
    "KINDS",
    "Box",
    "Capsule",
    "HalfSpace",
    "Mesh",
    "MeshIndex",
    "Obstacle",
    "PairProximity",
    "Proximity",
    "Sphere",
    "box_distance",
    "boxes_distance",
    "capsule_distance",
    "capsule_pairs",
    "degenerate_faces",
    "halfspace_distance",
    "mesh_distance",
    "obstacle_distance",
    "read_mesh",
    "sphere_distance",
    "write_obj",
]
