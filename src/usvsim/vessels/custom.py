"""Custom vessels from a hull mesh file (OBJ, STL, PLY, glTF/GLB, DAE via trimesh)."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from usvsim.config.vessel import StateSpaceDrag
from usvsim.core.errors import MeshError
from usvsim.vessels.parts import Mesh

MAX_MESH_FACES = 200_000  # hulls and obstacles; a hull's cost per step is proportional to its faces
MAX_MESH_BYTES = 256 << 20


def load_mesh(path: Path, scale: float = 1.0, key: str = "hull_mesh", require_closed: bool = True) -> Mesh:
    """Load a mesh file as one triangle mesh (all geometry merged); errors name the file and the problem."""
    if path.is_dir():  # `hull_mesh: .` said "mesh file not found: /the/folder"
        raise MeshError(f"{key}: {path} is a directory; give a mesh file (.stl, .obj, .ply, .glb)")
    if not path.is_file():
        raise MeshError(f"{key}: mesh file not found: {path}")
    if path.stat().st_size > MAX_MESH_BYTES:
        raise MeshError(f"{key}: {path} is larger than {MAX_MESH_BYTES >> 20} MiB; decimate the mesh")
    import trimesh  # here (and below): importing trimesh takes ~0.5 s, and the built-in vessels never need it

    try:
        loaded = trimesh.load(path, force="mesh", process=False)
    except Exception as exc:  # trimesh raises many types for unreadable files
        raise MeshError(f"{key}: cannot read mesh {path}: {str(exc)[:200]}") from None
    if not isinstance(loaded, trimesh.Trimesh) or len(loaded.faces) == 0:
        raise MeshError(f"{key}: {path} contains no triangles")
    if len(loaded.faces) > MAX_MESH_FACES:
        raise MeshError(f"{key}: {path} has {len(loaded.faces)} triangles, more than {MAX_MESH_FACES}; decimate it")
    if not np.isfinite(loaded.vertices).all():
        raise MeshError(f"{key}: {path} has non-finite vertex coordinates")
    loaded.process()
    loaded.apply_scale(scale)
    if require_closed:
        if not loaded.is_watertight:
            raise MeshError(
                f"{key}: mesh {path} is not watertight (it has open edges); hulls (buoyancy) and obstacles (convex decomposition) must be closed solids"
            )
        if not loaded.is_winding_consistent:
            raise MeshError(f"{key}: hull mesh {path} has inconsistent face winding")
        if loaded.volume < 0:
            loaded.invert()
    return Mesh(np.asarray(loaded.vertices), np.asarray(loaded.faces))


def solid_mass_properties(mesh: Mesh, mass_kg: float) -> tuple[np.ndarray, np.ndarray]:
    """CoM and inertia about it (body axes) of the hull as a solid of uniform density with this mass."""
    import trimesh

    tm = trimesh.Trimesh(mesh.vertices, mesh.faces, process=False)
    tm.density = mass_kg / tm.volume
    return np.asarray(tm.center_mass), np.asarray(tm.moment_inertia)


def estimated_drag(mesh: Mesh, mass_kg: float, inertia: np.ndarray, rho: float = 1025.0, g: float = 9.81):
    """Default damping for a hull nobody has identified yet: surge and sway/yaw time constants of
    5 s and 1 s (Fossen's rule for small craft), heave, roll and pitch at 30 % of critical damping with
    stiffnesses from a 0.75-full waterplane of the hull's bounding box. Override with real values."""
    length, beam, _ = np.ptp(mesh.vertices, axis=0)
    area = 0.75 * length * beam
    k_heave = rho * g * area
    k_roll = rho * g * 0.75 * length * beam**3 / 12
    k_pitch = rho * g * 0.75 * beam * length**3 / 12
    ixx, iyy, izz = np.diag(inertia)
    return StateSpaceDrag(
        X_u=mass_kg / 5.0, Y_v=mass_kg, N_r=izz,
        Z_w=0.6 * np.sqrt(k_heave * mass_kg), K_p=0.6 * np.sqrt(k_roll * ixx), M_q=0.6 * np.sqrt(k_pitch * iyy),
    )  # fmt: skip
