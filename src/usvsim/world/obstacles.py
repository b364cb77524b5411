"""Static obstacles from scenario objects, as collision-true convex pieces in the world frame (ENU, m).

Every piece is convex (boxes, cylinders or convex meshes), so MuJoCo's contacts are exact: a boat
inside a U-shaped berth touches nothing. Non-convex mesh obstacles are split with CoACD; the parts
are cached on disk, keyed by the mesh's content hash.
"""

from __future__ import annotations

import hashlib
import math
import os
from pathlib import Path
from typing import Any, cast

import numpy as np

from usvsim.config.objects import COLORS, Berth, Box, MeshObstacle, Pier
from usvsim.core.errors import MeshError
from usvsim.core.transforms import quat_from_rpy
from usvsim.vessels.custom import load_mesh
from usvsim.vessels.parts import Mesh, Part


def _yawed(center, yaw_deg: float, local_offset) -> tuple[float, float, float]:
    c, s = math.cos(math.radians(yaw_deg)), math.sin(math.radians(yaw_deg))
    dx, dy, dz = local_offset
    return (center[0] + c * dx - s * dy, center[1] + s * dx + c * dy, center[2] + dz)


def box_parts(obj: Box) -> list[Part]:
    half = tuple(s / 2 for s in obj.size)
    quat = tuple(quat_from_rpy(0, 0, math.radians(obj.yaw_deg)))
    return [Part("box", size=half, pos=obj.position, quat=quat, rgba=COLORS[obj.color], name=obj.name)]


def berth_parts(obj: Berth) -> list[Part]:
    """Two side walls along x and a back wall at -x; the slot opens toward the berth's +x."""
    length, width, t = obj.inner_length_m, obj.inner_width_m, obj.wall_thickness_m
    zc = obj.freeboard_m - obj.height_m / 2
    quat = tuple(quat_from_rpy(0, 0, math.radians(obj.yaw_deg)))
    rgba = COLORS[obj.color]
    pieces = [
        ((0.0, width / 2 + t / 2, zc), (length / 2, t / 2, obj.height_m / 2), "left"),
        ((0.0, -width / 2 - t / 2, zc), (length / 2, t / 2, obj.height_m / 2), "right"),
        ((-length / 2 - t / 2, 0.0, zc), (t / 2, width / 2 + t, obj.height_m / 2), "back"),
    ]
    return [
        Part("box", size=half, pos=_yawed(obj.position, obj.yaw_deg, off), quat=quat, rgba=rgba,
             name=f"{obj.name}_{tag}")
        for off, half, tag in pieces
    ]  # fmt: skip


def pier_parts(obj: Pier) -> list[Part]:
    """A deck box on two rows of round piles reaching the seabed."""
    quat = tuple(quat_from_rpy(0, 0, math.radians(obj.yaw_deg)))
    rgba = COLORS[obj.color]
    half = (obj.length_m / 2, obj.width_m / 2, obj.deck_thickness_m / 2)
    parts = [Part("box", size=half, pos=obj.position, quat=quat, rgba=rgba, name=f"{obj.name}_deck")]
    bottom = -obj.water_depth_m
    top = obj.position[2] - obj.deck_thickness_m / 2
    half_len = (top - bottom) / 2
    n = max(2, int(obj.length_m // obj.pile_spacing_m) + 1)
    for i, x in enumerate(np.linspace(-half[0] + obj.pile_radius_m, half[0] - obj.pile_radius_m, n)):
        for side in (1, -1):
            local = (x, side * (half[1] - obj.pile_radius_m), 0.0)
            px, py, _ = _yawed(obj.position, obj.yaw_deg, local)
            parts.append(Part("cylinder", size=(obj.pile_radius_m, half_len), pos=(px, py, bottom + half_len),
                              rgba=rgba, name=f"{obj.name}_pile{i}{'l' if side > 0 else 'r'}"))  # fmt: skip
    return parts


def mesh_parts(obj: MeshObstacle, base_dir: Path, key: str) -> list[Part]:
    mesh = load_mesh(base_dir / obj.file, obj.scale, key=key)  # closed: CoACD decomposes solids
    quat = tuple(quat_from_rpy(0, 0, math.radians(obj.yaw_deg)))
    rgba = COLORS[obj.color]
    return [
        Part("mesh", mesh=piece, pos=obj.position, quat=quat, rgba=rgba, name=f"{obj.name}_{i}")
        for i, piece in enumerate(convex_pieces(mesh, key))
    ]


MAX_DECOMPOSE_FACES = 20_000


def convex_pieces(mesh: Mesh, key: str = "mesh") -> list[Mesh]:
    """Convex decomposition (CoACD) of a mesh; a convex mesh is returned whole. Cached on disk."""
    import trimesh

    tm = trimesh.Trimesh(mesh.vertices, mesh.faces, process=True)
    if tm.is_convex:
        return [mesh]
    if len(tm.faces) > MAX_DECOMPOSE_FACES:  # CoACD's time grows quickly with the faces: keep it bounded
        raise MeshError(f"{key}: a non-convex obstacle mesh has {len(tm.faces)} triangles; convex decomposition takes at "
                        f"most {MAX_DECOMPOSE_FACES}: decimate it or split it into convex parts")  # fmt: skip
    digest = hashlib.sha256(mesh.vertices.tobytes() + mesh.faces.tobytes()).hexdigest()[:24]
    cache = Path(os.environ.get("USVSIM_CACHE", Path.home() / ".cache" / "usvsim")) / "convex" / f"{digest}.npz"
    if cache.is_file():
        data = np.load(cache)
        return [Mesh(data[f"v{i}"], data[f"f{i}"]) for i in range(int(data["n"]))]
    try:
        import coacd
    except ImportError:
        raise MeshError("non-convex mesh obstacles need the 'coacd' package (pip install coacd)") from None
    coacd.set_log_level("error")
    parts = coacd.run_coacd(coacd.Mesh(tm.vertices, tm.faces), threshold=0.05)
    pieces = [Mesh(np.asarray(v), np.asarray(f)) for v, f in parts]
    cache.parent.mkdir(parents=True, exist_ok=True)
    arrays = {f"v{i}": p.vertices for i, p in enumerate(pieces)} | {f"f{i}": p.faces for i, p in enumerate(pieces)}
    np.savez(cache, n=len(pieces), **cast(dict[str, Any], arrays))  # (keys v0.., f0..: no savez option)
    return pieces


def static_parts(objects, base_dir: Path, source: str) -> list[Part]:
    """All static obstacle pieces of the scenario's objects (buoys are floating bodies, not here)."""
    parts: list[Part] = []
    for i, obj in enumerate(objects):
        if isinstance(obj, Box):
            parts += box_parts(obj)
        elif isinstance(obj, Berth):
            parts += berth_parts(obj)
        elif isinstance(obj, Pier):
            parts += pier_parts(obj)
        elif isinstance(obj, MeshObstacle):
            parts += mesh_parts(obj, base_dir, key=f"{source}: objects[{i}].file")
    return parts
