"""Geometry pieces of a body: closed triangle meshes and primitive shapes, in the body frame (FLU, m)."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from usvsim.core.transforms import matrix_from_quat, quat_multiply


@dataclass(frozen=True)
class Mesh:
    """A triangle mesh: vertices (n, 3) float64 in metres, faces (m, 3) int32, outward CCW winding."""

    vertices: np.ndarray
    faces: np.ndarray

    def __post_init__(self):
        object.__setattr__(self, "vertices", np.ascontiguousarray(self.vertices, dtype=np.float64))
        object.__setattr__(self, "faces", np.ascontiguousarray(self.faces, dtype=np.int32))

    def translated(self, offset) -> Mesh:
        return Mesh(self.vertices + np.asarray(offset, dtype=float), self.faces)

    def mirrored_y(self) -> Mesh:
        """Its mirror image in the x-z plane (y -> -y), faces still wound outward: a catamaran's starboard hull
        made this way leaves the pair exactly symmetric (a translated copy keeps its triangulation's lean)."""
        return Mesh(self.vertices * np.array([1.0, -1.0, 1.0]), self.faces[:, ::-1])

    def volume(self) -> float:
        """Enclosed volume (m^3) by the divergence theorem; positive for outward winding."""
        a, b, c = (self.vertices[self.faces[:, k]] for k in range(3))
        return float(np.einsum("ij,ij->i", a, np.cross(b, c)).sum() / 6.0)


def merge(meshes: list[Mesh]) -> Mesh:
    """One mesh holding several closed components (e.g. the two hulls of a catamaran)."""
    verts, faces, offset = [], [], 0
    for m in meshes:
        verts.append(m.vertices)
        faces.append(m.faces + offset)
        offset += len(m.vertices)
    return Mesh(np.vstack(verts), np.vstack(faces))


@dataclass(frozen=True)
class Part:
    """A collision or visual piece. `kind` is box (size = half extents), cylinder (radius, half length
    along z), sphere (radius), mesh (convex for collision) or hfield (size = half extents x, y; `heights`
    (rows along +y, columns along +x) in m above `pos`). Pose `pos`, `quat` (w, x, y, z) in the body frame."""

    kind: str
    size: tuple[float, ...] = ()
    pos: tuple[float, float, float] = (0.0, 0.0, 0.0)
    quat: tuple[float, float, float, float] = (1.0, 0.0, 0.0, 0.0)
    mesh: Mesh | None = None
    rgba: tuple[float, float, float, float] = (0.8, 0.8, 0.8, 1.0)
    name: str = field(default="")
    heights: np.ndarray | None = None
    texture: np.ndarray | None = None  # (rows, cols, 3) uint8 stretched over a height field, row 0 at +y

    def placed(self, base_pos=None, base_quat=None) -> tuple[np.ndarray, np.ndarray]:
        """Its pose (position m, quaternion w, x, y, z) in the frame where its body sits at `base_pos`, `base_quat`
        (none given: the body frame)."""
        pos, quat = np.asarray(self.pos, float), np.asarray(self.quat, float)
        if base_pos is None or base_quat is None:
            return pos, quat
        base_quat = np.asarray(base_quat, float)
        return np.asarray(base_pos, float) + matrix_from_quat(base_quat) @ pos, quat_multiply(base_quat, quat)
